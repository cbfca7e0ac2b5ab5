"""Part of the main job: a full head of rendered hair from the guides of the demo's runs.

Run through Scripts/demo.sh (after Scripts/demo_simulation.py), or:
  xvfb-run -a pvpython Scripts/demo_hair.py <HairDynamics.so> Output
Reads Output/super-helix.h5 and Output/projective.h5 (the demo's wavy guides), simulates
200 curly Super-Helix guides under the same shake (Output/super-helix-curly.h5), and renders
50 000 strands from each with Hair Interpolation. Writes, in Output/:
  full_head.png     the three heads at the same instant of the shake, and at rest
and prints, per run, the time per frame and the points pushed out of the body.
"""
import os
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from paraview.simple import (ColorBy, GetColorTransferFunction, Hide, LoadPlugin,  # noqa: E402
                             SaveScreenshot, Show)

import bundled  # noqa: E402

plugin, out = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
STRANDS = 50000
EARLY, SHOWN = 1.25, 2.25  # s: the head at the end of a swing, and swinging back through the middle

body = bundled.body()
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821
head, trunk = parts["head"], parts["trunk"]

curly_state = os.path.join(out, "super-helix-curly.h5")
curly = HairStrands(registrationName="Curly guides", Input=body, NumberOfStrands=200,  # noqa: F821
                    StrandLength=0.30, NumberOfElements=10, HairType="Curly (Caucasian 2)", Growth="Combed", CombDirection=[0, -1, -0.3],
                    CombWeight=0.35)
curly_sim = HairSimulation(registrationName="Curly simulation", Input=curly,  # noqa: F821
                           Colliders=[head, trunk], Duration=SHOWN, FrameRate=30,
                           BodyMotion="Shake", MotionAmplitude=0.5, MotionFrequency=1.0,
                           Wind=[0, 0, -0.5], StateFileName=curly_state,
                           OverwriteStateFile=1)
curly_sim.UpdatePipeline(SHOWN)

runs = [("Super-Helix, wavy", os.path.join(out, "super-helix.h5")),
        ("Projective, wavy", os.path.join(out, "projective.h5")),
        ("Super-Helix, curly", curly_state)]
view = bundled.white_view([0.75, 1.75, -0.75], [0.0, 1.45, 0.0], size=[600, 700])
skin = Show(body, view)
skin.DiffuseColor = [0.87, 0.76, 0.68]
lut = GetColorTransferFunction("ArcParameter")
# Dark brown at the roots to a lighter brown at the tips.
lut.RGBPoints = [0.0, 0.16, 0.09, 0.05, 1.0, 0.55, 0.36, 0.2]
lut.AutomaticRescaleRangeMode = "Never"
lut.RescaleTransferFunction(0.0, 1.0)
pictures = []
print(f"{'run':<22}{'strands':>9}{'points':>11}{'frame (s)':>11}{'pushed out':>12}{'left inside':>13}")
for name, state in runs:
    reader = HairStateReader(registrationName=f"{name} state", FileName=state)  # noqa: F821
    hair = HairInterpolation(registrationName=f"{name} hair", Input=reader, Scalp=body,  # noqa: F821
                             Colliders=[head, trunk], NumberOfStrands=STRANDS)
    for when in (EARLY, SHOWN):
        start = time.time()
        hair.UpdatePipeline(when)
        seconds = time.time() - start
        data = hair.GetClientSideObject().GetOutputDataObject(0)
        field = data.GetFieldData()
        pushed = int(field.GetArray("PointsPushedOut").GetValue(0))
        left = int(field.GetArray("PointsInsideAfterPushOut").GetValue(0))
        print(f"{name + f' t={when:g}':<22}{data.GetNumberOfLines():>9}{data.GetNumberOfPoints():>11}"
              f"{seconds:>11.2f}{pushed:>12}{left:>13}")
    display = Show(hair, view)
    ColorBy(display, ("POINTS", "ArcParameter"))
    display.SetScalarBarVisibility(view, False)
    display.Ambient = 0.25
    display.Diffuse = 0.8
    for when in (EARLY, SHOWN):
        view.ViewTime = when
        path = os.path.join(out, "frames", f"full_head_{name.split(',')[0].lower()}_"
                            f"{name.split()[-1]}_{when:g}.png")
        SaveScreenshot(path, view, ImageResolution=[600, 700])
        pictures.append((name, when, path))
    Hide(hair, view)

fig, axes = plt.subplots(2, len(runs), figsize=(4.2 * len(runs), 9.6))
for k, (name, when, path) in enumerate(pictures):
    ax = axes[k % 2][k // 2]
    ax.imshow(plt.imread(path))
    ax.set_title(f"{name}, t = {when:g} s", fontsize=10)
    ax.axis("off")
fig.suptitle(f"{STRANDS} rendered strands from 200 guides (Hair Interpolation, "
             "semi-interpolation); head shaking ±0.5 rad at 1 Hz")
fig.tight_layout(rect=[0, 0, 1, 0.96])
fig.savefig(os.path.join(out, "full_head.png"), dpi=100)
print(f"picture: {out}/full_head.png")
