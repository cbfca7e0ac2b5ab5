"""Shared by Scripts/study_convergence.py, study_buckling.py and study_energy.py: finding and
running hair_study (Tools/hair_study.cxx, built into <build>/bin/), reading its CSV, fitting
slopes on log-log axes."""
import csv
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def parse_args(script, usage_tail=""):
    """(tool, outdir, quick) from `<hair_study> <output dir> [--quick]`."""
    args = [a for a in sys.argv[1:] if a != "--quick"]
    quick = "--quick" in sys.argv[1:]
    if len(args) != 2:
        sys.exit(f"usage: /usr/bin/python3 Scripts/{script} <build>/bin/hair_study <output dir> "
                 f"[--quick]{usage_tail}")
    tool, outdir = args
    if not (os.path.isfile(tool) and os.access(tool, os.X_OK)):
        sys.exit(f"no hair_study program at {tool!r}: build it with "
                 "`cmake --build build --target hair_study` (it lands in build/bin/)")
    os.makedirs(outdir, exist_ok=True)
    return tool, outdir, quick


def run(tool, study, **kwargs):
    """Runs `hair_study <study> key=value ...`; exits with its message if it fails."""
    cmd = [tool, study] + [f"{k}={v}" for k, v in kwargs.items()]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit status {r.returncode}):\n{r.stderr}")


def read_csv(path):
    """Columns of a CSV as numpy arrays (numbers) keyed by header name."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def slope(x, y):
    """Least-squares slope of log|y| against log x."""
    return float(np.polyfit(np.log(x), np.log(np.abs(y)), 1)[0])


def write_summary(outdir, name, lines):
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, name), "w") as f:
        f.write(text)
    print(text, end="")
