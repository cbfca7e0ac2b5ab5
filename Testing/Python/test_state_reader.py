"""pvpython: Hair State Reader reads, frame by frame, a state file that h5py wrote by the
documented names only (docs/state-file.md); a foreign file gets a clear error."""
import os
import tempfile

import h5py
import numpy as np
from paraview.simple import UpdatePipeline

import hairtest
from hairtest import Errors, check, fetch

hairtest.load_plugin(globals())

T, S, per = 6, 4, 5  # frames, strands, points per strand
P = S * per
rng = np.random.default_rng(3)
positions = rng.normal(size=(T, P, 3))
velocities = rng.normal(size=(T, P, 3))
times = np.arange(T) / 30.0
path = os.path.join(tempfile.mkdtemp(), "from_h5py.h5")
with h5py.File(path, "w") as f:
    f.attrs["format"] = "HairDynamics states"
    f.attrs["format_version"] = 1
    f.attrs["model"] = "projective"
    f.attrs["coordinates_per_strand"] = 0
    f.attrs["time_step"] = 1 / 30
    f["time"] = times
    f["strands/offsets"] = np.arange(S + 1, dtype=np.int64) * per
    f["strands/length"] = np.full(S, 0.3)
    f["frames/positions"] = positions
    f["frames/velocities"] = velocities
    for k, name in enumerate(["kinetic", "elastic", "gravitational", "dissipated", "external_work"]):
        f[f"energy/{name}"] = times * (k + 1)

reader = HairStateReader(FileName=path)  # noqa: F821 (from the plugin)
UpdatePipeline(proxy=reader, time=0)
check(list(reader.TimestepValues) == list(times), f"time steps are the file's ({list(reader.TimestepValues)})")
exact = True
for t in range(T):
    UpdatePipeline(proxy=reader, time=times[t])
    out = fetch(reader)
    pts = np.array([out.GetPoint(i) for i in range(out.GetNumberOfPoints())])
    vel = out.GetPointData().GetArray("Velocity")
    v = np.array([vel.GetTuple3(i) for i in range(P)])
    exact = exact and np.array_equal(pts, positions[t]) and np.array_equal(v, velocities[t])
check(exact, "every frame's positions and velocities come back exactly")
check(out.GetNumberOfLines() == S, f"one polyline per strand ({out.GetNumberOfLines()})")
# Named as the pipeline names them (Hair Strands' "Length"), not as the file does ("length").
check(out.GetCellData().GetArray("Length") is not None and out.GetCellData().GetArray("length") is None,
      "per-strand parameters become cell data, named as Hair Strands names them")
# Between frames: the frame at or before the time asked.
UpdatePipeline(proxy=reader, time=times[2] + 0.01)
between = fetch(reader)
check(between.GetPoint(0) == tuple(positions[2][0]), "a time between frames gives the earlier frame")
table = fetch(reader, 1)
check(table.GetNumberOfRows() == T and table.GetColumnByName("kinetic") is not None,
      f"energy table: {table.GetNumberOfRows()} rows with a kinetic column")
check(abs(table.GetColumnByName("elastic").GetValue(5) - times[5] * 2) < 1e-15, "energy values as written")

foreign = os.path.join(tempfile.mkdtemp(), "foreign.h5")
with h5py.File(foreign, "w") as f:
    f["data"] = np.zeros(3)
# The file is opened when its name is set: watch the errors first, then name the file.
bad = HairStateReader(FileName=path)  # noqa: F821
errors = Errors(bad)
bad.FileName = foreign
UpdatePipeline(proxy=bad)
check(any("not a HairDynamics state file" in m for m in errors.messages),
      f"a foreign HDF5 file is refused ({errors.messages[:1]})")
text = os.path.join(tempfile.mkdtemp(), "notes.h5")
open(text, "w").write("not hdf5")
bad2 = HairStateReader(FileName=path)  # noqa: F821
errors2 = Errors(bad2)
bad2.FileName = text
UpdatePipeline(proxy=bad2)
check(any("not an HDF5 file" in m for m in errors2.messages), "a text file is refused")

hairtest.finish()
