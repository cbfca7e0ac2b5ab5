"""pvpython: the pipeline as a user builds it — body, tables, strands, simulation, state
file, reader — with time handled the ParaView way; a run killed with SIGKILL leaves a
readable file."""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np
from paraview.simple import Calculator, Delete, LegacyVTKReader, UpdatePipeline

import hairtest
from hairtest import Errors, check, fetch, table_columns

hairtest.load_plugin(globals())
tmp = tempfile.mkdtemp()


def points(polydata):
    return np.array([polydata.GetPoint(i) for i in range(polydata.GetNumberOfPoints())])


body = LegacyVTKReader(FileNames=[os.path.join(hairtest.DATA, "body.vtk")])
head = CylindricalCollisionMap(Input=body, Projection="Spherical", AutomaticFrame=0,  # noqa: F821
                               Origin=[0, 1.555, 0.055], MaximumRadius=0.16,
                               BodyPartName="head", MovesWithHead=1)
strands = HairStrands(Input=body, NumberOfStrands=12, NumberOfElements=5, StrandLength=0.25)  # noqa: F821

for model in ("Super-Helix", "Projective"):
    state = os.path.join(tmp, f"{model}.h5")
    sim = HairSimulation(Input=strands, Colliders=[head], Model=model, Duration=0.5,  # noqa: F821
                         FrameRate=30, BodyMotion="Shake", MotionAmplitude=0.3,
                         StateFileName=state)
    steps = list(sim.TimestepValues)
    check(len(steps) == 16 and abs(steps[-1] - 0.5) < 1e-12, f"{model}: 16 time steps from 0 to 0.5 s")
    # proxy.UpdatePipeline(t), not simple.UpdatePipeline(time=t), which drops t = 0.
    sim.UpdatePipeline(steps[6])
    early = points(fetch(sim))
    sim.UpdatePipeline(steps[15])
    late = points(fetch(sim))
    sim.UpdatePipeline(steps[6])
    again = points(fetch(sim))
    check(np.array_equal(early, again), f"{model}: asking again for an earlier time returns exactly what was computed")
    check(not np.array_equal(early, late), f"{model}: the strands move")
    pd = fetch(sim).GetPointData()
    check(all(pd.GetArray(a) is not None for a in ("Velocity", "curvature", "twist", "contact_depth")),
          f"{model}: velocity, curvature, twist and contact_depth point arrays")
    # Fetched as a view would ask for it: port 1 must follow time too (it reports
    # TIME_STEPS), or a line chart of it stays at its first frame.
    energy = fetch(sim, 1)
    check(energy.GetNumberOfRows() == 16, f"{model}: energy table has a row per computed frame")

    # The reader gives back, frame by frame, exactly what the simulation produced.
    reader = HairStateReader(FileName=state)  # noqa: F821
    stored = list(reader.TimestepValues)
    check(len(stored) == 16 and max(abs(a - b) for a, b in zip(stored, steps)) < 1e-9,
          f"{model}: the state file holds every frame (times within 1e-9 s of the frames')")
    same = True
    for t in (steps[0], steps[6], steps[15]):
        sim.UpdatePipeline(t)
        reader.UpdatePipeline(t)
        same = same and np.array_equal(points(fetch(sim)), points(fetch(reader)))
    check(same, f"{model}: the reader returns exactly the simulated frames")
    check(fetch(reader).GetPointData().GetArray("curvature") is not None,
          f"{model}: the reader gives the per-point arrays back")
    with h5py.File(state, "r", swmr=True) as f:
        ok = (f.attrs["format"] == "HairDynamics states" and f["frames/positions"].shape[0] == 16
              and f["energy/kinetic"].shape[0] >= 16 and f["strands/offsets"].shape[0] == 13)
    check(ok, f"{model}: h5py reads positions and energies by the documented names")

# The projective model's friction: on with a static coefficient, recorded in the state file,
# and what it dissipates in the energy table.
state = os.path.join(tmp, "projective-friction.h5")
sticky = HairSimulation(Input=strands, Colliders=[head], Model="Projective", Duration=0.5,  # noqa: F821
                        FrameRate=30, BodyMotion="Shake", MotionAmplitude=0.3,
                        StaticFrictionCoefficient=0.4, StateFileName=state)
sticky.UpdatePipeline(0.5)
columns = table_columns(fetch(sticky, 1))
check("body_friction_dissipated" in columns and columns["body_friction_dissipated"][-1] >= 0,
      f"projective with friction: body_friction_dissipated in the energy table ({sorted(columns)})")
with h5py.File(state, "r", swmr=True) as f:
    recorded = (f.attrs["static_friction_coefficient"], f.attrs["friction_coefficient"])
check(abs(recorded[0] - 0.4) < 1e-12 and abs(recorded[1] - 0.3) < 1e-12,
      f"projective with friction: its coefficients in the state file ({recorded})")

# Bad input: a surface instead of strands; strands without Hair Strands' arrays.
bad = HairSimulation(Input=strands)  # noqa: F821
errors = Errors(bad)
bad.Input = body
bad.UpdatePipeline(0.0)
check(any("no polylines" in m for m in errors.messages), f"a surface instead of strands is refused ({errors.messages[:1]})")

# A run whose frames cannot fit in memory (all frames are kept) is refused before it starts,
# with the figures: an hour at 1000 frames per second of these strands needs ~100 GiB.
too_long = HairSimulation(Input=strands, Duration=3600, FrameRate=1000)  # noqa: F821
errors = Errors(too_long)
started = time.time()
too_long.UpdatePipeline(0.0)
# A lower bound of what the frames need: 9 doubles per point and frame, and the frames have
# at least the input strands' points (the Super-Helix displays 4 per element).
need = 3600001 * 72 * fetch(strands).GetNumberOfPoints()
budget = 0.5 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
if need > budget:
    check(any("memory" in m and "frames" in m and "Duration" in m for m in errors.messages)
          and time.time() - started < 30,
          f"a run that cannot fit in memory ({need / 2**30:.0f} GiB) is refused at once "
          f"({errors.messages[:1]})")
else:
    print(f"skip: this machine's memory would hold {need / 2**30:.0f} GiB of frames")

# Streaming: with a state file, a run longer than Memory Budget keeps only its newest frames
# in memory and reads earlier ones back from the file; every frame must be the one the
# in-memory run gives, in any order of requests. Without a file the same run is refused,
# and the message says a state file would let it run.
motion = dict(Input=strands, Colliders=[head], Duration=0.5, FrameRate=30, BodyMotion="Shake",
              MotionAmplitude=0.3)
reference = HairSimulation(**motion)  # noqa: F821
reference.UpdatePipeline(0.0)
# About three frames, so the window holds two. A frame keeps states: per strand of N elements,
# its N + 1 nodes (position, velocity, contact depth: 7 doubles), q and q-dot (6N) and the
# root's pose and rates (18). Output 0 is drawn at 16 points per element.
drawn = fetch(reference)
S = drawn.GetNumberOfCells()
N = (drawn.GetNumberOfPoints() // S - 1) // 16
budget_mib = 3 * 8 * S * (7 * (N + 1) + 6 * N + 18) / 2**20
streamed = HairSimulation(StateFileName=os.path.join(tmp, "streamed.h5"),  # noqa: F821
                          MemoryBudget=budget_mib, **motion)
errors = Errors(streamed)
steps = list(reference.TimestepValues)
same = True
for i in (15, 2, 9, 0, 15, 14):
    reference.UpdatePipeline(steps[i])
    streamed.UpdatePipeline(steps[i])
    same = same and np.array_equal(points(fetch(reference)), points(fetch(streamed)))
check(same and not errors.messages,
      f"a run streamed to its state file with a {budget_mib * 1024:.0f} KiB budget gives every "
      f"frame exactly, early times read back from the file ({errors.messages[:1]})")
check(fetch(streamed, 1).GetNumberOfRows() == 16,
      "the streamed run's energy table still has a row per frame")
no_file = HairSimulation(MemoryBudget=budget_mib, **motion)  # noqa: F821
errors = Errors(no_file)
no_file.UpdatePipeline(0.0)
check(any("State File Name" in m and "Memory Budget" in m for m in errors.messages),
      f"without a state file the same run is refused and told about State File Name "
      f"({errors.messages[:1]})")

# Contact parameters: a bad one is refused with its name; a good run with contacts keeps the
# Super-Helix strands out of the head table (contact_depth, the depth into the table).
bad_contact = HairSimulation(Input=strands, Colliders=[head], Duration=0.1,  # noqa: F821
                             FrictionCoefficient=-0.5)
errors = Errors(bad_contact)
bad_contact.UpdatePipeline(0.0)
check(any("friction coefficient" in m for m in errors.messages),
      f"a negative friction coefficient is refused by name ({errors.messages[:1]})")
bad_static = HairSimulation(Input=strands, Colliders=[head], Duration=0.1,  # noqa: F821
                            FrictionCoefficient=0.3, StaticFrictionCoefficient=0.2)
errors = Errors(bad_static)
bad_static.UpdatePipeline(0.0)
check(any("static friction coefficient" in m for m in errors.messages),
      f"static friction below the kinetic is refused by name ({errors.messages[:1]})")
for on in (1, 0):
    run = HairSimulation(Input=strands, Colliders=[head], Duration=1.0, Contacts=on,  # noqa: F821
                         ContactStiffness=10, FrictionCoefficient=0.3, FrictionAnisotropy=0.2,
                         StaticFrictionCoefficient=0.4 if on else 0, ContactThickness=0.001)
    run.UpdatePipeline(1.0)
    depth = fetch(run).GetPointData().GetArray("contact_depth").GetRange()[1]
    print(f"contacts {on}: deepest point inside the head table at 1 s: {depth * 1e3:.2f} mm")
    if on:
        # Hair Strands' roots lie on the mesh; the table interpolates it with an error of
        # 1.2 mm (95th percentile, docs/study-table-error.md), 10 mm at the worst silhouettes.
        check(depth < 2e-3, f"contacts on: strands stay within 2 mm of the head table ({depth:.2e} m)")
    else:
        check(depth > 5e-3, f"contacts off: strands fall into the head ({depth:.2e} m)")

# Hair–hair contacts: a bad thickness is refused by name; a run with them on goes through
# and records them in the state file's attributes.
bad_hh = HairSimulation(Input=strands, Duration=0.1, HairHairContacts=1,  # noqa: F821
                        HairContactThickness=-0.001)
errors = Errors(bad_hh)
bad_hh.UpdatePipeline(0.0)
check(any("hair–hair" in m and "thickness" in m for m in errors.messages),
      f"a negative hair contact thickness is refused by name ({errors.messages[:1]})")
hh_state = os.path.join(tmp, "hair_hair.h5")
hh = HairSimulation(Input=strands, Colliders=[head], Duration=0.5, HairHairContacts=1,  # noqa: F821
                    HairContactThickness=0.003, StateFileName=hh_state)
errors = Errors(hh)
hh.UpdatePipeline(0.5)
check(not errors.messages, f"a run with hair–hair contacts goes through ({errors.messages[:1]})")
with h5py.File(hh_state, "r", swmr=True) as f:
    attrs = dict(f.attrs)
check(attrs.get("hair_hair_contacts") == 1 and abs(attrs.get("hair_hair_thickness", 0) - 0.003) < 1e-15
      and attrs.get("hair_hair_per_length") == 0,
      f"the state file records the hair–hair parameters ({ {k: v for k, v in attrs.items() if 'hair_hair' in k} })")
# The per-length penalty from the GUI's property, recorded too.
hh_state = os.path.join(tmp, "hair_hair_per_length.h5")
hh = HairSimulation(Input=strands, Colliders=[head], Duration=0.5, HairHairContacts=1,  # noqa: F821
                    HairContactThickness=0.003, HairContactPerLength=1, StateFileName=hh_state)
errors = Errors(hh)
hh.UpdatePipeline(0.5)
with h5py.File(hh_state, "r", swmr=True) as f:
    attrs = dict(f.attrs)
check(not errors.messages and attrs.get("hair_hair_per_length") == 1
      and attrs.get("hair_hair_reference_length") == 0.01,
      f"a run with the per-length hair–hair penalty goes through and is recorded ({errors.messages[:1]})")

# The default interaction: the grid (volume and friction), recorded with its parameters
# and the cell it used; a bad grid parameter is refused by name.
g_state = os.path.join(tmp, "hair_grid.h5")
g = HairSimulation(Input=strands, Colliders=[head], Duration=0.3, StateFileName=g_state)  # noqa: F821
errors = Errors(g)
g.UpdatePipeline(0.3)
with h5py.File(g_state, "r", swmr=True) as f:
    attrs = dict(f.attrs)
check(not errors.messages and attrs.get("hair_hair_contacts") == 2
      and attrs.get("hair_volume_fraction") == 0.05 and attrs.get("hair_volume") == 1
      and attrs.get("hair_grid_friction") == 10 and attrs.get("hair_grid_cell_size", 0) >= 0.008,
      f"the grid is on by default and recorded ({ {k: v for k, v in attrs.items() if 'hair' in k} })")
bad_g = HairSimulation(Input=strands, Duration=0.1, HairVolume=2)  # noqa: F821
errors = Errors(bad_g)
bad_g.UpdatePipeline(0.0)
check(any("hair grid" in m and "volume" in m for m in errors.messages),
      f"a hair volume above 1 is refused by name ({errors.messages[:1]})")

# The quadrature tolerance (advanced): out of range is refused by name; a loose one goes
# through and is recorded; the default is Core's.
bad_q = HairSimulation(Input=strands, Duration=0.1, QuadratureTolerance=0.5)  # noqa: F821
errors = Errors(bad_q)
bad_q.UpdatePipeline(0.0)
check(any("quadrature tolerance" in m for m in errors.messages),
      f"a quadrature tolerance of 0.5 is refused by name ({errors.messages[:1]})")
q_state = os.path.join(tmp, "quadrature.h5")
loose = HairSimulation(Input=strands, Colliders=[head], Duration=0.2,  # noqa: F821
                       QuadratureTolerance=1e-2, StateFileName=q_state)
errors = Errors(loose)
loose.UpdatePipeline(0.2)
with h5py.File(q_state, "r", swmr=True) as f:
    attrs = dict(f.attrs)
check(not errors.messages and attrs.get("quadrature_tolerance") == 1e-2,
      f"a run with quadrature tolerance 1e-2 goes through and is recorded ({errors.messages[:1]})")
default_q = HairSimulation(Input=strands).GetProperty("QuadratureTolerance")[0]  # noqa: F821
check(default_q == 5.3362954729907547e-06,
      f"the property's default is Core's ({default_q!r})")

# Integrator and Tolerance: out of range is refused by name; the second-order step with a
# tolerance goes through, is recorded, and the energy table has, per frame, the sub-steps it
# took and their error estimate, which stays within its share of the tolerance (m per second
# of simulated time, so 1/30 of it per frame); fixed steps take one step per frame of the
# first-order step.
bad_t = HairSimulation(Input=strands, Duration=0.1, Tolerance=-1)  # noqa: F821
errors = Errors(bad_t)
bad_t.UpdatePipeline(0.0)
check(any("Tolerance" in m for m in errors.messages),
      f"a negative tolerance is refused by name ({errors.messages[:1]})")
i_state = os.path.join(tmp, "integrator.h5")
accurate = HairSimulation(Input=strands, Duration=0.2,  # noqa: F821
                          Integrator="Second order (midpoint)", Tolerance=2e-2,
                          HairHairContacts=0,  # each strand's own sub-steps
                          BodyMotion="Shake", MotionAmplitude=0.3, StateFileName=i_state)
errors = Errors(accurate)
accurate.UpdatePipeline(0.2)
with h5py.File(i_state, "r", swmr=True) as f:
    attrs = dict(f.attrs)
check(not errors.messages and attrs.get("integrator") == 1 and attrs.get("tolerance") == 2e-2,
      f"a second-order run with a tolerance goes through and is recorded ({errors.messages[:1]})")
steps_table = table_columns(fetch(accurate, 1))
check(steps_table["substeps"][0] == 0 and all(steps_table["substeps"][1:] >= 1)
      and steps_table["substeps"].max() > 1
      and all(steps_table["error_estimate"][1:] <= 2e-2 / 30 * (1 + 1e-9)),
      f"the energy table has the sub-steps per frame ({steps_table['substeps']}) and their "
      f"error estimate within 2e-2/30 m ({steps_table['error_estimate'].max():.2e} m)")
# BDF2 under the hair grid while the head starts shaking: recorded as integrator 2; the
# first step of each strand is semi-implicit (no history), and while the grown strands fall
# the energy guard declines some (measured: 6, 4, 3, 0, 1 of the 12 in frames 2–6), so most
# steps are its own.
b_state = os.path.join(tmp, "bdf2.h5")
bdf = HairSimulation(Input=strands, Duration=0.2,  # noqa: F821
                     Integrator="Second order (BDF2)", BodyMotion="Shake", MotionAmplitude=0.3,
                     StateFileName=b_state)
errors = Errors(bdf)
bdf.UpdatePipeline(0.2)
with h5py.File(b_state, "r", swmr=True) as f:
    attrs = dict(f.attrs)
bdf_table = table_columns(fetch(bdf, 1))
check(not errors.messages and attrs.get("integrator") == 2
      and bdf_table["first_order_share"][1] == 1
      and bdf_table["first_order_share"][2:].mean() < 0.5,
      f"a BDF2 run goes through, is recorded and keeps its own step "
      f"({errors.messages[:1]}, first-order share {bdf_table['first_order_share']})")
fixed = table_columns(fetch(loose, 1))
check(all(fixed["substeps"][1:] == 1) and all(fixed["first_order_share"][1:] == 1)
      and all(fixed["error_estimate"][1:] > 0),
      "fixed semi-implicit steps: one step per frame, first order, with an error estimate")

# A run killed with SIGKILL mid-way leaves a readable file.
killed = os.path.join(tmp, "killed.h5")
script = os.path.join(tmp, "long_run.py")
with open(script, "w") as f:
    f.write(f"""
from paraview.simple import *
LoadPlugin({sys.argv[1]!r}, remote=False, ns=globals())
body = LegacyVTKReader(FileNames=[{os.path.join(hairtest.DATA, 'body.vtk')!r}])
strands = HairStrands(Input=body, NumberOfStrands=40, NumberOfElements=8)
sim = HairSimulation(Input=strands, Duration=600, StateFileName={killed!r}, BodyMotion="Shake")
UpdatePipeline(proxy=sim, time=600)
""")
run = subprocess.Popen([shutil.which("pvpython"), script], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
deadline = time.time() + 60
frames = 0
while time.time() < deadline and frames < 10:
    time.sleep(0.5)
    try:
        with h5py.File(killed, "r", swmr=True) as f:
            frames = f["time"].shape[0]
    except Exception:
        pass
run.send_signal(signal.SIGKILL)
run.wait()
reader = HairStateReader(FileName=killed)  # noqa: F821
n = len(reader.TimestepValues)
UpdatePipeline(proxy=reader, time=reader.TimestepValues[-1])
check(n >= 10 and fetch(reader).GetNumberOfPoints() > 0,
      f"a run killed with SIGKILL reads back up to its last whole frame ({n} frames)")

# Run properties outside their domains are refused with the property, its value and its
# range, before any work (issue 24: Duration or Frame Rate NaN aborted ParaView with
# std::length_error, Duration 1e6 at 1e4 frames/s with bad_alloc; Time Step 0 or negative was
# clamped to 1e-7 s, 333 334 steps per frame).
for props, words in (({"Duration": float("nan")}, "Duration is nan"),
                     ({"FrameRate": float("nan")}, "Frame Rate is nan"),
                     ({"Duration": 1e6, "FrameRate": 1e4}, "Duration is 1e+06"),
                     ({"TimeStep": 0.0}, "Time Step is 0"),
                     ({"TimeStep": -1.0}, "Time Step is -1"),
                     ({"NumberOfThreads": 0}, "Number Of Threads is 0")):
    bad = HairSimulation(Input=strands, Colliders=[head])  # noqa: F821
    errors = Errors(bad)
    for name, value in props.items():
        setattr(bad, name, value)
    start = time.time()
    UpdatePipeline(proxy=bad)
    check(any(words in m for m in errors.messages) and time.time() - start < 10,
          f"{props} is refused at once ({errors.messages[:1]})")

# Cell arrays of absurd size are refused, not allocated (issue 24: NumberOfElements 10000
# and Length 1e300 aborted with bad_alloc at 14-15 GB).
for name, value, words in (("NumberOfElements", "10000", "10000 elements"),
                           ("Length", "1e300", "length 1e+300")):
    crafted = Calculator(Input=strands, AttributeType="Cell Data", ResultArrayName=name,  # noqa: F821
                         Function=value)
    bad = HairSimulation(Input=crafted, Colliders=[head])  # noqa: F821
    errors = Errors(bad)
    start = time.time()
    UpdatePipeline(proxy=bad)
    check(any(words in m for m in errors.messages) and time.time() - start < 10,
          f"a {name} cell array of {value} is refused at once ({errors.messages[:1]})")

# A State File Name that names something else is never written over; an existing state
# file only with Overwrite State File (issue 24: both were overwritten without a word).
notes = os.path.join(tmp, "notes.h5")
with open(notes, "w") as f:
    f.write("my notes\n")
for overwrite in (0, 1):
    bad = HairSimulation(Input=strands, Duration=0.1, StateFileName=notes,  # noqa: F821
                         OverwriteStateFile=overwrite)
    errors = Errors(bad)
    bad.UpdatePipeline(0.1)
    check(any("not written over" in m for m in errors.messages) and open(notes).read() == "my notes\n",
          f"a user's file is kept (Overwrite {overwrite}: {errors.messages[:1]})")
existing = os.path.join(tmp, "existing.h5")
first = HairSimulation(Input=strands, Duration=0.2, StateFileName=existing)  # noqa: F821
first.UpdatePipeline(0.2)
Delete(first)  # closes its writer
del first
again = HairSimulation(Input=strands, Duration=0.1, StateFileName=existing)  # noqa: F821
errors = Errors(again)
again.UpdatePipeline(0.1)
check(any("it is kept" in m for m in errors.messages), f"an existing state file is kept ({errors.messages[:1]})")
again.OverwriteStateFile = 1
errors = Errors(again)
again.UpdatePipeline(0.1)
with h5py.File(existing, "r", swmr=True) as f:
    frames = f["time"].shape[0]
check(not errors.messages and frames == 4,
      f"with Overwrite State File it is replaced ({frames} frames; {errors.messages[:1]})")
# While another run writes the file, it is refused with a message that says so.
busy = HairSimulation(Input=strands, Duration=0.1, StateFileName=existing, OverwriteStateFile=1)  # noqa: F821
errors = Errors(busy)
busy.UpdatePipeline(0.1)
check(any("other run is writing" in m for m in errors.messages),
      f"a file another run is writing is refused ({errors.messages[:1]})")

# Resume: a run stopped part-way (its filter deleted, the file closed) goes on from its state
# file with Resume on; the file then equals that of a run that never stopped, bit for bit. A
# property changed since is refused by name and the file kept.
run = dict(Input=strands, Colliders=[head], Duration=0.3, FrameRate=30, BodyMotion="Shake",
           MotionAmplitude=0.3, StaticFrictionCoefficient=0.4)
whole_file, resumed_file = os.path.join(tmp, "whole.h5"), os.path.join(tmp, "resumed.h5")
whole = HairSimulation(StateFileName=whole_file, **run)  # noqa: F821
whole.UpdatePipeline(0.3)
Delete(whole)
del whole
part = HairSimulation(StateFileName=resumed_file, **run)  # noqa: F821
part.UpdatePipeline(0.1)
Delete(part)
del part
changed = HairSimulation(StateFileName=resumed_file, Resume=1, ContactStiffness=20, **run)  # noqa: F821
errors = Errors(changed)
changed.UpdatePipeline(0.3)
check(any("'contact_stiffness' is 10 in the file and 20 in this run" in m for m in errors.messages),
      f"resumed with a property changed, the run is refused by name ({errors.messages[:1]})")
Delete(changed)
del changed
with h5py.File(resumed_file, "r", swmr=True) as f:
    kept = f["time"].shape[0]
check(kept == 4, f"the refused resume left the file's {kept} frames as they were")
resumed = HairSimulation(StateFileName=resumed_file, Resume=1, **run)  # noqa: F821
errors = Errors(resumed)
resumed.UpdatePipeline(0.3)
rows = fetch(resumed, 1).GetNumberOfRows()
Delete(resumed)
del resumed
with h5py.File(whole_file, "r", swmr=True) as a, h5py.File(resumed_file, "r", swmr=True) as b:
    T = a["time"].shape[0]
    equal = b["time"].shape[0] == T and np.array_equal(a["time"][:], b["time"][:T])
    for group in ("frames", "energy"):
        for name in a[group]:
            equal = equal and np.array_equal(a[group][name][:T], b[group][name][:T])
check(equal and T == 10 and rows == 10 and not errors.messages,
      f"resumed after 4 of {T} frames, the file equals the unbroken run's bit for bit, and the "
      f"energy table has a row per frame ({rows}; {errors.messages[:1]})")

hairtest.finish()
