"""A run under mpirun killed with SIGKILL leaves a state file that reads back to its last whole
frame (docs/state-file.md, "Crash safety").

Runs mpi_write_frames.py on 2 ranks for an hour into a file, in a session of its own; once
the file counts at least 12 whole frames, and a little later (so that the ranks are somewhere
in a later frame), SIGKILL goes to mpirun and both ranks at once. Then the same run to the
end into another file (the reference: at least 2 s, and at least one second longer than the
killed run got). The killed file is then read
with h5py by the documented procedure and with the project's reader (Hair State Reader, in
pvpython): every whole frame, every dataset, equals the reference's same frame exactly (the
same run: without hair-hair contacts, bit for bit), and the reader reports exactly the whole
frames. Last, the killed run is resumed from its file (Hair Simulation's Resume, pvbatch on
the same 2 ranks) to the reference's end: every frame of the file then equals the
reference's, bit for bit (docs/state-file.md, "Resuming a run").

Run: /usr/bin/python3 Testing/Python/mpi_killed_run.py <mpirun> <pvbatch> <pvpython> <HairDynamics.so> <work dir>
"""
import os
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

mpirun, pvbatch, pvpython, plugin, work = sys.argv[1:6]
HERE = os.path.dirname(os.path.abspath(__file__))
os.makedirs(work, exist_ok=True)
reference, killed = os.path.join(work, "reference.h5"), os.path.join(work, "killed.h5")
for path in (reference, killed):
    if os.path.exists(path):
        os.remove(path)
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)


def command(state, duration, *extra):
    return [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", "2", pvbatch, "--symmetric",
            os.path.join(HERE, "mpi_write_frames.py"), plugin, state, str(duration), *extra]


def whole_frames(path):
    """/whole_frames of a file the ranks write together (read while they write it)."""
    try:
        with h5py.File(path, "r") as f:
            return int(f["whole_frames"][()])
    except (OSError, KeyError):
        return -1  # not created yet, or its structure not yet flushed


run = subprocess.Popen(command(killed, 3600), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       start_new_session=True)
deadline = time.time() + 240
while whole_frames(killed) < 12 and run.poll() is None and time.time() < deadline:
    time.sleep(0.05)
time.sleep(0.3)  # into a later frame


def session(sid):
    """The live processes of the session mpirun leads (OpenMPI puts each rank in a process
    group of its own, so a signal to mpirun's group would miss them; they stay in its
    session). Zombies, dead and waiting to be reaped, are not counted."""
    out = subprocess.run(["ps", "-s", str(sid), "-o", "pid=,stat="], capture_output=True, text=True)
    return [int(line.split()[0]) for line in out.stdout.splitlines()
            if line.split() and not line.split()[1].startswith("Z")]


processes = session(run.pid)
for pid in processes:
    os.kill(pid, signal.SIGKILL)  # mpirun and every rank, at once
run.wait()
before = whole_frames(killed)
check(run.returncode == -signal.SIGKILL and len(processes) >= 3,
      f"mpirun and its ranks ({len(processes)} processes) killed with SIGKILL after {before} "
      f"whole frames")
deadline = time.time() + 10  # SIGKILL is not refused, but dying takes the kernel a moment
while session(run.pid) and time.time() < deadline:
    time.sleep(0.1)
left = session(run.pid)
check(not left, f"no process of the killed run is left ({left})")

# The reference, run to the end after the kill and at least as long as the killed run got
# (30 frames a second; on an idle machine the killed run passed 2 s before the kill landed).
seconds = max(2.0, (before + 30) / 30.0)
done = subprocess.run(command(reference, seconds), stdout=subprocess.DEVNULL,
                      stderr=subprocess.DEVNULL)
check(done.returncode == 0, f"the reference run of {seconds:.2f} s ends normally ({done.returncode})")

with h5py.File(killed, "r") as k, h5py.File(reference, "r", swmr=True) as r:
    T = int(k["whole_frames"][()])
    R = int(r["whole_frames"][()]) if "whole_frames" in r else r["time"].shape[0]
    check(k.attrs["format_version"] == 3 and T == before and 12 <= T <= R,
          f"h5py opens the killed file: {T} whole frames, as counted when it was killed "
          f"(format_version {k.attrs['format_version']})")
    worst, names = 0.0, []
    for group in ("frames", "energy"):
        for name, d in k[group].items():
            names.append(f"{group}/{name}")
            worst = max(worst, float(np.abs(d[:T] - r[group][name][:T]).max()))
    worst = max(worst, float(np.abs(k["time"][:T] - r["time"][:T]).max()))
    check(worst == 0, f"every whole frame of {len(names)} datasets and /time equals the reference's "
          f"(largest difference {worst})")
    # Frame T was being written (its time may be there); none after it was begun.
    tail = k["time"][T + 1:]
    check(tail.size > 0 and np.isnan(tail).all(),
          f"/time after the frame being written holds NaN ({np.count_nonzero(np.isnan(tail))} of "
          f"{tail.size}), which no reader takes for a frame")
    expected_last = k["frames/positions"][T - 1]

# The project's reader, in pvpython: exactly the whole frames, the last one as h5py reads it.
script = f"""
import sys
import numpy as np
from paraview import servermanager
from paraview.simple import LoadPlugin
from vtkmodules.util.numpy_support import vtk_to_numpy
LoadPlugin({plugin!r}, remote=False, ns=globals())
reader = HairStateReader(FileName={killed!r}, PointsPerElement=1)
times = list(reader.TimestepValues)
reader.UpdatePipeline(times[-1])
data = servermanager.Fetch(reader)
np.save({os.path.join(work, 'last.npy')!r}, vtk_to_numpy(data.GetPoints().GetData()))
print(len(times))
"""
out = subprocess.run([pvpython, "-c", script], capture_output=True, text=True)
frames = int(out.stdout.strip().splitlines()[-1]) if out.returncode == 0 and out.stdout.strip() else -1
check(frames == T, f"Hair State Reader opens the killed file: {frames} time steps, the whole frames")
if frames == T:
    # Drawn at one point per element: the nodes, from q and the roots in double; the file keeps
    # them in single precision, so rounded they are the file's bit for bit.
    last = np.load(os.path.join(work, "last.npy"))
    difference = float(np.abs(last.astype(np.float32) - expected_last).max()) if last.shape == expected_last.shape else np.inf
    check(difference == 0, f"Hair State Reader's last frame, rounded to single precision, is the file's nodes (largest difference {difference} m)")
else:
    print(out.stdout[-2000:], out.stderr[-2000:])

# The killed run resumed from its last whole frame to the reference's end (the file has room
# for the hour it was started for).
resumed = subprocess.run(command(killed, seconds, "resume"), capture_output=True, text=True)
check(resumed.returncode == 0, f"the killed run resumed to {seconds:.2f} s ends normally "
      f"({resumed.returncode}{': ' + resumed.stderr[-1500:] if resumed.returncode else ''})")
with h5py.File(killed, "r") as k, h5py.File(reference, "r", swmr=True) as r:
    T = int(k["whole_frames"][()])
    R = int(r["whole_frames"][()]) if "whole_frames" in r else r["time"].shape[0]
    worst = 0.0
    for group in ("frames", "energy"):
        for name, d in r[group].items():
            a, b = k[group][name][:T], d[:R]
            worst = max(worst, float(np.abs(a - b).max()) if a.shape == b.shape else np.inf)
    times_equal = np.array_equal(k["time"][:T], r["time"][:R])
    check(T == R and times_equal and worst == 0,
          f"the resumed file has the reference's {R} frames ({T}), every value equal "
          f"(largest difference {worst})")

print(f"{len(failures)} failed" if failures else "all checks passed")
sys.exit(1 if failures else 0)
