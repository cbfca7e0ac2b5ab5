"""pvpython: the guides as Hair Simulation and Hair State Reader draw them — Points Per
Element sets the Super-Helix points per strand (and changing it does not run the simulation
again), the reader draws a file again at any
resolution as the run does, both give the material frame (Tangent, Director1) at every
point and the rest root, scalp normal and growth direction per strand, the frame at each
root is the guide's rest root frame at t = 0, and a file without root poses reads at its
stored points with a warning."""
import os
import shutil
import tempfile

import h5py
import numpy as np
from paraview.simple import LegacyVTKReader
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand

import hairtest
from hairtest import check, fetch

hairtest.load_plugin(globals())
tmp = tempfile.mkdtemp()


def array(data, name):
    a = data.GetArray(name)
    if a is None:
        return None
    return np.array([a.GetTuple(i) for i in range(a.GetNumberOfTuples())])


def points(polydata):
    return np.array([polydata.GetPoint(i) for i in range(polydata.GetNumberOfPoints())])


def firsts(polydata):
    """The index of each polyline's first point."""
    lines = polydata.GetLines()
    ids = [int(lines.GetOffsetsArray().GetValue(i)) for i in range(lines.GetNumberOfCells())]
    conn = lines.GetConnectivityArray()
    return [int(conn.GetValue(i)) for i in ids]


def unit_orthogonal(v):
    """Eigen's unitOrthogonal() of a 3-vector (GuideStrand::rootFrame() takes it when the
    growth is along the normal)."""
    x, y, z = v
    if not (abs(x) <= abs(z) * 1e-12 and abs(y) <= abs(z) * 1e-12):
        r = 1 / np.hypot(x, y)
        return np.array([-y * r, x * r, 0.0])
    r = 1 / np.hypot(y, z)
    return np.array([0.0, -z * r, y * r])


def rest_root_frames(cd):
    """GuideStrand::rootFrame() from the cell arrays: n0 along the growth, n1 the scalp normal
    made perpendicular (any perpendicular when they are parallel), n2 = n0 × n1."""
    frames = []
    for g, n in zip(array(cd, "GrowthDirection"), array(cd, "RootNormal")):
        n0 = g / np.linalg.norm(g)
        n1 = n - n.dot(n0) * n0
        n1 = unit_orthogonal(n0) if np.linalg.norm(n1) < 1e-6 else n1 / np.linalg.norm(n1)
        frames.append(np.column_stack([n0, n1, np.cross(n0, n1)]))
    return frames


class Warnings:
    def __init__(self, proxy):
        self.messages = []

        @calldata_type(VTK_STRING)
        def on_warning(obj, event, message):
            self.messages.append(str(message))

        self._observer = on_warning
        proxy.GetClientSideObject().AddObserver(vtkCommand.WarningEvent, on_warning)


body = LegacyVTKReader(FileNames=[os.path.join(hairtest.DATA, "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16,
                               BodyPartName="head", MovesWithHead=1)
guides = HairStrands(Input=body, NumberOfStrands=6, NumberOfElements=10, StrandLength=0.3,  # noqa: F821
                     HairType="Curly (Caucasian 2)")

for model in ("Super-Helix", "Projective"):
    runs = {}
    for per in (8, 16):
        runs[per] = HairSimulation(Input=guides, Colliders=[head], Model=model, Duration=0.3,  # noqa: F821
                                   BodyMotion="Shake", PointsPerElement=per,
                                   StateFileName=os.path.join(tmp, f"{model}-{per}.h5"))
    default = HairSimulation(Input=guides, Colliders=[head], Model=model, Duration=0.1)  # noqa: F821
    check(default.PointsPerElement == 16, f"{model}: Points Per Element defaults to 16")
    expected = {8: 81, 16: 161} if model == "Super-Helix" else {8: 11, 16: 11}
    for per, sim in runs.items():
        sim.UpdatePipeline(0.3)
        out = fetch(sim)
        check(out.GetNumberOfPoints() == 6 * expected[per],
              f"{model}: at {per} points per element, {expected[per]} points per strand "
              f"(got {out.GetNumberOfPoints() / 6:g})")

    # Points Per Element is how a frame is drawn, not the run: changed, the frame is drawn
    # again from the kept state, the state file (created when a run is built) is not made anew.
    sim = runs[8]
    path = os.path.join(tmp, f"{model}-8.h5")
    made = os.stat(path).st_ino, os.stat(path).st_mtime_ns
    sim.PointsPerElement = 4
    sim.UpdatePipeline(0.3)
    redrawn = fetch(sim).GetNumberOfPoints()
    again = os.stat(path).st_ino, os.stat(path).st_mtime_ns
    sim.PointsPerElement = 8
    sim.UpdatePipeline(0.3)
    check(redrawn == 6 * (41 if model == "Super-Helix" else 11) and again == made
          and fetch(sim).GetNumberOfPoints() == 6 * expected[8],
          f"{model}: changing Points Per Element draws the frame again ({redrawn / 6:g} points per "
          f"strand at 4) without running the simulation again (the state file untouched: {again == made})")

    # The arrays, on the run at 16 and on the reader at 16 of the file of the run drawn at 8
    # (the file keeps states and nodes, whatever the run drew).
    sim = runs[16]
    reader = HairStateReader(FileName=os.path.join(tmp, f"{model}-8.h5"), PointsPerElement=16)  # noqa: F821
    worst = 0.0
    for t in (0.0, 0.1, 0.3):
        sim.UpdatePipeline(t)
        reader.UpdatePipeline(t)
        a, b = fetch(sim), fetch(reader)
        for name in ("Tangent", "Director1", "Velocity"):
            x, y = array(a.GetPointData(), name), array(b.GetPointData(), name)
            worst = max(worst, np.abs(x - y).max() if x is not None and y is not None else np.inf)
        worst = max(worst, np.abs(points(a) - points(b)).max())
    check(worst < 1e-12, f"{model}: the reader at 16 points per element of the run drawn at 8's file "
                         f"is the run at 16 (largest difference {worst:.2g})")

    for who, proxy in (("Hair Simulation", sim), ("Hair State Reader", reader)):
        proxy.UpdatePipeline(0.0)
        out = fetch(proxy)
        pd, cd = out.GetPointData(), out.GetCellData()
        t, d = array(pd, "Tangent"), array(pd, "Director1")
        check(t is not None and d is not None and t.shape[1] == 3 and d.shape[1] == 3,
              f"{model}, {who}: point arrays Tangent and Director1 (3 components)")
        check(all(cd.GetArray(n) is not None and cd.GetArray(n).GetNumberOfComponents() == 3
                  for n in ("RestRoot", "RootNormal", "GrowthDirection")),
              f"{model}, {who}: cell arrays RestRoot, RootNormal, GrowthDirection")
        unit = max(np.abs(np.linalg.norm(t, axis=1) - 1).max(), np.abs(np.linalg.norm(d, axis=1) - 1).max(),
                   np.abs(np.einsum("ij,ij->i", t, d)).max())
        check(unit < 1e-12, f"{model}, {who}: Tangent and Director1 unit and orthogonal ({unit:.2g})")
        roots = firsts(out)
        dev = max(np.abs(np.column_stack([t[i], d[i], np.cross(t[i], d[i])]) - f).max()
                  for i, f in zip(roots, rest_root_frames(cd)))
        check(dev < 1e-12, f"{model}, {who}: at t = 0 the frame at each root is the rest root "
                           f"frame ({dev:.2g})")
        rest = array(cd, "RestRoot")
        check(np.abs(points(out)[roots] - rest).max() < 1e-12, f"{model}, {who}: RestRoot is the root at t = 0")

# A file without root poses (as written before them): the stored points, a warning, no frames.
old = os.path.join(tmp, "old.h5")
with h5py.File(os.path.join(tmp, "Super-Helix-8.h5"), "r", swmr=True) as src, h5py.File(old, "w") as dst:
    for name, value in src.attrs.items():
        dst.attrs[name] = value
    for group in ("strands", "energy"):
        src.copy(src[group], dst, group)
    src.copy(src["time"], dst, "time")
    frames = dst.create_group("frames")
    for name in src["frames"]:
        if name not in ("root_frames", "root_velocities"):
            src.copy(src["frames"][name], frames, name)
reader = HairStateReader(FileName=old, PointsPerElement=16)  # noqa: F821
warnings = Warnings(reader)
reader.UpdatePipeline(0.1)
out = fetch(reader)
check(out.GetNumberOfPoints() == 6 * 11, f"a file without root poses reads at its stored 11 nodes per strand "
                                         f"(got {out.GetNumberOfPoints() / 6:g})")
check(any("no root poses" in m for m in warnings.messages), f"with a warning saying why ({warnings.messages[:1]})")
check(out.GetPointData().GetArray("Director1") is None, "and without material frames")

shutil.rmtree(tmp)
hairtest.finish()
