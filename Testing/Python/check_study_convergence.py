"""Study 1 of issue 6 (Scripts/study_convergence.py) at its quick size, with its headline
numbers asserted. Run by CTest as `study.convergence` (Tools/CMakeLists.txt):

    /usr/bin/python3 Testing/Python/check_study_convergence.py build/bin/hair_study

Runs the quick study (N = 2, 3, 5, 10, 20, 40) into a temporary directory and checks:
  - the CSV, PNG and summary exist;
  - the fitted slopes of log|relative error| against log N over N >= 5 are -2 within 0.15
    for f1, f2 and the static deflection (the same tolerance as
    Testing/Core/test_superhelix_eb.cxx: a first-order discretization gives -1);
  - the static deflection equals the discrete rod's linear theory delta_EB (1 - 1/(3N^2))
    within 1e-5 relative at every N (the geometric nonlinearity at delta/L = 1e-3 is
    O((delta/L)^2) = 1e-6; 1e-5 leaves a factor 10 for the stopping test);
  - issue 3's accuracy at N = 10: f1 within 0.3 %, f2 within 2 %, delta within 1 %.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

from studycheck import check, finish, png_ok, ROOT, tool_from_argv

tool = tool_from_argv()
out = tempfile.mkdtemp(prefix="study_convergence_")
run = subprocess.run([sys.executable, os.path.join(ROOT, "Scripts", "study_convergence.py"), tool,
                      out, "--quick"], capture_output=True, text=True, timeout=240)
print(run.stdout[-3000:])
if run.returncode != 0:
    print(run.stderr[-3000:])
check(run.returncode == 0, f"the quick study runs (exit status {run.returncode})")

csv_path = os.path.join(out, "study_convergence.csv")
check(os.path.exists(csv_path), "study_convergence.csv is written")
check(png_ok(os.path.join(out, "study_convergence.png")), "study_convergence.png is written")
txt = os.path.join(out, "study_convergence.txt")
check(os.path.exists(txt) and "fitted slopes" in open(txt).read(), "the summary is written")
if os.path.exists(csv_path):
    d = np.genfromtxt(csv_path, delimiter=",", names=True)
    n = d["N"]
    check(list(n) == [2, 3, 5, 10, 20, 40], f"quick N = 2, 3, 5, 10, 20, 40 ({list(n)})")
    e1 = d["f1_hz"] / d["f1_eb_hz"] - 1
    e2 = d["f2_hz"] / d["f2_eb_hz"] - 1
    ed = d["deflection_m"] / d["deflection_eb_m"] - 1
    fit = n >= 5
    for name, e in (("f1", e1), ("f2", e2), ("static deflection", ed)):
        s = float(np.polyfit(np.log(n[fit]), np.log(np.abs(e[fit])), 1)[0])
        check(abs(s + 2) <= 0.15, f"{name}: fitted slope {s:.3f} is -2 within 0.15")
    gap = np.abs((1 + ed) / (1 - 1 / (3 * n ** 2)) - 1)
    check(gap.max() <= 1e-5, f"deflection = delta_EB (1 - 1/(3N^2)) within 1e-5 at every N "
                             f"(largest gap {gap.max():.2e})")
    i = int(np.where(n == 10)[0][0])
    check(abs(e1[i]) < 3e-3, f"N = 10: f1 within 0.3 % ({100 * e1[i]:+.3f} %)")
    check(abs(e2[i]) < 2e-2, f"N = 10: f2 within 2 % ({100 * e2[i]:+.3f} %)")
    check(abs(ed[i]) < 1e-2, f"N = 10: deflection within 1 % ({100 * ed[i]:+.3f} %)")

shutil.rmtree(out, ignore_errors=True)
finish()
