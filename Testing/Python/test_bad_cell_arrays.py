"""pvpython: Hair Simulation against strands whose cell arrays or cells are bad (issue 24;
docs/bad-input.md): a cell array shorter than the strands, one of the wrong number of
components, an empty line cell, NaN and out-of-range values, a zero growth direction. Each
is refused at once with a message naming what is wrong, none is read out of bounds, none
silently copies another strand. (These checks live in convert::toGuides and
GuideStrand::validate since before issue 24's fixes; this test pins their messages.)"""
import os
import time

from paraview.simple import LegacyVTKReader, TrivialProducer, UpdatePipeline
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

import hairtest
from hairtest import Errors, check, fetch

hairtest.load_plugin(globals())

body = LegacyVTKReader(FileNames=[os.path.join(hairtest.DATA, "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16,
                               BodyPartName="head", MovesWithHead=1)
strands = HairStrands(Input=body, NumberOfStrands=5, NumberOfElements=4, StrandLength=0.2)  # noqa: F821
UpdatePipeline(proxy=strands)
good = fetch(strands)


def copy():
    out = vtkPolyData()
    out.DeepCopy(good)
    return out


def refused(polydata, words, what):
    source = TrivialProducer()
    source.GetClientSideObject().SetOutput(polydata)
    sim = HairSimulation(Input=source, Colliders=[head], Duration=0.1)  # noqa: F821
    errors = Errors(sim)
    start = time.time()
    sim.UpdatePipeline(0.1)
    check(any(words in m for m in errors.messages) and time.time() - start < 10,
          f"{what} is refused at once ({errors.messages[:1]})")


# The unedited strands run (the test's inputs are otherwise valid).
source = TrivialProducer()
source.GetClientSideObject().SetOutput(copy())
ok = HairSimulation(Input=source, Colliders=[head], Duration=0.1)  # noqa: F821
ok_errors = Errors(ok)
ok.UpdatePipeline(0.1)
check(not ok_errors.messages and fetch(ok).GetNumberOfLines() == 5, "the unedited strands run")

short = copy()
short.GetCellData().GetArray("Length").SetNumberOfTuples(3)
refused(short, "cell array 'Length' has 3 tuples of 1 components for 5 cells",
        "a Length array shorter than the strands")

wide = copy()
wide.GetCellData().RemoveArray("Radius")
radius = good.GetCellData().GetArray("Radius").NewInstance()
radius.SetName("Radius")
radius.SetNumberOfComponents(2)
radius.SetNumberOfTuples(5)
for i in range(5):
    radius.SetTuple2(i, 5e-5, 5e-5)
wide.GetCellData().AddArray(radius)
refused(wide, "cell array 'Radius' has 5 tuples of 2 components", "a Radius array of 2 components")

missing = copy()
missing.GetCellData().RemoveArray("YoungModulus")
refused(missing, "lacks the cell array 'YoungModulus'", "a missing cell array")

# Strand 2's line replaced by an empty one (the issue: it silently took strand 1's root).
empty = copy()
lines = vtkCellArray()
ids = good.GetLines()
ids.InitTraversal()
cell = vtkIdList()
k = 0
while ids.GetNextCell(cell):
    if k == 2:
        lines.InsertNextCell(0)
    else:
        lines.InsertNextCell(cell)
    k += 1
empty.SetLines(lines)
refused(empty, "polyline 2 of the strands input has no points", "an empty line cell")

for array, value, words in (("Length", float("nan"), "length nan"),
                            ("Length", -0.3, "length -0.3"),
                            ("Radius", float("nan"), "radius"),
                            ("YoungModulus", -1.0, "youngModulus"),
                            ("NumberOfElements", 0, "0 elements")):
    bad = copy()
    bad.GetCellData().GetArray(array).SetTuple1(1, value)
    refused(bad, words, f"{array} = {value} on strand 1")

zero = copy()
zero.GetCellData().GetArray("GrowthDirection").SetTuple3(3, 0, 0, 0)
refused(zero, "zero or NaN growth direction", "a zero growth direction")

hairtest.finish()
