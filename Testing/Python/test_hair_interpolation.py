"""pvpython: Hair Interpolation on the guides of both models over time, on Hair Strands'
guides at rest, and on a state file read back: the rendered hair's shape and arrays, the
same hair at the same time whichever way time is scrubbed, the push-out, bad inputs."""
import os
import tempfile

import numpy as np
from paraview.simple import LegacyVTKReader, Sphere, UpdatePipeline
from vtkmodules.util.numpy_support import vtk_to_numpy

import hairtest
from hairtest import Errors, check, fetch

hairtest.load_plugin(globals())
tmp = tempfile.mkdtemp()


def points(polydata):
    return vtk_to_numpy(polydata.GetPoints().GetData()).copy()


body = LegacyVTKReader(FileNames=[os.path.join(hairtest.DATA, "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16,
                               BodyPartName="head", MovesWithHead=1)
strands = HairStrands(Input=body, NumberOfStrands=40, NumberOfElements=8, StrandLength=0.25,  # noqa: F821
                      HairType="Curly (Caucasian 2)")

# Guides at rest, straight from Hair Strands.
rest = HairInterpolation(Input=strands, Scalp=body, Colliders=[head], NumberOfStrands=3000)  # noqa: F821
UpdatePipeline(proxy=rest)
out = fetch(rest)
check(out.GetNumberOfLines() == 3000 and out.GetNumberOfPoints() == 3000 * 32,
      f"3000 rendered strands of 32 points from Hair Strands' guides ({out.GetNumberOfLines()} lines)")
pd, cd = out.GetPointData(), out.GetCellData()
check(all(pd.GetArray(a) is not None for a in ("Tangent", "ArcParameter")) and
      all(cd.GetArray(a) is not None for a in ("StrandId", "GuideId")),
      "Tangent, ArcParameter per point; StrandId, GuideId per strand")
t = vtk_to_numpy(pd.GetArray("Tangent"))
check(np.allclose(np.linalg.norm(t, axis=1), 1, atol=1e-5), "tangents are unit vectors")
guide = vtk_to_numpy(cd.GetArray("GuideId"))
check(guide.min() >= 0 and guide.max() < 40 and len(np.unique(guide)) > 30,
      f"every rendered strand follows one of the 40 guides ({len(np.unique(guide))} used)")
check(out.GetFieldData().GetArray("PointsPushedOut") is not None, "the points pushed out are reported")
check(out.GetFieldData().GetArray("PointsLookedUp") is not None, "the points looked up are reported")

for model in ("Super-Helix", "Projective"):
    state = os.path.join(tmp, f"{model}.h5")
    sim = HairSimulation(Input=strands, Colliders=[head], Model=model, Duration=0.4,  # noqa: F821
                         FrameRate=30, BodyMotion="Shake", MotionAmplitude=0.3,
                         StateFileName=state)
    hair = HairInterpolation(Input=sim, Scalp=body, Colliders=[head], NumberOfStrands=4000)  # noqa: F821
    steps = list(hair.TimestepValues)
    check(len(steps) == 13, f"{model}: the rendered hair has the guides' 13 time steps")
    hair.UpdatePipeline(steps[3])
    early = points(fetch(hair))
    hair.UpdatePipeline(steps[12])
    late = points(fetch(hair))
    hair.UpdatePipeline(steps[3])
    again = points(fetch(hair))
    check(np.array_equal(early, again), f"{model}: scrubbing back gives the same hair, point for point")
    check(not np.array_equal(early, late) and early.shape == (4000 * 32, 3), f"{model}: the hair moves with its guides")
    moved = np.linalg.norm(late - early, axis=1).max()
    check(moved < 0.5, f"{model}: no rendered point jumps across the head ({moved:.3f} m at most)")

    # From the state file read back: the same hair as from the simulation.
    reader = HairStateReader(FileName=state)  # noqa: F821
    again = HairInterpolation(Input=reader, Scalp=body, Colliders=[head], NumberOfStrands=4000)  # noqa: F821
    again.UpdatePipeline(steps[12])
    diff = np.abs(points(fetch(again)) - late).max()
    check(diff < 1e-5, f"{model}: from Hair State Reader the same hair as from Hair Simulation ({diff:.2e} m)")

# Bad input.
bad = HairInterpolation(Input=strands, Scalp=body, NumberOfStrands=0)  # noqa: F821
errors = Errors(bad)
UpdatePipeline(proxy=bad)
check(any("rendered strands" in m for m in errors.messages), f"0 rendered strands is refused ({errors.messages[:1]})")
far = HairInterpolation(Input=strands, Scalp=Sphere(Center=[5, 5, 5]), NumberOfStrands=10)  # noqa: F821
errors = Errors(far)
UpdatePipeline(proxy=far)
check(any("near the guides" in m for m in errors.messages),
      f"a scalp far from the guides is refused ({errors.messages[:1]})")

hairtest.finish()
