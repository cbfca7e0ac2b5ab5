"""pvpython: Hair Analysis on a small run, as a user builds it — Hair Strands, Hair
Simulation (with the head's collision table and a shake), Hair Analysis — checked against
the simulation's own outputs fetched frame by frame and measured here with numpy; the same
table from Hair State Reader on the run's state file; bad inputs refused with a message
that says what to do."""
import os
import tempfile

import h5py
import numpy as np
from paraview.simple import Delete, LegacyVTKReader, OutputPort
from vtkmodules.numpy_interface import dataset_adapter as dsa

import hairtest
from hairtest import Errors, check, fetch, table_columns

hairtest.load_plugin(globals())
tmp = tempfile.mkdtemp()

TRACKED = [1, 5]
GROUP = [0, 2, 3, 6]
# Tolerance of quantities recomputed here in another order of operations (numpy's sums,
# norms): distances of order 0.1 m carry a few rounding errors of 2.2e-16 relative.
ROUNDING = 1e-14


def frame_of(proxy, t):
    """The strands at time t: tips and roots by StrandId, and the point arrays."""
    proxy.UpdatePipeline(t)
    pd = fetch(proxy)
    ids = dsa.WrapDataObject(pd).CellData["StrandId"]
    lines = pd.GetLines()
    lines.InitTraversal()
    from vtkmodules.vtkCommonCore import vtkIdList
    cell = vtkIdList()
    tips, roots = {}, {}
    k = 0
    while lines.GetNextCell(cell):
        roots[int(ids[k])] = np.array(pd.GetPoint(cell.GetId(0)))
        tips[int(ids[k])] = np.array(pd.GetPoint(cell.GetId(cell.GetNumberOfIds() - 1)))
        k += 1
    arrays = {n: np.array(dsa.WrapDataObject(pd).PointData[n]) for n in ("curvature", "twist", "contact_depth")}
    return tips, roots, arrays


def span_numpy(points):
    """Largest horizontal (x-z, the vertical being y) distance between two points."""
    p = np.array(points)[:, [0, 2]]
    d = p[:, None, :] - p[None, :, :]
    return np.sqrt((d ** 2).sum(axis=2)).max()


body = LegacyVTKReader(FileNames=[os.path.join(hairtest.DATA, "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16,
                               BodyPartName="head", MovesWithHead=1)
strands = HairStrands(Input=body, NumberOfStrands=8, NumberOfElements=4, StrandLength=0.25)  # noqa: F821
state = os.path.join(tmp, "run.h5")
# Drawn at one point per element, output 0's points are the nodes at which the simulation
# measures its penetration (nodes_inside, max_depth).
sim = HairSimulation(Input=strands, Colliders=[head], Duration=0.4, FrameRate=30,  # noqa: F821
                     BodyMotion="Shake", MotionAmplitude=0.3, StateFileName=state,
                     PointsPerElement=1)
steps = list(sim.TimestepValues)

analysis = HairAnalysis(Input=sim, Energy=OutputPort(sim, 1), TrackedStrands=TRACKED,  # noqa: F821
                        Group=GROUP)
analysis.UpdatePipeline()
table = fetch(analysis)
cols = table_columns(table)
check(table.GetNumberOfRows() == len(steps) == 13, f"one row per frame ({table.GetNumberOfRows()} rows, {len(steps)} time steps)")
check(np.array_equal(cols["Time"], steps), "Time is the input's TIME_STEPS, exactly")

# Energy: every column of the simulation's table but the two contact diagnostics and the
# step statistics, exactly; the contact diagnostics are the analysis's contacts and
# max_contact_depth, the step statistics are not in a state file and not in the analysis.
energy = table_columns(fetch(sim, 1))
STEPS = ("substeps", "rejected_substeps", "first_order_share", "error_estimate")
check(all(n in energy for n in STEPS) and not any(n in cols for n in STEPS),
      "the simulation's table has the step statistics, the analysis's does not")
terms = [n for n in energy if n not in ("Time", "nodes_inside", "max_depth") + STEPS]
check(len(energy["Time"]) == len(steps) and np.array_equal(energy["Time"], steps),
      "the simulation's energy table has every frame, at the same times")
check(set(terms) >= {"kinetic", "elastic", "gravitational", "dissipated", "external_work"}
      and all(n in cols for n in terms), f"every energy term is a column ({terms})")
check(all(np.array_equal(cols[n], energy[n]) for n in terms),
      "energy columns equal the simulation's energy table exactly")
check(np.array_equal(cols["contacts"], energy["nodes_inside"])
      and np.array_equal(cols["max_contact_depth"], energy["max_depth"]),
      f"contacts and max_contact_depth equal the simulation's nodes_inside and max_depth "
      f"(contacts up to {int(cols['contacts'].max())})")
check(cols["contacts"].max() > 0, "the run has contacts, so the contact columns are tested on something")

# Frame by frame against the simulation's strands, measured here.
first_tips, _, _ = frame_of(sim, steps[0])
tips_exact = mean_exact = arrays_exact = True
span_ok = deflection_ok = displacement_ok = True
for row, t in enumerate(steps):
    tips, roots, arrays = frame_of(sim, t)
    for sid in TRACKED:
        tips_exact &= all(cols[f"tip_{sid}_{a}"][row] == tips[sid][i] for i, a in enumerate("xyz"))
    # The mean as the analysis sums it: strand after strand, then divided.
    total = np.zeros(3)
    for sid in sorted(tips):
        total = total + tips[sid]
    mean = total / len(tips)
    mean_exact &= all(cols[f"mean_tip_{a}"][row] == mean[i] for i, a in enumerate("xyz"))
    arrays_exact &= (cols["max_curvature"][row] == np.abs(arrays["curvature"]).max()
                     and cols["max_twist"][row] == np.abs(arrays["twist"]).max()
                     and cols["contacts"][row] == np.count_nonzero(arrays["contact_depth"] > 0))
    span_ok &= np.isclose(cols["span"][row], span_numpy([tips[s] for s in GROUP]), rtol=ROUNDING, atol=0)
    deflection = np.array([np.hypot(*(tips[s] - roots[s])[[0, 2]]) for s in sorted(tips)])
    deflection_ok &= (np.isclose(cols["max_deflection"][row], deflection.max(), rtol=ROUNDING, atol=0)
                      and np.isclose(cols["mean_deflection"][row], deflection.mean(), rtol=ROUNDING, atol=0))
    moved = np.array([np.linalg.norm(tips[s] - first_tips[s]) for s in sorted(tips)])
    displacement_ok &= (np.isclose(cols["max_tip_displacement"][row], moved.max(), rtol=ROUNDING, atol=1e-300)
                        and np.isclose(cols["mean_tip_displacement"][row], moved.mean(), rtol=ROUNDING, atol=1e-300))
check(tips_exact, f"tips of strands {TRACKED} equal the simulation's at every frame, exactly")
check(mean_exact, "mean tip position equals the simulation's tips summed and divided, exactly")
check(arrays_exact, "max curvature, max twist and contacts equal the fetched point arrays', exactly")
check(span_ok, f"span of strands {GROUP} equals numpy's largest x-z distance between their tips (rtol {ROUNDING})")
check(deflection_ok, "max and mean deflection equal numpy's x-z distance of tip from root")
check(displacement_ok, "max and mean tip displacement equal numpy's distance from the first frame's tips")
check(cols["max_tip_displacement"][0] == 0 and cols["max_tip_displacement"][-1] > 0.01,
      f"the tips move (by {cols['max_tip_displacement'][-1]:.4f} m at the end), none at the first frame")
check(np.ptp(cols["span"]) > 0, f"the span changes over the run ({cols['span'].min():.4f} … {cols['span'].max():.4f} m)")

# The same from the state file.
reader = HairStateReader(FileName=state, PointsPerElement=1)  # noqa: F821
from_file = HairAnalysis(Input=reader, Energy=OutputPort(reader, 1), TrackedStrands=TRACKED,  # noqa: F821
                         Group=GROUP)
from_file.UpdatePipeline()
again = table_columns(fetch(from_file))
check(list(again) == list(cols) and all(np.array_equal(again[n], cols[n]) for n in cols),
      "Hair State Reader on the state file gives the same table, column for column, exactly")

# Without the Energy input: the same table without energy columns.
bare = HairAnalysis(Input=sim, TrackedStrands=TRACKED, Group=GROUP)  # noqa: F821
bare.UpdatePipeline()
bare_cols = table_columns(fetch(bare))
check(not any(n in bare_cols for n in terms)
      and all(np.array_equal(bare_cols[n], cols[n]) for n in bare_cols),
      "without Energy: no energy columns, the measurements unchanged "
      f"{[n for n in bare_cols if not np.array_equal(bare_cols[n], cols[n])]}")
Delete(bare)

# Bad input.
no_time = HairAnalysis(Input=strands)  # noqa: F821
errors = Errors(no_time)
no_time.UpdatePipeline()
check(any("no time steps" in m and "Hair Simulation" in m for m in errors.messages),
      f"strands without time steps are refused ({errors.messages[:1]})")

# A state file without the per-point arrays (written with h5py by the documented names).
bare_file = os.path.join(tmp, "no_curvature.h5")
with h5py.File(bare_file, "w") as f:
    f.attrs["format"] = "HairDynamics states"
    f.attrs["format_version"] = 1
    f.attrs["model"] = "projective"
    f.attrs["coordinates_per_strand"] = 0
    f["time"] = np.arange(3) / 30.0
    f["strands/offsets"] = np.array([0, 4, 8], dtype=np.int64)
    f["frames/positions"] = np.random.default_rng(1).normal(size=(3, 8, 3))
    f["frames/velocities"] = np.zeros((3, 8, 3))
    for name in ("kinetic", "elastic", "gravitational", "dissipated", "external_work"):
        f[f"energy/{name}"] = np.zeros(3)
lacking = HairAnalysis(Input=HairStateReader(FileName=bare_file))  # noqa: F821
errors = Errors(lacking)
lacking.UpdatePipeline()
check(any("lacks the point array 'curvature'" in m for m in errors.messages),
      f"strands without curvature are refused, naming the array ({errors.messages[:1]})")

wrong_id = HairAnalysis(Input=sim, TrackedStrands=[99])  # noqa: F821
errors = Errors(wrong_id)
wrong_id.UpdatePipeline()
check(any("Tracked Strands: strand 99 is not in the input" in m for m in errors.messages),
      f"an unknown tracked strand is refused ({errors.messages[:1]})")
check(fetch(wrong_id).GetNumberOfRows() == 0, "and the table is empty")

# Another model's step statistics: the Discrete Elastic Rods report Newton iterations and
# steps, which the analysis leaves out as it does the Super-Helix's (it takes the columns
# the table names as energy terms, whatever model made them).
# 16 edges: the rods must follow the wavy preset's curl, 104 /m over 25 cm, at most 90° a node.
rod_strands = HairStrands(Input=body, NumberOfStrands=8, NumberOfElements=16,  # noqa: F821
                          StrandLength=0.25)
rods = HairSimulation(Input=rod_strands, Colliders=[head], Duration=0.2, FrameRate=30,  # noqa: F821
                      BodyMotion="Shake", MotionAmplitude=0.3, Model="Discrete Elastic Rods")
rods_analysis = HairAnalysis(Input=rods, Energy=OutputPort(rods, 1))  # noqa: F821
rods_analysis.UpdatePipeline()
rods_energy = table_columns(fetch(rods, 1))
rods_cols = table_columns(fetch(rods_analysis))
ROD_STEPS = ("newton_iterations", "steps")
check(all(n in rods_energy for n in ROD_STEPS) and not any(n in rods_cols for n in ROD_STEPS),
      "the rods' step statistics are in the simulation's table, not in the analysis's")
check(rods_energy["newton_iterations"][1:].min() >= 1,
      f"the rods took Newton iterations every frame ({rods_energy['newton_iterations'][1:]})")
rod_terms = [n for n in rods_energy if n not in ("Time", "nodes_inside", "max_depth") + ROD_STEPS]
check(all(np.array_equal(rods_cols[n], rods_energy[n]) for n in rod_terms),
      f"the rods' energy terms are the analysis's columns exactly ({rod_terms})")

# The energy of another run: its rows are at other times (every 1/20 s); refused at the
# first frame it lacks, in the middle of the loop over time.
other = HairSimulation(Input=strands, Duration=0.4, FrameRate=20)  # noqa: F821
mismatched = HairAnalysis(Input=sim, Energy=OutputPort(other, 1))  # noqa: F821
errors = Errors(mismatched)
mismatched.UpdatePipeline()
check(any("no row at the strands' time" in m for m in errors.messages),
      f"an energy table of another run is refused ({errors.messages[:1]})")

# An input that fails in the middle of the loop over time ends the loop (VTK's own loop
# would ask it again for ever; ctest's timeout catches a hang) with an error.
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase  # noqa: E402
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as SDDP  # noqa: E402


class FailsAtThirdStep(VTKPythonAlgorithmBase):
    def __init__(self, good):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1, outputType="vtkPolyData")
        self.good = good

    def RequestInformation(self, request, inInfo, outInfo):
        info = outInfo.GetInformationObject(0)
        info.Set(SDDP.TIME_STEPS(), [0.0, 1.0, 2.0, 3.0], 4)
        info.Set(SDDP.TIME_RANGE(), [0.0, 3.0], 2)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        if outInfo.GetInformationObject(0).Get(SDDP.UPDATE_TIME_STEP()) >= 2:
            return 0
        outInfo.GetInformationObject(0).Get(dsa.vtkDataObject.DATA_OBJECT()).ShallowCopy(self.good)
        return 1


sim.UpdatePipeline(steps[0])
failing = FailsAtThirdStep(fetch(sim))
broken = HairAnalysis(Input=sim)  # noqa: F821
errors = Errors(broken)
broken.GetClientSideObject().SetInputConnection(0, failing.GetOutputPort())
broken.GetClientSideObject().Update()
check(any("the input failed at t = 2 s" in m for m in errors.messages),
      f"an input failing at the third time step ends the loop with an error ({errors.messages[-1:]})")

hairtest.finish()
