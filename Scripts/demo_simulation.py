"""Part of the main job: hair on the bundled body, simulated and stored, pictures and plots.

Run through Scripts/demo.sh (after Scripts/demo.py), or:
  xvfb-run -a pvpython Scripts/demo_simulation.py <HairDynamics.so> Output
Writes, in Output/:
  projective.h5, super-helix.h5    the state files (docs/state-file.md)
  frames/<model>_XXX.png           the picture sequences of both runs (every 0.25 s)
  hair_shake.png                   five frames of each run, one row per model
  energy.png                       the energy terms of both runs over time
  demo.pvsm                        a ParaView state with the same pipeline (load the plugin first):
                                   both runs side by side over their energy chart, at t = 5 s
and prints a summary.
"""
import os
import sys
import time

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from paraview.simple import LoadPlugin, SaveScreenshot  # noqa: E402

import bundled  # noqa: E402

plugin, out = sys.argv[1], sys.argv[2]
os.makedirs(os.path.join(out, "frames"), exist_ok=True)
LoadPlugin(plugin, remote=False, ns=globals())

DURATION = 5.0
body = bundled.body()
# The bundled body's parts (Data/body_parts.txt): the head follows the shake, the trunk stays.
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821
head, trunk = parts["head"], parts["trunk"]

runs = {}
for model, elements in (("Projective", 40), ("Super-Helix", 10)):
    guides = HairStrands(registrationName=f"{model} guides", Input=body,  # noqa: F821
                         NumberOfStrands=200, StrandLength=0.30, NumberOfElements=elements,
                         HairType="Wavy (Caucasian 1)", Growth="Combed",
                         CombDirection=[0, -1, -0.3], CombWeight=0.35)
    state = os.path.join(out, f"{model.lower()}.h5")
    # Hair–hair interaction by its default, the grid: the hair's volume and friction
    # (docs/hair-hair-interaction.md), named here so that the demo says what it runs.
    sim = HairSimulation(registrationName=f"{model} simulation", Input=guides,  # noqa: F821
                         Colliders=[head, trunk], Model=model, Duration=DURATION, FrameRate=30,
                         BodyMotion="Shake", MotionAmplitude=0.5, MotionFrequency=1.0,
                         Wind=[0, 0, -0.5], HairHairContacts="Grid (volume and friction)",
                         StateFileName=state, OverwriteStateFile=1)
    start = time.time()
    sim.UpdatePipeline(DURATION)
    runs[model] = dict(sim=sim, state=state, seconds=time.time() - start)

# --- Pictures of both runs: the same camera, the hair coloured by speed -----------------
# One view per run, as the rows of hair_shake.png: in one view the two runs' 400 guides
# would be drawn over each other on the same head. The saved state keeps both views.
times = np.arange(0, DURATION + 1e-9, 0.25)
pictures = {}
for model, run in runs.items():
    view = run["view"] = bundled.hair_view(body, run["sim"])
    tag = model.lower()
    pictures[model] = []
    for i, t in enumerate(times):
        view.ViewTime = t
        path = os.path.join(out, "frames", f"{tag}_{i:03d}.png")
        SaveScreenshot(path, view, ImageResolution=[500, 600])
        pictures[model].append((t, path))
# t = 0 shows the strands as Hair Strands grows them (standing out of the scalp); the montage
# starts once they have fallen onto the body.
rows = list(pictures.items())
chosen = [k for k, (t, _) in enumerate(rows[0][1]) if t > 0 and abs(t - round(t)) < 1e-9]
fig, axes = plt.subplots(len(rows), len(chosen), figsize=(3 * len(chosen), 4.0 * len(rows)))
for r, (model, pics) in enumerate(rows):
    for c, k in enumerate(chosen):
        t, path = pics[k]
        ax = axes[r][c]
        ax.imshow(plt.imread(path))
        ax.set_title(f"{model}, t = {t:.0f} s", fontsize=9)
        ax.axis("off")
fig.suptitle("200 wavy guides (Super-Helix: 10 elements; projective: 40 segments), "
             "head shaking ±0.5 rad at 1 Hz, wind 0.5 m/s from the front")
fig.tight_layout(rect=[0, 0, 1, 0.95])
fig.savefig(os.path.join(out, "hair_shake.png"), dpi=100)

# --- Energy of both runs, from the state files (as an h5py user reads them) --------------
fig, axes = plt.subplots(1, 2, figsize=(13, 4.5))
print(f"{'model':<12}{'frames':>7}{'run (s)':>9}{'E_kin max (J)':>15}{'residual (J)':>14}"
      f"{'|residual|/work':>17}{'nodes inside (max)':>20}{'deepest (mm)':>14}{'at t = 0':>10}")
print("(nodes inside and deepest over the frames after t = 0; 'at t = 0': nodes inside as grown, "
      "roots included: the roots lie on the mesh, which the head table passes up to 4.5 mm "
      "outside)")
for ax, (model, run) in zip(axes, runs.items()):
    with h5py.File(run["state"], "r", swmr=True) as f:
        T = f["time"].shape[0]
        t = f["time"][:T]
        e = {name: f["energy"][name][:T] for name in f["energy"]}
    mech0 = e["kinetic"][0] + e["elastic"][0] + e["gravitational"][0]
    ax.plot(t, e["kinetic"], label="kinetic")
    ax.plot(t, e["elastic"] - e["elastic"][0], label="elastic − elastic(0)")
    ax.plot(t, e["gravitational"] - e["gravitational"][0], label="gravitational − gravitational(0)")
    ax.plot(t, e["dissipated"], label="dissipated")
    ax.plot(t, e["external_work"], label="work done on the hair")
    ax.plot(t, e["residual"], "k--", label="integrator residual")
    ax.set_title(f"{model}: 200 guides, head shake")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.legend(fontsize=7)
    table = run["sim"].GetClientSideObject().GetOutputDataObject(1)
    inside = np.array([table.GetColumnByName("nodes_inside").GetValue(i) for i in range(table.GetNumberOfRows())])
    depth = np.array([table.GetColumnByName("max_depth").GetValue(i) for i in range(table.GetNumberOfRows())])
    work = np.abs(e["external_work"][-1]) + np.abs(e["dissipated"][-1])
    print(f"{model:<12}{T:>7}{run['seconds']:>9.1f}{e['kinetic'].max():>15.3e}{e['residual'][-1]:>14.3e}"
          f"{abs(e['residual'][-1]) / max(work, 1e-300):>17.3f}{int(inside[1:].max()):>20}{1000 * depth[1:].max():>14.1f}"
          f"{int(inside[0]):>10}")
fig.tight_layout()
fig.savefig(os.path.join(out, "energy.png"), dpi=100)

# The ParaView state: both runs side by side above their energy chart, on the last frame.
bundled.save_state(os.path.join(out, "demo.pvsm"), [(model, run["view"], run["sim"]) for model, run in runs.items()],
                   DURATION)
print(f"pictures: {out}/frames/ ({sum(len(p) for p in pictures.values())}), {out}/hair_shake.png, "
      f"{out}/energy.png; ParaView state: {out}/demo.pvsm")
print("('nodes inside' counts the nodes inside the head or trunk tables, 'deepest' their "
      "largest depth.)")
