"""pvpython: Hair Strands on the bundled body, as a user grows guide strands."""
import math
import os
import time

from paraview.simple import (LegacyVTKReader, PointSource, GenerateSurfaceNormals,
                             UpdatePipeline, Calculator)

import hairtest
from hairtest import Errors, check, fetch

hairtest.load_plugin(globals())
body = LegacyVTKReader(FileNames=[os.path.join(hairtest.DATA, "body.vtk")])

strands = HairStrands(Input=body, NumberOfStrands=200, StrandLength=0.3, NumberOfElements=10)  # noqa: F821
UpdatePipeline(proxy=strands)
out = fetch(strands)
check(out.GetNumberOfLines() == 200 and out.GetNumberOfPoints() == 200 * 11,
      f"200 polylines of 11 points ({out.GetNumberOfLines()}, {out.GetNumberOfPoints()})")
lengths_ok, on_scalp = True, True
for k in range(200):
    pts = [out.GetPoint(k * 11 + i) for i in range(11)]
    length = sum(math.dist(pts[i], pts[i + 1]) for i in range(10))
    lengths_ok = lengths_ok and abs(length - 0.3) < 1e-12
    on_scalp = on_scalp and pts[0][1] > 1.47
check(lengths_ok, "every strand is exactly 0.3 m long")
check(on_scalp, "every root is on the scalp (above y = 1.47 m)")
cd = out.GetCellData()
# The wavy preset: the Super-Helices paper's appendix B, column Caucasian 1.
expect = {"Radius": 35e-6, "Ellipticity": 1.1, "YoungModulus": 2e9, "PoissonRatio": 0.48,
          "HelixRadius": 0.01, "HelixStep": 0.005, "Density": 1300}
for name, value in expect.items():
    a = cd.GetArray(name)
    check(a is not None and abs(a.GetValue(0) - value) <= 1e-12 * value, f"{name} = {value} (wavy preset)")
for name in ("StrandId", "NumberOfElements", "HairType", "Length", "InternalFriction", "AirFriction",
             "RestRoot", "RootNormal", "GrowthDirection", "Seed"):
    check(cd.GetArray(name) is not None, f"cell array {name}")

first = out.GetPoint(0)
strands.Seed = 2
UpdatePipeline(proxy=strands)
check(fetch(strands).GetPoint(0) != first, "another seed, other roots")
strands.Seed = 1
UpdatePipeline(proxy=strands)
check(fetch(strands).GetPoint(0) == first, "the same seed, the same roots")

# One strand per point of a point set with normals.
points = PointSource(NumberOfPoints=7, Radius=0.0, Center=[0, 1.7, 0])
with_normals = Calculator(Input=points, ResultArrayName="Normals", Function="jHat",
                          ResultNormals=1)
per_point = HairStrands(Input=with_normals, NumberOfElements=4)  # noqa: F821
UpdatePipeline(proxy=per_point)
check(fetch(per_point).GetNumberOfLines() == 7, "one strand per input point")

# Bad input.
no_normals = HairStrands(Input=body)  # noqa: F821
errors = Errors(no_normals)
no_normals.Input = points
UpdatePipeline(proxy=no_normals)
check(any("no point normals" in m for m in errors.messages), "points without normals are refused")
custom = HairStrands(Input=body)  # noqa: F821
errors = Errors(custom)
custom.HairType = "Custom"
custom.Radius = -1
UpdatePipeline(proxy=custom)
check(any("radius" in m for m in errors.messages), f"a negative radius is refused ({errors.messages[:1]})")
masked = HairStrands(Input=body)  # noqa: F821
errors = Errors(masked)
masked.Region = "Point mask"
masked.RegionArray = "no-such-array"
UpdatePipeline(proxy=masked)
check(any("no-such-array" in m for m in errors.messages), "a missing region array is refused")

# Values outside the properties' domains are refused with the value and the range, before
# any work, never clamped to something the user did not ask for (issue 24: these were
# clamped silently, and 10 million strands ran without end).
for prop, value, words in (("NumberOfStrands", 10**7, "10000000"), ("NumberOfStrands", 0, "give 1"),
                           ("StrandLength", 0.0, "give a length"), ("StrandLength", 1e6, "1e+06"),
                           ("StrandLength", float("nan"), "nan"), ("NumberOfElements", 0, "give 1"),
                           ("NumberOfElements", 10000, "10000"), ("CombWeight", 2.0, "[0, 1]")):
    bad = HairStrands(Input=body, Growth="Combed")  # noqa: F821
    errors = Errors(bad)
    setattr(bad, prop, value)
    start = time.time()
    UpdatePipeline(proxy=bad)
    check(any(words in m for m in errors.messages) and time.time() - start < 10,
          f"{prop} = {value} is refused at once ({errors.messages[:1]})")
zero = HairStrands(Input=body, Growth="Combed", CombDirection=[0, 0, 0])  # noqa: F821
errors = Errors(zero)
UpdatePipeline(proxy=zero)
check(any("comb direction" in m for m in errors.messages), "a zero comb direction is refused")

hairtest.finish()
