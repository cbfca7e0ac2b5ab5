"""pvpython: study 2 of issue 6 (Scripts/study_table_error.py) at its quick size, so that CI
keeps it working: collision-table error against VTK's exact distance to the head mesh.

Run: pvpython Testing/Python/test_study_table_error.py build/lib/paraview-5.11/plugins/HairDynamics/HairDynamics.so
Runs `pvpython Scripts/study_table_error.py <plugin> <temp dir> --quick` (n = 10, 20, 40) and
checks its outputs: the CSV and the PNG exist, the errors shrink as n grows for both
projections, and the fitted order (minus the slope of log(mean error) against log(n)) is
positive.
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import hairtest
from hairtest import check

plugin = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("HAIR_PLUGIN")
if not plugin or not os.path.exists(plugin):
    sys.exit(f"give the path of the built HairDynamics.so (got {plugin!r})")

script = os.path.join(hairtest.ROOT, "Scripts", "study_table_error.py")
pvpython = shutil.which("pvpython") or sys.executable
out = tempfile.mkdtemp(prefix="study_table_error_")
t0 = time.time()
run = subprocess.run([pvpython, script, plugin, out, "--quick"], capture_output=True, text=True,
                     timeout=300)
elapsed = time.time() - t0
print(run.stdout[-3000:])
if run.returncode != 0:
    print(run.stderr[-3000:])
check(run.returncode == 0, f"the quick study runs (exit status {run.returncode})")
print(f"the quick study took {elapsed:.1f} s")  # speed is for benchmarks, not tests

csv_path = os.path.join(out, "study_table_error.csv")
png_path = os.path.join(out, "study_table_error.png")
txt_path = os.path.join(out, "study_table_error.txt")
check(os.path.exists(csv_path), "study_table_error.csv is written")
png_ok = os.path.exists(png_path) and os.path.getsize(png_path) > 10000
if png_ok:
    with open(png_path, "rb") as f:
        png_ok = f.read(8) == b"\x89PNG\r\n\x1a\n"
check(png_ok, "study_table_error.png is written (a PNG image)")
check(os.path.exists(txt_path) and "fitted order" in open(txt_path).read(),
      "study_table_error.txt is written with the fitted orders")

rows = list(csv.DictReader(open(csv_path))) if os.path.exists(csv_path) else []
check(rows and list(rows[0].keys()) == ["projection", "n", "points", "mean_mm", "p95_mm", "max_mm"],
      "the CSV has the columns projection, n, points, mean_mm, p95_mm, max_mm")
for projection in ("spherical", "cylindrical"):
    rs = sorted((r for r in rows if r["projection"] == projection), key=lambda r: int(r["n"]))
    ns = [int(r["n"]) for r in rs]
    check(ns == [10, 20, 40], f"{projection}: quick resolutions 10, 20, 40 ({ns})")
    if len(rs) < 2:
        continue
    mean = [float(r["mean_mm"]) for r in rs]
    p95 = [float(r["p95_mm"]) for r in rs]
    points = [int(r["points"]) for r in rs]
    check(all(p > 0 for p in points) and points == sorted(points),
          f"{projection}: more points measured as n grows ({points})")
    check(all(b < a for a, b in zip(mean, mean[1:])),
          f"{projection}: the mean error shrinks as n grows ({', '.join(f'{m:.3f}' for m in mean)} mm)")
    check(all(b < a for a, b in zip(p95, p95[1:])),
          f"{projection}: the 95th percentile shrinks as n grows ({', '.join(f'{m:.3f}' for m in p95)} mm)")
    # least-squares slope of log(mean) against log(n); the order is minus the slope
    x = [math.log(n) for n in ns]
    y = [math.log(m) for m in mean]
    xm, ym = sum(x) / len(x), sum(y) / len(y)
    slope = sum((a - xm) * (b - ym) for a, b in zip(x, y)) / sum((a - xm) ** 2 for a in x)
    check(-slope > 0, f"{projection}: the fitted order is positive ({-slope:.2f}; expected 2 on a "
                      "smooth surface, less on the head's creases)")

shutil.rmtree(out, ignore_errors=True)
hairtest.finish()
