"""pvbatch under MPI (2 ranks, --symmetric): every rank asks for the whole body and builds
the same, whole collision table, since every rank's strands need all of it.

Run: mpirun -np 2 pvbatch --symmetric Testing/Python/mpi_collision_map.py <HairDynamics.so>
"""
import os
import sys

from paraview import servermanager
from paraview.simple import LegacyVTKReader, LoadPlugin, UpdatePipeline

LoadPlugin(sys.argv[1], remote=False, ns=globals())
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
body = LegacyVTKReader(FileNames=[os.path.join(ROOT, "Data", "body.vtk")])
table = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                                Origin=[0, 1.555, 0.055], MaximumRadius=0.16)
UpdatePipeline(proxy=table)
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()
image = table.GetClientSideObject().GetOutputDataObject(0)
radius = image.GetPointData().GetArray("Radius")
checksum = sum(radius.GetValue(i) * (i + 1) for i in range(radius.GetNumberOfTuples()))

from mpi4py import MPI  # noqa: E402  (ParaView's Python has it when built with MPI)

sums = MPI.COMM_WORLD.allgather(checksum)
ok = ranks == 2 and image.GetDimensions() == (40, 40, 1) and max(sums) - min(sums) == 0
print(f"rank {rank} of {ranks}: table {image.GetDimensions()}, checksum {checksum:.9f}, "
      f"{'same on every rank' if ok else 'DIFFERS'}")
if not ok:
    sys.exit(1)  # mpirun reports the rank that left without finalising: the test fails
