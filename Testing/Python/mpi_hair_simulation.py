"""pvbatch under MPI (--symmetric, any number of ranks): Hair Simulation shares the strands
among the ranks, each rank's output is its piece (every strand on exactly one rank, by its
StrandId), the energy table is rank 0's, and the one state file is written by every rank.
Downstream, on the pieces: Hair Analysis gives rank 0 the whole run's table (the others an
empty one, without hanging in its loop over time), Hair State Reader reads the file back
with each rank reading its share, equal to what the simulation output, and Hair
Interpolation renders hair on each piece.

The state file and Hair Analysis's table (<state>.analysis.csv) are left for
compare_mpi_runs.py, which checks that runs on 1, 2 and 4 ranks agree.

Run: mpirun -np N pvbatch --symmetric Testing/Python/mpi_hair_simulation.py <HairDynamics.so> <state.h5>
"""
import os
import sys

import numpy as np
from mpi4py import MPI  # ParaView's Python has it when built with MPI
from paraview import servermanager
from paraview.simple import LegacyVTKReader, LoadPlugin, OutputPort
from vtkmodules.util.numpy_support import vtk_to_numpy

LoadPlugin(sys.argv[1], remote=False, ns=globals())
state = sys.argv[2]
comm = MPI.COMM_WORLD
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STRANDS, DURATION, FRAMES = 24, 0.3, 10  # frames 0 … 9 at 30 per second
failures = []


def check(condition, what):
    """Every rank checks; rank 0 prints what every rank found."""
    flags = comm.allgather(bool(condition))
    if rank == 0:
        print(("ok   " if all(flags) else "FAIL ") + what +
              ("" if all(flags) else f" (per rank {flags})"))
    if not all(flags):
        failures.append(what)


def strands_of(data, ghosts=False):
    """{StrandId: (points, velocities)} of a polydata piece: its own strands, or (ghosts) the
    ghost strands (vtkGhostType DUPLICATECELL: another rank's, sent for what needs the
    neighbouring strands; ParaView asks for one ghost level in parallel)."""
    ids = data.GetCellData().GetArray("StrandId")
    marks = data.GetCellData().GetArray("vtkGhostType")
    points = vtk_to_numpy(data.GetPoints().GetData()) if data.GetNumberOfPoints() else None
    velocity = data.GetPointData().GetArray("Velocity")
    velocity = vtk_to_numpy(velocity) if velocity is not None and data.GetNumberOfPoints() else None
    out = {}
    lines = data.GetLines()
    lines.InitTraversal()
    from vtkmodules.vtkCommonCore import vtkIdList
    cell = vtkIdList()
    k = 0
    while lines.GetNextCell(cell):
        ghost = marks is not None and int(marks.GetValue(k)) & 1
        if bool(ghost) == ghosts:
            idx = [cell.GetId(i) for i in range(cell.GetNumberOfIds())]
            out[int(ids.GetValue(k))] = (points[idx].copy(), velocity[idx].copy())
        k += 1
    return out


def whole(piece):
    """Every rank's pieces, merged: {StrandId: arrays}; a StrandId twice is a failure."""
    merged, twice = {}, []
    for part in comm.allgather(piece):
        for k, v in part.items():
            if k in merged:
                twice.append(k)
            merged[k] = v
    return merged, twice


body = LegacyVTKReader(FileNames=[os.path.join(ROOT, "Data", "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16, BodyPartName="head",
                               MovesWithHead=1)
guides = HairStrands(Input=body, NumberOfStrands=STRANDS, NumberOfElements=5,  # noqa: F821
                     HairType="Curly (Caucasian 2)")
sim = HairSimulation(Input=guides, Colliders=[head], Duration=DURATION, BodyMotion="Shake",  # noqa: F821
                     PointsPerElement=4, StateFileName=state, OverwriteStateFile=1)
sim.UpdatePipeline(DURATION)
piece = sim.GetClientSideObject().GetOutputDataObject(0)
energy = sim.GetClientSideObject().GetOutputDataObject(1)
mine = strands_of(piece)
simulated, twice = whole(mine)
counts = comm.allgather(len(mine))
check(sorted(simulated) == list(range(STRANDS)) and not twice,
      f"every strand on exactly one rank (strands per rank {counts})")
check(ranks == 1 or len(mine) > 0, "every rank has strands (24 strands, at most 4 ranks)")
ghosts = strands_of(piece, ghosts=True)
check(all(k in simulated and k not in mine and np.array_equal(v[0], simulated[k][0])
          for k, v in ghosts.items()),
      f"ghost strands are other ranks' strands as they have them "
      f"(ghosts per rank {comm.allgather(len(ghosts))})")
rows = comm.allgather(energy.GetNumberOfRows())
check(rows == [FRAMES] + [0] * (ranks - 1), f"the energy table is rank 0's (rows per rank {rows})")

# Hair Analysis on the pieces: the whole run's table on rank 0.
analysis = HairAnalysis(Input=sim, Energy=OutputPort(sim, 1), TrackedStrands=[0, STRANDS - 1],  # noqa: F821
                        Group=list(range(0, STRANDS, 3)))
analysis.UpdatePipeline(DURATION)
table = analysis.GetClientSideObject().GetOutputDataObject(0)
rows = comm.allgather(table.GetNumberOfRows())
check(rows == [FRAMES] + [0] * (ranks - 1), f"Hair Analysis: rank 0's table (rows per rank {rows})")
if rank == 0:
    names = [table.GetColumnName(c) for c in range(table.GetNumberOfColumns())]
    values = np.array([[table.GetValue(r, c).ToDouble() for c in range(len(names))]
                       for r in range(table.GetNumberOfRows())])
    np.savetxt(state + ".analysis.csv", values, delimiter=",", header=",".join(names), comments="")

# Hair State Reader of the file, on pieces: each rank reads its share, and the strands are
# the ones simulated, point for point (drawn again at the stored 4 points per element).
reader = HairStateReader(FileName=state, PointsPerElement=4)  # noqa: F821
reader.UpdatePipeline(DURATION)
read_piece = reader.GetClientSideObject().GetOutputDataObject(0)
read_mine = strands_of(read_piece)
read, twice = whole(read_mine)
check(sorted(read) == list(range(STRANDS)) and not twice,
      f"Hair State Reader: every strand read by exactly one rank "
      f"(per rank {comm.allgather(len(read_mine))})")
difference = max((np.abs(read[k][0] - simulated[k][0]).max() for k in read if k in simulated),
                 default=np.inf)
check(difference == 0, f"Hair State Reader: the file's strands are the simulated ones (largest "
      f"difference {difference} m)")
read_rows = comm.allgather(reader.GetClientSideObject().GetOutputDataObject(1).GetNumberOfRows())
check(read_rows == [FRAMES] + [0] * (ranks - 1),
      f"Hair State Reader: the energy table is piece 0's (rows per rank {read_rows})")

# Hair Interpolation on each piece: rendered hair from the rank's guides.
hair = HairInterpolation(Input=sim, Scalp=body, NumberOfStrands=400)  # noqa: F821
hair.UpdatePipeline(DURATION)
rendered = hair.GetClientSideObject().GetOutputDataObject(0).GetNumberOfLines()
counts = comm.allgather(rendered)
check(sum(counts) == 400 and (ranks == 1 or all(c > 0 for c in counts)),
      f"Hair Interpolation renders hair on every piece, 400 in all (strands per rank {counts})")

if rank == 0:
    print(f"{ranks} ranks: {len(failures)} failed" if failures else f"{ranks} ranks: all checks passed")
if failures:
    sys.exit(1)  # mpirun reports the ranks that left without finalizing: the test fails
# (no sys.exit on success: pvbatch finalizes MPI when the script ends)
