"""Hair Interpolation as ParaView runs it: the time of one frame of rendered hair.

  pvpython Scripts/bench_hair_interpolation.py <HairDynamics.so> <state.h5>
           [--strands 100000 200000] [--rounds 5]

Reads the guides of a state file (the demo's Output/super-helix.h5: 200 wavy Super-Helix
guides under the head shake) with Hair State Reader, and renders them on the bundled body
with the head and trunk tables (as Scripts/demo_hair.py does). Per number of rendered
strands: the median and smallest time of a request for a new time step around t = 1 s
(UpdatePipeline: the reader's frame and the interpolation; the reader's share is timed on
its own and given beside), and the points looked up in the tables and pushed out. Made for
docs/benchmarks.md ("Rendered hair").
"""
import argparse
import statistics
import time

from paraview.simple import Delete, LoadPlugin

import bundled

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("state")
parser.add_argument("--strands", type=int, nargs="+", default=[100000, 200000])
parser.add_argument("--rounds", type=int, default=5)
parser.add_argument("--threads", type=int, default=2)
args = parser.parse_args()
LoadPlugin(args.plugin, remote=False, ns=globals())

body = bundled.body()
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821 (the plugin's)
reader = HairStateReader(FileName=args.state)  # noqa: F821
steps = [t for t in reader.TimestepValues if 0.9 <= t <= 1.2]
if len(steps) < 2:
    raise SystemExit(f"{args.state} has no frames between 0.9 and 1.2 s: give the demo's state file")


def timed(proxy, when):
    start = time.perf_counter()
    proxy.UpdatePipeline(when)
    return time.perf_counter() - start


read = [timed(reader, t) for t in steps[: args.rounds]]
print(f"Hair State Reader alone: {1e3 * statistics.median(read):.1f} ms a frame (median)")
print(f"{'strands':>9}{'points':>11}{'median ms':>11}{'best ms':>9}{'looked up':>11}{'pushed out':>12}")
for strands in args.strands:
    hair = HairInterpolation(Input=reader, Scalp=body, Colliders=[parts["head"], parts["trunk"]],  # noqa: F821
                             NumberOfStrands=strands, NumberOfThreads=args.threads)
    hair.UpdatePipeline(steps[0])  # binds once
    seconds = [timed(hair, steps[1 + k % (len(steps) - 1)]) for k in range(args.rounds)]
    data = hair.GetClientSideObject().GetOutputDataObject(0)
    field = data.GetFieldData()
    looked = int(field.GetArray("PointsLookedUp").GetValue(0))
    pushed = int(field.GetArray("PointsPushedOut").GetValue(0))
    points = data.GetNumberOfPoints()
    print(f"{strands:>9}{points:>11}{1e3 * statistics.median(seconds):>11.1f}{1e3 * min(seconds):>9.1f}"
          f"{looked / points:>11.1%}{pushed:>12}")
    Delete(hair)
