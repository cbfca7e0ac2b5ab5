"""Hair State Reader drawing one frame: the time of a request for another time step
(UpdatePipeline: the frame read from the file and drawn at Points Per Element), for each
state file given, requests alternated between the files round after round.

  pvpython Scripts/bench_state_reader.py <HairDynamics.so> <file.h5> [<file.h5> …]
           [--points 16] [--rounds 5]

Per file: its format version, strands, bytes per strand per frame (the file's size over its
strands and frames), and the median and smallest time of a request over the rounds (each
round asks every file for the same two frames, one after the other, and times the second).
Made for docs/benchmarks.md ("Hair State Reader"): a file of format version 1 at 16 points
per element (written by a build of format version 1 or 2) beside one of version 3.
"""
import argparse
import os
import statistics
import time

import h5py
from paraview.simple import LoadPlugin

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("files", nargs="+")
parser.add_argument("--points", type=int, default=16)
parser.add_argument("--rounds", type=int, default=5)
args = parser.parse_args()
LoadPlugin(args.plugin, remote=False, ns=globals())

readers, info = [], []
for path in args.files:
    with h5py.File(path, "r", swmr=True) as f:
        T = int(f["whole_frames"][()]) if "whole_frames" in f else f["time"].shape[0]
        S = f["strands/offsets"].shape[0] - 1
        info.append((int(f.attrs["format_version"]), S, os.path.getsize(path) / S / T, T))
    r = HairStateReader(FileName=path, PointsPerElement=args.points)  # noqa: F821 (the plugin's)
    r.UpdatePipeline(list(r.TimestepValues)[0])
    readers.append(r)

times = [[] for _ in readers]
for _ in range(args.rounds):
    for k, r in enumerate(readers):
        steps = list(r.TimestepValues)
        r.UpdatePipeline(steps[1])
        t0 = time.perf_counter()
        r.UpdatePipeline(steps[2])
        times[k].append(time.perf_counter() - t0)
        r.UpdatePipeline(steps[0])

print(f"| file | format_version | strands | bytes per strand per frame | a frame at {args.points} points per element, median (min) |")
print("|---|---|---|---|---|")
for path, (v, S, per, T), t in zip(args.files, info, times):
    print(f"| {os.path.basename(path)} | {v} | {S} | {per:.0f} | {1e3 * statistics.median(t):.1f} ms ({1e3 * min(t):.1f}) |")
