"""Study 4 of issue 6 (Scripts/study_energy.py) at its quick size, with its headline numbers
asserted. Run by CTest as `study.energy` (Tools/CMakeLists.txt):

    /usr/bin/python3 Testing/Python/check_study_energy.py build/bin/hair_study

Runs the quick study: (a) the released wavy strand at dt = 1/30 ... 1/960 s, (b) the small
scene that hair_study writes as state files (Super-Helix at dt = 1/30 and 1/120 s, and
projective), read back with h5py.
Checks, recomputing the budget from the CSV and the state files:
  - the budget's bookkeeping: (kinetic - start) + (elastic - start) + dissipated - work done
    - residual is zero to round-off (1e-12 of the largest work; the terms are sums of ~1e3
    step contributions of double precision), for every dt and in the three state files (both
    models' layouts of the energy terms);
  - the closure max|residual| / max|work done| falls like the step actually taken
    h = dt / sub-steps: fitted order 1 within 0.2 (the step is first order in dt; the same
    tolerance as Testing/Core/test_superhelix_energy.cxx; a flow missing from the budget
    would leave a closure that does not fall at all, order 0), and it falls at every halving;
  - in the Super-Helix scene, the closure at dt = 1/120 s is below the one at 1/30 s.
"""
import glob
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

from studycheck import check, finish, png_ok, ROOT, tool_from_argv

tool = tool_from_argv()
out = tempfile.mkdtemp(prefix="study_energy_")
run = subprocess.run([sys.executable, os.path.join(ROOT, "Scripts", "study_energy.py"), tool,
                      out, "--quick"], capture_output=True, text=True, timeout=240)
print(run.stdout[-4000:])
if run.returncode != 0:
    print(run.stderr[-3000:])
check(run.returncode == 0, f"the quick study runs (exit status {run.returncode})")
csv_path = os.path.join(out, "study_energy_release.csv")
check(os.path.exists(csv_path), "study_energy_release.csv is written")
check(png_ok(os.path.join(out, "study_energy_release.png")), "study_energy_release.png is written")
check(png_ok(os.path.join(out, "study_energy_scene.png")), "study_energy_scene.png is written")
txt = os.path.join(out, "study_energy.txt")
check(os.path.exists(txt) and "closure" in open(txt).read(), "the summary is written")


def terms(e):
    """(stack, work, residual) recomputed here from the energy series."""
    stack = (e["kinetic"] - e["kinetic"][0]) + (e["elastic"] - e["elastic"][0])
    # every dissipation: the sum when the series has it (hair–hair's included), else the
    # Super-Helix's two
    if "dissipated" in e:
        stack = stack + e["dissipated"]
    else:
        stack = stack + e["friction_dissipated"] + e["air_dissipated"]
    external = e["external_work"] if "external_work" in e else (
        e["root_work"] + e["wind_work"] + e["contact_work"] + e["load_work"])
    work = external - (e["gravitational"] - e["gravitational"][0])
    return stack, work, e["residual"]


if os.path.exists(csv_path):
    d = np.genfromtxt(csv_path, delimiter=",", names=True)
    dts = sorted(set(d["dt_s"]), reverse=True)
    hs, closures = [], []
    for dt in dts:
        k = d["dt_s"] == dt
        e = {name: d[name][k] for name in d.dtype.names}
        stack, work, res = terms(e)
        scale = np.abs(work).max()
        check(np.abs(stack - work - res).max() <= 1e-12 * scale,
              f"dt = {dt:.4g} s: the budget's bookkeeping closes to round-off "
              f"({np.abs(stack - work - res).max() / scale:.1e})")
        hs.append(dt / e["substeps"][1:].mean())
        closures.append(np.abs(res).max() / scale)
    check(len(dts) == 6, f"quick dt = 1/30 ... 1/960 s ({len(dts)} values)")
    order = np.polyfit(np.log(hs), np.log(closures), 1)[0]
    check(abs(order - 1) <= 0.2, f"the closure falls like h: fitted order {order:.3f}, 1 within 0.2 "
                                 "(" + ", ".join(f"{100 * c:.2f} %" for c in closures) + ")")
    distinct = [(h, c) for h, c in zip(hs, closures)]
    falls = all(c2 < c1 for (h1, c1), (h2, c2) in zip(distinct, distinct[1:]) if h2 < 0.9 * h1)
    check(falls, "the closure falls at every halving of the step actually taken")

scenes = sorted(glob.glob(os.path.join(out, "study_energy_scene_*.h5")))
check(len(scenes) == 3, f"the quick study made its three small state files ({len(scenes)})")
scene_closure = {}
for path in scenes:
    with h5py.File(path, "r", swmr=True) as f:
        n = f["time"].shape[0]
        e = {k: f["energy"][k][:n] for k in f["energy"].keys()}
    stack, work, res = terms(e)
    scale = np.abs(work).max()
    name = os.path.basename(path)
    check(n == 31, f"{name}: 31 whole frames (1 s at 30 frames/s; {n})")
    check(np.abs(stack - work - res).max() <= 1e-12 * scale,
          f"{name}: the budget read back from the state file closes to round-off")
    scene_closure[name] = np.abs(res).max() / scale
if scene_closure:
    c30 = scene_closure.get("study_energy_scene_super-helix_30.h5")
    c120 = scene_closure.get("study_energy_scene_super-helix_120.h5")
    check(c30 is not None and c120 is not None and c120 < c30,
          f"Super-Helix scene: the closure is smaller at dt = 1/120 s than at 1/30 s ({100 * c120:.2f} % vs {100 * c30:.2f} %)")

shutil.rmtree(out, ignore_errors=True)
finish()
