"""Frames per second of the whole pipeline, as ParaView runs it: Hair Strands on the bundled
body, its head and trunk collision maps, and Hair Simulation (Super-Helix, the demo's shake
and wind, body contacts on), timed from pvpython.

  xvfb-run -a pvpython Scripts/bench_hair_simulation.py <HairDynamics.so> [guides] [threads] [points]

guides: 1000 by default; threads: Hair Simulation's NumberOfThreads (2); points: its Points
Per Element (16). Prints the time of
a 2 s run (60 frames computed, each stepped and recorded), and of asking again for frames
already computed (the conversion to VTK data and the energy table; what scrubbing the time
costs). Real time is 33 ms per frame.
"""
import os
import sys
import time

from paraview.simple import LoadPlugin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundled  # noqa: E402

if len(sys.argv) < 2:
    sys.exit(__doc__)
LoadPlugin(sys.argv[1], remote=False, ns=globals())
guides_count = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
per = int(sys.argv[4]) if len(sys.argv) > 4 else 16
DURATION, RATE = 2.0, 30

body = bundled.body()
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821
head, trunk = parts["head"], parts["trunk"]
guides = HairStrands(Input=body, NumberOfStrands=guides_count, StrandLength=0.30,  # noqa: F821
                     NumberOfElements=10, HairType="Wavy (Caucasian 1)", Growth="Combed",
                     CombDirection=[0, -1, -0.3], CombWeight=0.35)
for p in (guides, head, trunk):
    p.UpdatePipeline()
sim = HairSimulation(Input=guides, Colliders=[head, trunk], Model="Super-Helix",  # noqa: F821
                     Duration=DURATION, FrameRate=RATE, BodyMotion="Shake", MotionAmplitude=0.5,
                     MotionFrequency=1.0, Wind=[0, 0, -0.5], NumberOfThreads=threads,
                     PointsPerElement=per)
start = time.time()
sim.UpdatePipeline(DURATION)
run = time.time() - start
frames = int(DURATION * RATE)
print(f"{guides_count} Super-Helix guides, {per} points per element, body contacts, {threads} thread(s): "
      f"{1000 * run / frames:.1f} ms per frame ({frames / run:.1f} frames/s) over {frames} frames")
again = [i / RATE for i in range(0, frames, 7)]
start = time.time()
for t in again:
    sim.UpdatePipeline(t)
print(f"frames already computed: {1000 * (time.time() - start) / len(again):.1f} ms per request")
