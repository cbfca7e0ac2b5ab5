"""Part of the main job: a full head of rendered hair from the guides of the demo's runs.

Run through Scripts/demo.sh (after Scripts/demo_simulation.py), or:
  xvfb-run -a pvpython Scripts/demo_hair.py <HairDynamics.so> Output
Reads Output/super-helix.h5 and Output/projective.h5 (the demo's wavy guides), simulates
200 curly Super-Helix guides under the same shake (Output/super-helix-curly.h5), and renders
50 000 strands from each with Hair Interpolation. Writes, in Output/:
  full_head.png     the three heads at two instants of the shake, one period apart, lit
                    lines with ambient occlusion, the head shown turned as the shake has it
and prints, per run, the time per frame and the points pushed out of the body.
"""
import math
import os
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from paraview.simple import (Calculator, Hide, LoadPlugin, ProgrammableFilter,  # noqa: E402
                             SaveScreenshot, Show)

import bundled  # noqa: E402

plugin, out = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
STRANDS = 50000
EARLY, SHOWN = 1.25, 2.25  # s: the head at the same end of its swing, one period apart
AMPLITUDE, FREQUENCY = 0.5, 1.0  # rad, Hz: the shake of all three runs, about the vertical
PIVOT = [0.0, 1.45, 0.02]        # through Hair Simulation's default Motion Pivot (the neck)
# Lit lines: a line has no normal of its own, and VTK draws lines without normals unlit (flat
# colour). Each point gets the normal of a hair seen from the camera: the direction to the eye
# made perpendicular to the strand's tangent (the normal of a thin cylinder where the eye sees
# it), which gives the strands diffuse shading and highlights. And a shade for the colour map:
# the arc parameter (0 at the root, 1 at the tip) times a per-strand factor in [0.8, 1.2]
# (seeded by StrandId), so that neighbouring strands differ a little in lightness.
LIT_HAIR = """
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
hair = self.GetPolyDataInput()
out = self.GetPolyDataOutput()
out.ShallowCopy(hair)
points = vtk_to_numpy(hair.GetPoints().GetData()).astype(float)
tangent = vtk_to_numpy(hair.GetPointData().GetArray("Tangent")).astype(float)
eye = np.array({camera}) - points
normal = eye - np.sum(eye * tangent, axis=1)[:, None] * tangent
normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-12)[:, None]
normals = numpy_to_vtk(normal.astype(np.float32), deep=1)
normals.SetName("Normals")
out.GetPointData().SetNormals(normals)
lines = hair.GetLines()
counts = np.diff(vtk_to_numpy(lines.GetOffsetsArray()))
strand = vtk_to_numpy(hair.GetCellData().GetArray("StrandId"))[hair.GetNumberOfVerts():][:len(counts)]
factor = 0.8 + 0.4 * np.random.default_rng(1).random(int(strand.max(initial=0)) + 1)
per_point = np.ones(len(points))
per_point[vtk_to_numpy(lines.GetConnectivityArray())] = np.repeat(factor[strand], counts)
arc = vtk_to_numpy(hair.GetPointData().GetArray("ArcParameter"))
shade = numpy_to_vtk(np.clip(arc * per_point, 0, 1).astype(np.float32), deep=1)
shade.SetName("HairShade")
out.GetPointData().AddArray(shade)
""".format(camera=bundled.HAIR_CAMERA)

body = bundled.body()
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821
head, trunk = parts["head"], parts["trunk"]

curly_state = os.path.join(out, "super-helix-curly.h5")
curly = HairStrands(registrationName="Curly guides", Input=body, NumberOfStrands=200,  # noqa: F821
                    StrandLength=0.30, NumberOfElements=10, HairType="Curly (Caucasian 2)", Growth="Combed", CombDirection=[0, -1, -0.3],
                    CombWeight=0.35)
curly_sim = HairSimulation(registrationName="Curly simulation", Input=curly,  # noqa: F821
                           Colliders=[head, trunk], Duration=SHOWN, FrameRate=30,
                           BodyMotion="Shake", MotionAmplitude=AMPLITUDE, MotionFrequency=FREQUENCY,
                           Wind=[0, 0, -0.5], StateFileName=curly_state,
                           OverwriteStateFile=1)
curly_sim.UpdatePipeline(SHOWN)

runs = [("Super-Helix, wavy", os.path.join(out, "super-helix.h5")),
        ("Projective, wavy", os.path.join(out, "projective.h5")),
        ("Super-Helix, curly", curly_state)]
view = bundled.white_view(bundled.HAIR_CAMERA, bundled.HAIR_FOCUS, size=[600, 700])


def head_turn(t):
    """A Calculator function that turns the body's head as the shake has it at time t: the
    hair was simulated on a turning head, the mesh is at rest. A rotation about the vertical
    axis through the pivot, faded in over the neck (y 1.40 to 1.45 m) so that the shoulders
    stay where they are."""
    fade = "clamp(0, (coordsY - 1.40) / 0.05, 1)"
    angle = f"({AMPLITUDE * math.sin(2 * math.pi * FREQUENCY * t)} * {fade}^2 * (3 - 2 * {fade}))"
    x, z = f"(coordsX - {PIVOT[0]})", f"(coordsZ - {PIVOT[2]})"
    return (f"({PIVOT[0]} + {x} * cos({angle}) + {z} * sin({angle})) * iHat + coordsY * jHat"
            f" + ({PIVOT[2]} - {x} * sin({angle}) + {z} * cos({angle})) * kHat")


posed = Calculator(registrationName="body, head turned", Input=body, CoordinateResults=1,
                   Function=head_turn(EARLY))
skin = Show(posed, view)
skin.ColorArrayName = ["POINTS", ""]
skin.DiffuseColor = [0.87, 0.76, 0.68]
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
    lit = ProgrammableFilter(registrationName=f"{name} lit hair", Input=hair, Script=LIT_HAIR)
    display = Show(lit, view)
    display.Interpolation = "Gouraud"
    display.LineWidth = 1.0
    bundled.hair_look(view, display, "HairShade")
    for when in (EARLY, SHOWN):
        view.ViewTime = when
        posed.Function = head_turn(when)
        path = os.path.join(out, "frames", f"full_head_{name.split(',')[0].lower()}_"
                            f"{name.split()[-1]}_{when:g}.png")
        SaveScreenshot(path, view, ImageResolution=[600, 700])
        pictures.append((name, when, path))
    Hide(lit, view)

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
