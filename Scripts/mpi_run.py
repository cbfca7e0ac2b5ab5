"""A Hair Simulation run shared among MPI ranks: the demo's scene (wavy guides combed on the
bundled body, head and trunk collision tables, the head shaking, a little wind, body
contacts), each rank stepping its share of the guides, every rank writing its part of one
state file, and Hair Analysis's table of the whole run written by rank 0 (docs/mpi.md).

  mpirun -np N pvbatch --symmetric Scripts/mpi_run.py <HairDynamics.so> [--guides 500]
      [--duration 1.0] [--out Output/mpi_run]

Writes <out>/run.h5 (the state file: open it in ParaView with Hair State Reader, or with
h5py, docs/state-file.md) and <out>/analysis.csv (Hair Analysis's table, one row a frame).
Every rank prints its share of the guides. On one process (`pvbatch Scripts/mpi_run.py …`)
the same run, the same file.
"""
import argparse
import os
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, OutputPort

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundled  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("--guides", type=int, default=500)
parser.add_argument("--duration", type=float, default=1.0)
parser.add_argument("--out", default="Output/mpi_run")
args = parser.parse_args()

LoadPlugin(args.plugin, remote=False, ns=globals())
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()
if rank == 0:
    os.makedirs(args.out, exist_ok=True)
state = os.path.join(args.out, "run.h5")

body = bundled.body()
parts = bundled.tables(body, CylindricalCollisionMap)  # noqa: F821
guides = HairStrands(Input=body, NumberOfStrands=args.guides, StrandLength=0.30,  # noqa: F821
                     NumberOfElements=10, HairType="Wavy (Caucasian 1)", Growth="Combed",
                     CombDirection=[0, -1, -0.3], CombWeight=0.35)
sim = HairSimulation(Input=guides, Colliders=[parts["head"], parts["trunk"]],  # noqa: F821
                     Duration=args.duration, FrameRate=30, BodyMotion="Shake",
                     MotionAmplitude=0.5, MotionFrequency=1.0, Wind=[0, 0, -0.5],
                     StateFileName=state, OverwriteStateFile=1)
# Every frame: each rank steps its strands and writes its part of the file.
sim.UpdatePipeline(args.duration)
piece = sim.GetClientSideObject().GetOutputDataObject(0)
ghost = piece.GetCellData().GetArray("vtkGhostType")
own = sum(1 for k in range(piece.GetNumberOfCells()) if not (ghost and int(ghost.GetValue(k)) & 1))
print(f"rank {rank} of {ranks}: {own} of the {args.guides} guides", flush=True)

# Hair Analysis reduces over the pieces: the whole run's table, on rank 0.
analysis = HairAnalysis(Input=sim, Energy=OutputPort(sim, 1))  # noqa: F821
analysis.UpdatePipeline(args.duration)
table = analysis.GetClientSideObject().GetOutputDataObject(0)
if rank == 0:
    names = [table.GetColumnName(c) for c in range(table.GetNumberOfColumns())]
    with open(os.path.join(args.out, "analysis.csv"), "w") as out:
        out.write(",".join(names) + "\n")
        for r in range(table.GetNumberOfRows()):
            out.write(",".join(repr(table.GetValue(r, c).ToDouble()) for c in range(len(names))) + "\n")
    print(f"{state}: {table.GetNumberOfRows()} frames; {os.path.join(args.out, 'analysis.csv')}",
          flush=True)
