"""pvpython: Hair State Reader reads, frame by frame, a state file that h5py wrote by the
documented names only (docs/state-file.md); times outside the run give its first or last
frame and NaN an error; two readers of a growing file both see its new frames after Reload
Files; a foreign file, a FIFO and a damaged file get clear errors."""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np
from paraview.simple import ReloadFiles, UpdatePipeline

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

# Times outside the run: before it the first frame, after it (1e300, +inf) the last, as
# ParaView's time-series readers do; NaN an error (issue 24: NaN and 1e300 gave frame 0).
for asked, expected in ((-5.0, 0), (1e300, T - 1), (float("inf"), T - 1)):
    UpdatePipeline(proxy=reader, time=asked)
    got = fetch(reader)
    check(got.GetPoint(0) == tuple(positions[expected][0]), f"time {asked} gives frame {expected}")
nan_errors = Errors(reader)
UpdatePipeline(proxy=reader, time=float("nan"))
check(any("the time asked for is NaN" in m for m in nan_errors.messages),
      f"time NaN is refused ({nan_errors.messages[:1]})")

# Two readers of one file that grows (another process appends frames, then finishes): each
# sees the new frames after Reload Files (issue 24: the second stayed at its first count).
growing = os.path.join(tempfile.mkdtemp(), "growing.h5")
with h5py.File(growing, "w", libver="latest") as f:
    f.attrs["format"] = "HairDynamics states"
    f.attrs["format_version"] = 1
    f.attrs["model"] = "projective"
    f.attrs["coordinates_per_strand"] = 0
    f.create_dataset("time", data=times[:3], maxshape=(None,), chunks=(16,))
    f["strands/offsets"] = np.arange(S + 1, dtype=np.int64) * per
    for name, data in (("positions", positions), ("velocities", velocities)):
        f.create_dataset(f"frames/{name}", data=data[:3], maxshape=(None, P, 3), chunks=(1, P, 3))
    for k, name in enumerate(["kinetic", "elastic", "gravitational", "dissipated", "external_work"]):
        f.create_dataset(f"energy/{name}", data=times[:3] * (k + 1), maxshape=(None,), chunks=(16,))
first, second = HairStateReader(FileName=growing), HairStateReader(FileName=growing)  # noqa: F821
for r in (first, second):
    UpdatePipeline(proxy=r, time=0)
check(len(first.TimestepValues) == 3 and len(second.TimestepValues) == 3, "both readers see 3 frames")
grow = f"""
import h5py, numpy as np
with h5py.File({growing!r}, "a") as f:
    for name in ["time"] + ["energy/" + n for n in f["energy"]]:
        f[name].resize(({T},))
    f["time"][3:] = {list(times[3:])}
    for name, data in (("positions", {positions[3:].tolist()}), ("velocities", {velocities[3:].tolist()})):
        f["frames/" + name].resize(({T}, {P}, 3))
        f["frames/" + name][3:] = np.array(data)
"""
# Another process (Debian's python3 with h5py: pvpython's sys.executable is not a Python), as a
# simulation elsewhere would be; HDF5's file locks off there, since
# this process may still hold the file (it must not, but the test is of what readers see).
subprocess.run(["/usr/bin/python3", "-c", grow], check=True, env=dict(os.environ, HDF5_USE_FILE_LOCKING="FALSE"))
for r in (first, second):
    ReloadFiles(r)
    UpdatePipeline(proxy=r, time=times[T - 1])
check(len(first.TimestepValues) == T and len(second.TimestepValues) == T,
      f"after Reload Files both readers see the {T} frames ({len(first.TimestepValues)}, {len(second.TimestepValues)})")
last = fetch(second)
check(last.GetPoint(0) == tuple(positions[T - 1][0]), "the second reader shows the new last frame")

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
fifo = os.path.join(tempfile.mkdtemp(), "pipe.h5")
os.mkfifo(fifo)
bad3 = HairStateReader(FileName=path)  # noqa: F821
errors3 = Errors(bad3)
bad3.FileName = fifo
UpdatePipeline(proxy=bad3)
check(any("is not a regular file" in m for m in errors3.messages), f"a FIFO is refused, not waited on ({errors3.messages[:1]})")

hairtest.finish()
