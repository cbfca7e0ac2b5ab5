"""pvpython: the Cylindrical Collision Map filter as a user applies it to the bundled body.

Run: pvpython Testing/Python/test_collision_map.py build/lib/paraview-5.11/plugins/HairDynamics/HairDynamics.so
The references are VTK's own: vtkImplicitPolyDataDistance (distance to the input mesh) and
vtkSelectEnclosedPoints (inside test), not HairDynamics code.
"""
import math
import os
import tempfile

from paraview.simple import LegacyVTKReader, UpdatePipeline, XMLPolyDataReader
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkCellArray
from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import hairtest
from hairtest import check, fetch, Errors

hairtest.load_plugin(globals())

body_file = os.path.join(hairtest.DATA, "body.vtk")
body = LegacyVTKReader(FileNames=[body_file])
mesh = fetch(body)
check(mesh.GetNumberOfCells() == 26756, "the bundled body has 26756 triangles")

# --- The head, spherical, as in Data/body_parts.txt ---------------------------------
head = CylindricalCollisionMap(Input=body)  # noqa: F821 (defined by the plugin)
head.Projection = "Spherical"
head.AutomaticFrame = 0
head.Origin = [0, 1.555, 0.055]
head.Axis = [0, 1, 0]
head.ReferenceDirection = [0, 0, 1]
head.MaximumRadius = 0.16
head.BodyPartName = "head"
head.MovesWithHead = 1
UpdatePipeline(proxy=head)

table = fetch(head, 0)
check(table.GetDimensions() == (40, 40, 1), f"the table is 40 x 40 (got {table.GetDimensions()})")
pd = table.GetPointData()
for name, comps in (("Radius", 1), ("InnerRadius", 1), ("Normal", 3), ("InnerNormal", 3), ("Hit", 1)):
    a = pd.GetArray(name)
    check(a is not None and a.GetNumberOfComponents() == comps and a.GetNumberOfTuples() == 1600,
          f"point array {name} with {comps} component(s) on every sample")
fd = table.GetFieldData()
check(fd.GetArray("Projection").GetValue(0) == 1, "field data says spherical")
check([fd.GetArray("FrameOrigin").GetComponent(0, k) for k in range(3)] == [0, 1.555, 0.055],
      "field data carries the frame origin")
check(fd.GetAbstractArray("BodyPartName").GetValue(0) == "head", "field data names the part")
check(fd.GetArray("MovesWithHead").GetValue(0) == 1, "field data says it moves with the head")

hit = pd.GetArray("Hit")
radius = pd.GetArray("Radius")
check(all(hit.GetValue(i) == 1 for i in range(1600)), "every ray from inside the head meets it")
# The crown is at y = 1.6599 (the mesh's top): the pole sample (j = 0) must find it.
crown = radius.GetValue(0)
check(abs(crown - (1.6599 - 1.555)) < 0.003, f"radius at the pole reaches the crown ({crown:.4f} m)")
# Straight down the rays run into the neck and are capped at the maximum radius.
check(abs(radius.GetValue(39 * 40) - 0.16) < 1e-12, "the downward ray is capped at 0.16 m")

# --- The represented surface lies on the mesh: VTK's distance to the input mesh --------
surface = fetch(head, 1)
check(surface.GetNumberOfPolys() > 1400, f"surface output has quads ({surface.GetNumberOfPolys()})")
distance = vtkImplicitPolyDataDistance()
distance.SetInput(mesh)
worst = 0.0
capped = 0
for i in range(surface.GetNumberOfPoints()):
    if abs(radius.GetValue(i) - 0.16) < 1e-12:
        capped += 1
        continue
    worst = max(worst, abs(distance.EvaluateFunction(surface.GetPoint(i))))
check(worst < 1e-6, f"uncapped surface points lie on the mesh (worst {worst:.2e} m)")
check(0 < capped < 400, f"a minority of samples are capped ({capped})")

# --- The trunk, cylindrical, automatic frame ----------------------------------------------
auto = CylindricalCollisionMap(Input=body)  # noqa: F821
UpdatePipeline(proxy=auto)
t = fetch(auto, 0)
fd = t.GetFieldData()
axis = [fd.GetArray("FrameAxis").GetComponent(0, k) for k in range(3)]
check(axis == [0, 1, 0], f"automatic frame: the body's longest side, Y, is the axis ({axis})")
h = fd.GetArray("HeightRange")
check(abs((h.GetValue(1) - h.GetValue(0)) - 1.6594 * 0.999) < 1e-3, "automatic heights span the body")

# --- Bad input: a clear error each, no crash, nothing half-made ---------------------------
def expect_error(proxy, fragment, what):
    errors = Errors(proxy)
    UpdatePipeline(proxy=proxy)
    joined = " | ".join(errors.messages)
    check(any(fragment in m for m in errors.messages), f"{what}: error says '{fragment}' ({joined[:160]})")


def write_polydata(points, polys):
    pts = vtkPoints()
    for p in points:
        pts.InsertNextPoint(p)
    cells = vtkCellArray()
    for c in polys:
        cells.InsertNextCell(len(c), c)
    pdata = vtkPolyData()
    pdata.SetPoints(pts)
    pdata.SetPolys(cells)
    fd_, path = tempfile.mkstemp(suffix=".vtp")
    os.close(fd_)
    w = vtkXMLPolyDataWriter()
    w.SetInputData(pdata)
    w.SetFileName(path)
    w.Write()
    return path


empty = XMLPolyDataReader(FileName=[write_polydata([], [])])
expect_error(CylindricalCollisionMap(Input=empty), "is empty", "an empty mesh")  # noqa: F821
points_only = XMLPolyDataReader(FileName=[write_polydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [])])
expect_error(CylindricalCollisionMap(Input=points_only), "no polygons", "a mesh with no polygons")  # noqa: F821
nan = XMLPolyDataReader(FileName=[write_polydata([(0, 0, 0), (1, 0, 0), (0, math.nan, 0)], [(0, 1, 2)])])
expect_error(CylindricalCollisionMap(Input=nan), "NaN", "NaN coordinates")  # noqa: F821

miss = CylindricalCollisionMap(Input=body)  # noqa: F821
miss.AutomaticFrame = 0
miss.Origin = [5, 0, 0]
miss.HeightRange = [3, 4]
expect_error(miss, "misses", "a frame whose axis misses the mesh")
zero = CylindricalCollisionMap(Input=body, Resolution=[0, 40])  # noqa: F821
expect_error(zero, "resolution", "a zero resolution")
absurd = CylindricalCollisionMap(Input=body, Resolution=[100000, 40])  # noqa: F821
expect_error(absurd, "resolution", "an absurd resolution")
parallel = CylindricalCollisionMap(Input=body, AutomaticFrame=0, ReferenceDirection=[0, 2, 0])  # noqa: F821
expect_error(parallel, "parallel", "a reference direction along the axis")
# Issue 24: a height range of ±1e308 aborted ParaView on a CGAL assertion; a negative or NaN
# maximum radius silently meant "no limit".
huge = CylindricalCollisionMap(Input=body, AutomaticFrame=0, Origin=[0, 1, 0],  # noqa: F821
                               HeightRange=[-1e308, 1e308])
expect_error(huge, "ten times the body's size", "a height range of ±1e308")
for radius in (-5.0, float("nan")):
    bad = CylindricalCollisionMap(Input=body, MaximumRadius=radius)  # noqa: F821
    expect_error(bad, "maximum radius", f"a maximum radius of {radius}")

hairtest.finish()
