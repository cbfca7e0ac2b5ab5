"""Makes the fuzzer's seed corpus, Testing/Fuzz/corpus/: small real state files of every kind
the reader meets (docs/robustness.md).

  python3 Scripts/make_fuzz_corpus.py <build>/bin/hair_study Testing/Fuzz/corpus

- super-helix.h5, projective.h5: Core's Simulation through hair_study (2 strands, 2 frames),
  as Hair Simulation writes them (format version 3: SWMR, latest format, states and nodes,
  and /resume, the continuation a resumed run reads).
- Kept, not made here (the code that wrote them is in git history): v1-super-helix.h5 and
  v1-projective.h5 (format version 1, at 4 points per element, commit 1b87920's
  hair_study), the fixtures of the version read.

Files written by several MPI ranks (HDF5's earliest format) are not seeds: their fixtures,
Testing/Fixtures/StateFiles/, are damaged 1 000 times each by Scripts/hostile_files.py and
each copy read in a child with a time limit (docs/robustness.md, "Hostile files at scale").
- h5py.h5: written by h5py by the documented names only (fixed-length strings, contiguous
  datasets, the default format), as a user's script writes one.
- killed.h5: an h5py SWMR writer that never closed (as after SIGKILL): the file still says a
  writer has it, so the reader's SWMR open and its retries are taken.
"""
import os
import subprocess
import sys

import h5py
import numpy as np

study, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for model in ("super-helix", "projective"):
    path = os.path.join(out, f"{model}.h5")
    subprocess.run([study, "scene", f"out={path}", "strands=2", "n=2", "duration=0.0334",
                    f"model={model}"] + (["dt=0.001"] if model == "projective" else []),
                   check=True)

T, S, per = 2, 2, 3
P = S * per


def fill(f):
    f["time"] = np.arange(T) / 30.0
    f["strands/offsets"] = np.arange(S + 1, dtype=np.int64) * per
    f["strands/length"] = np.full(S, 0.3)
    f["frames/positions"] = np.linspace(0, 1, T * P * 3).reshape(T, P, 3)
    f["frames/velocities"] = np.zeros((T, P, 3))
    for name in ("kinetic", "elastic", "gravitational", "dissipated", "external_work"):
        f[f"energy/{name}"] = np.zeros(T)


with h5py.File(os.path.join(out, "h5py.h5"), "w") as f:
    f.attrs["format"] = np.bytes_("HairDynamics states")
    f.attrs["format_version"] = np.int32(1)
    f.attrs["model"] = np.bytes_("projective")
    f.attrs["coordinates_per_strand"] = np.int32(0)
    f.attrs["time_step"] = 1 / 30
    fill(f)

# A SWMR writer left open: the child process exits without closing the file.
code = f"""
import os, h5py, numpy as np
f = h5py.File({os.path.join(out, 'killed.h5')!r}, "w", libver="latest")
f.attrs["format"] = "HairDynamics states"
f.attrs["format_version"] = 1
f.attrs["model"] = "projective"
f.attrs["coordinates_per_strand"] = 0
f["strands/offsets"] = np.arange({S + 1}, dtype=np.int64) * {per}
t = f.create_dataset("time", (0,), maxshape=(None,), chunks=(64,))
p = f.create_dataset("frames/positions", (0, {P}, 3), maxshape=(None, {P}, 3), chunks=(1, {P}, 3))
v = f.create_dataset("frames/velocities", (0, {P}, 3), maxshape=(None, {P}, 3), chunks=(1, {P}, 3))
e = [f.create_dataset("energy/" + n, (0,), maxshape=(None,), chunks=(64,))
     for n in ("kinetic", "elastic", "gravitational", "dissipated", "external_work")]
f.swmr_mode = True
for k in range({T}):
    for d in [p, v] + e:
        d.resize(k + 1, axis=0)
    p[k] = k
    t.resize(k + 1, axis=0)
    t[k] = k / 30
    f.flush()
os._exit(0)
"""
subprocess.run([sys.executable, "-c", code], check=True)
for name in sorted(os.listdir(out)):
    print(f"{name}: {os.path.getsize(os.path.join(out, name))} bytes")
