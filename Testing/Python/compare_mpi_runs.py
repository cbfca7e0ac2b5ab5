"""The same run of mpi_hair_simulation.py on 1, 2 and 4 ranks: the state files read the same
with h5py by the documented procedure (docs/state-file.md), and Hair Analysis's tables agree.

Without hair-hair contacts each strand's step depends on nothing else, so the strands are the
same bit for bit whatever rank stepped them: every /frames and /strands dataset and /time
must be equal, exactly. The energy terms are sums over the strands, each rank adding its own
and the ranks adding their sums: the same S numbers added in another order, off by at most
(S - 1) u sum|x_i| (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., 4.2;
u = 2**-53), sum|x_i| bounded by the sum of the magnitudes of every term of the frame. The
analysis's means (of S tips, deflections, displacements) likewise, by (S - 1) u max|x_i|;
its maxima, span, counts and tracked tips are exact.

Run: /usr/bin/python3 Testing/Python/compare_mpi_runs.py <state of 1 rank> <of 2> <of 4>
"""
import sys

import h5py
import numpy as np

U = 2.0 ** -53
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        failures.append(what)


def whole_frames(f):
    """The documented rule: /whole_frames when the file has it (written by several ranks),
    else the length of /time."""
    return int(f["whole_frames"][()]) if "whole_frames" in f else f["time"].shape[0]


def read(path):
    # swmr=True opens both kinds: a file of one writer and a file of ranks.
    with h5py.File(path, "r", swmr=True) as f:
        T = whole_frames(f)
        out = {"version": int(f.attrs["format_version"]), "T": T, "shared": "whole_frames" in f,
               "attrs": {k: f.attrs[k] for k in f.attrs if k != "format_version"},
               "time": f["time"][:T]}
        for group in ("strands", "frames", "energy"):
            for name, d in f[group].items():
                out[f"{group}/{name}"] = d[:] if group == "strands" else d[:T]
    return out


paths = sys.argv[1:4]
runs = [read(p) for p in paths]
one = runs[0]
S = one["strands/offsets"].shape[0] - 1
check([r["version"] for r in runs] == [3, 3, 3] and [r["shared"] for r in runs] == [False, True, True],
      f"format versions {[r['version'] for r in runs]}, /whole_frames {[r['shared'] for r in runs]}: "
      "version 3, counted by /whole_frames when ranks write together")
for n, r in zip((2, 4), runs[1:]):
    check(r["T"] == one["T"] and np.array_equal(r["time"], one["time"]),
          f"{n} ranks: the same {r['T']} whole frames at the same times")
    keys = sorted(k for k in one if k.startswith(("strands/", "frames/")))
    check(keys == sorted(k for k in r if k.startswith(("strands/", "frames/"))),
          f"{n} ranks: the same datasets")
    worst = max(np.abs(r[k] - one[k]).max() for k in keys)
    check(worst == 0, f"{n} ranks: every /strands and /frames dataset equal (largest difference {worst})")
    same_attrs = all(np.array_equal(np.asarray(r["attrs"][k]), np.asarray(v)) for k, v in one["attrs"].items())
    check(same_attrs and set(r["attrs"]) == set(one["attrs"]), f"{n} ranks: the same attributes")
    energy = sorted(k for k in one if k.startswith("energy/"))
    scale = sum(np.abs(one[k]) for k in energy)
    bound = (S - 1) * U * scale
    off = max((np.abs(r[k] - one[k]) / np.maximum(bound, 1e-300)).max() for k in energy)
    check(off <= 1, f"{n} ranks: the energy terms within (S-1) u sum|terms| "
          f"(largest difference {off:.2f} of the bound)")

# Hair Analysis, rank 0's table of each run.
tables = []
for p in paths:
    with open(p + ".analysis.csv") as f:
        names = f.readline().strip().split(",")
    tables.append((names, np.loadtxt(p + ".analysis.csv", delimiter=",", skiprows=1, ndmin=2)))
names, base = tables[0]
energy_columns = [c for c, n in enumerate(names) if f"energy/{n}" in one]
mean_columns = [c for c, n in enumerate(names) if n.startswith("mean_")]
exact_columns = [c for c, n in enumerate(names) if c not in energy_columns + mean_columns]
for n, (other_names, table) in zip((2, 4), tables[1:]):
    check(other_names == names and table.shape == base.shape, f"{n} ranks: Hair Analysis, the same columns and rows")
    if other_names != names or table.shape != base.shape:
        continue
    exact = np.abs(table[:, exact_columns] - base[:, exact_columns]).max()
    check(exact == 0, f"{n} ranks: Hair Analysis's time, tracked tips, span, maxima and contacts equal "
          f"(largest difference {exact})")
    scale = np.abs(base[:, energy_columns]).sum(axis=1, keepdims=True)
    off = (np.abs(table[:, energy_columns] - base[:, energy_columns]) / ((S - 1) * U * scale)).max()
    check(off <= 1, f"{n} ranks: Hair Analysis's energy columns within the bound ({off:.2f} of it)")
    # mean_tip_*: (S-1) u max|tip coordinate|; the tips are within 2 m of the origin here.
    off = (np.abs(table[:, mean_columns] - base[:, mean_columns]) / ((S - 1) * U * 2.0)).max()
    check(off <= 1, f"{n} ranks: Hair Analysis's means within (S-1) u max|x| ({off:.2f} of it)")

print(f"{len(failures)} failed" if failures else "all checks passed")
sys.exit(1 if failures else 0)
