"""pvbatch under MPI (2 ranks, --symmetric): Hair Simulation runs on rank 0 only, which
holds every strand and writes the one state file; rank 1 holds none. Hair Analysis on top
gives rank 0 one row per frame and rank 1 an empty table, without hanging in its loop over
time.

Run: mpirun -np 2 pvbatch --symmetric Testing/Python/mpi_hair_simulation.py <HairDynamics.so> <state.h5>
"""
import os
import sys

from paraview import servermanager
from paraview.simple import LegacyVTKReader, LoadPlugin, OutputPort

LoadPlugin(sys.argv[1], remote=False, ns=globals())
state = sys.argv[2]
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
body = LegacyVTKReader(FileNames=[os.path.join(ROOT, "Data", "body.vtk")])
strands = HairStrands(Input=body, NumberOfStrands=10, NumberOfElements=4)  # noqa: F821
sim = HairSimulation(Input=strands, Duration=0.2, StateFileName=state, OverwriteStateFile=1)  # noqa: F821
sim.UpdatePipeline(0.2)
pm = servermanager.vtkProcessModule.GetProcessModule()
rank = pm.GetPartitionId()
lines = sim.GetClientSideObject().GetOutputDataObject(0).GetNumberOfLines()

from mpi4py import MPI  # noqa: E402

analysis = HairAnalysis(Input=sim, Energy=OutputPort(sim, 1))  # noqa: F821
analysis.UpdatePipeline(0.2)
rows = analysis.GetClientSideObject().GetOutputDataObject(0).GetNumberOfRows()

counts = MPI.COMM_WORLD.allgather(lines)
row_counts = MPI.COMM_WORLD.allgather(rows)
ok = counts == [10, 0] and row_counts == [7, 0]
if rank == 0:
    import h5py
    with h5py.File(state, "r", swmr=True) as f:
        ok = ok and f["time"].shape[0] == 7
print(f"rank {rank}: {lines} strands; per rank {counts}; analysis rows per rank {row_counts}; "
      f"{'ok' if ok else 'WRONG'}")
if not ok:
    sys.exit(1)
