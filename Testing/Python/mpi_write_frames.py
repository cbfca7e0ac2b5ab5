"""pvbatch under MPI (--symmetric): Hair Simulation writes frames to a state file one after
the other, rank 0 printing "frame i" as each is whole. The run that mpi_killed_run.py kills,
its reference, and (with "resume") the killed run resumed from its file to the end.

Run: mpirun -np N pvbatch --symmetric Testing/Python/mpi_write_frames.py <HairDynamics.so> <state.h5> <duration s> [resume]
"""
import os
import sys

from paraview import servermanager
from paraview.simple import LegacyVTKReader, LoadPlugin

LoadPlugin(sys.argv[1], remote=False, ns=globals())
state, duration = sys.argv[2], float(sys.argv[3])
resume = len(sys.argv) > 4 and sys.argv[4] == "resume"
rank = servermanager.vtkProcessModule.GetProcessModule().GetPartitionId()
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
body = LegacyVTKReader(FileNames=[os.path.join(ROOT, "Data", "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16, BodyPartName="head",
                               MovesWithHead=1)
guides = HairStrands(Input=body, NumberOfStrands=24, NumberOfElements=5)  # noqa: F821
sim = HairSimulation(Input=guides, Colliders=[head], Duration=duration, BodyMotion="Shake",  # noqa: F821
                     PointsPerElement=4, StateFileName=state, OverwriteStateFile=int(not resume),
                     Resume=int(resume))
if resume:
    # The frames the file has are read back, the others computed: the last time asks for all.
    sim.UpdatePipeline(sim.TimestepValues[-1])
    if rank == 0:
        print(f"frame {len(sim.TimestepValues) - 1}", flush=True)
for i, t in enumerate([] if resume else sim.TimestepValues):
    sim.UpdatePipeline(t)
    if rank == 0:
        print(f"frame {i}", flush=True)
