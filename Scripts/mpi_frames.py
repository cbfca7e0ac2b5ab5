"""The frames of a Hair Simulation run under MPI, timed (what Scripts/bench_mpi.py pvbatch runs):
Hair Strands on the bundled body (wavy, combed), the head and trunk collision maps, and Hair
Simulation (Super-Helix, the demo's shake and wind, body contacts on, a state file), each
rank stepping its share of the guides.

  mpirun -np N pvbatch --symmetric Scripts/mpi_frames.py <HairDynamics.so> <guides> <frames> <state.h5> [threads] [points per element]

Every frame is asked for in turn (sim.UpdatePipeline(t)): stepped, written to the state file
by every rank together, drawn and handed to ParaView as each rank's piece (with the ghost
strands ParaView asks for in parallel). The first two frames (frame 0 and the first step,
which build the run and open the file) are not timed. Rank 0 prints one line of JSON: the
wall time of each timed frame (between barriers), each rank's CPU time per frame, its strands
and ghosts, and the time the run took to build.
"""
import json
import os
import sys
import time

from mpi4py import MPI
from paraview import servermanager
from paraview.simple import LoadPlugin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundled  # noqa: E402

if len(sys.argv) < 5:
    sys.exit(__doc__)
LoadPlugin(sys.argv[1], remote=False, ns=globals())
count, frames, state = int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
threads = int(sys.argv[5]) if len(sys.argv) > 5 else 1
per = int(sys.argv[6]) if len(sys.argv) > 6 else 16
comm = MPI.COMM_WORLD
rank = comm.Get_rank()
RATE = 30

body = bundled.body()
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821
guides = HairStrands(Input=body, NumberOfStrands=count, StrandLength=0.30,  # noqa: F821
                     NumberOfElements=10, HairType="Wavy (Caucasian 1)", Growth="Combed",
                     CombDirection=[0, -1, -0.3], CombWeight=0.35)
for p in (guides, parts["head"], parts["trunk"]):
    p.UpdatePipeline()
sim = HairSimulation(Input=guides, Colliders=[parts["head"], parts["trunk"]],  # noqa: F821
                     Duration=(frames + 1) / RATE, FrameRate=RATE, BodyMotion="Shake",
                     MotionAmplitude=0.5, MotionFrequency=1.0, Wind=[0, 0, -0.5],
                     NumberOfThreads=threads, PointsPerElement=per,
                     StateFileName="" if state == "-" else state,
                     OverwriteStateFile=1)
comm.Barrier()
start = time.time()
sim.UpdatePipeline(1 / RATE)  # builds the run (frame 0) and takes the first step
comm.Barrier()
build = time.time() - start
wall, cpu = [], []
for i in range(2, frames + 1):
    comm.Barrier()
    w, c = time.perf_counter(), time.process_time()
    sim.UpdatePipeline(i / RATE)
    c = time.process_time() - c
    comm.Barrier()
    wall.append(time.perf_counter() - w)
    cpu.append(c)
out = sim.GetClientSideObject().GetOutputDataObject(0)
ghost = out.GetCellData().GetArray("vtkGhostType")
ghosts = sum(1 for k in range(out.GetNumberOfCells()) if ghost and int(ghost.GetValue(k)) & 1)
mine = out.GetNumberOfCells() - ghosts
cpus = comm.gather(sum(cpu) / len(cpu), root=0)
strands = comm.gather(mine, root=0)
ghost_counts = comm.gather(ghosts, root=0)
if rank == 0:
    print(json.dumps({"ranks": comm.Get_size(), "guides": count, "threads": threads,
                      "points_per_element": per, "wall": wall, "cpu_per_rank": cpus,
                      "strands_per_rank": strands, "ghosts_per_rank": ghost_counts,
                      "build_s": build}), flush=True)
