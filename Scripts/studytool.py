"""Shared by Scripts/study_convergence.py, study_buckling.py and study_energy.py: finding and
running hair_study (Tools/hair_study.cxx and Tools/studies/, built into <build>/bin/), reading its CSV, fitting
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


# The perfect clamped–free elastica (Timoshenko & Gere, Theory of Elastic Stability, §2.7),
# shared by the buckling study and its check.
def ellipk(m):
    """Complete elliptic integral of the first kind K(m) = pi / (2 AGM(1, sqrt(1 - m)))."""
    a, b = 1.0, np.sqrt(1.0 - m)
    while abs(a - b) > 1e-15 * a:
        a, b = (a + b) / 2, np.sqrt(a * b)
    return np.pi / (2 * a)


def brentq(f, lo, hi):
    """Root of f in [lo, hi] by bisection (f changes sign there), to 1e-15."""
    flo = f(lo)
    while hi - lo > 1e-15:
        mid = (lo + hi) / 2
        fm = f(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return (lo + hi) / 2


def elastica(ratio):
    """Lateral tip deflection / L of the perfect clamped-free elastica at P/P_cr = ratio > 1."""
    m = brentq(lambda m: (2 * ellipk(m) / np.pi) ** 2 - ratio, 0.0, 1 - 1e-12)
    return 2 * np.sqrt(m) / ellipk(m)
