"""The three strand models on the same scene, side by side: the demo's guides on the bundled
body, its head shake, wind and body contacts, run by hair_study demo (Tools/studies/demo.cxx)
once per registered model. Writes per model its state file, and

  compare_models.csv   model, elements, strands, frames, wall and CPU seconds, the cost per
                       strand and frame of 1/30 s, the model's own step, the last frame's
                       energy terms, nodes inside the body and deepest
  compare_models.png   the strands at three instants, one row per model (front view)
  compare_energy.png   kinetic, elastic and gravitational energy and the residual over time
  compare_models.txt   the table as text

usage: /usr/bin/python3 Scripts/compare_models.py <build>/bin/hair_study <output dir> [--quick]
       (--quick: 12 guides for 1 s instead of 60 guides for 3 s)
docs/study-models.md says what it shows.
"""
import os
import resource
import subprocess
import sys
import time

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import studytool  # noqa: E402

# Every model at 20 elements (Super-Helix elements, projective segments, rod edges): 21
# stored points a strand each, drawn as stored, and a cost per strand at equal resolution.
# (The demo runs the Super-Helix at 10 and the projective strands at 40.)
MODELS = [("super-helix", 20, 1.0 / 30), ("projective", 20, 1e-3),
          ("discrete-elastic-rods", 20, 1.0 / 30)]


def run(tool, outdir, model, elements, strands, duration):
    out = os.path.join(outdir, f"{model}.h5")
    cmd = [tool, "demo", f"model={model}", f"strands={strands}", f"n={elements}",
           f"duration={duration}", "threads=2", f"out={out}"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit status {r.returncode}):\n{r.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out, wall, cpu


def strands_at(f, frame):
    offsets = f["strands/offsets"][:]
    points = f["frames/positions"][frame]
    return [points[offsets[k]:offsets[k + 1]] for k in range(len(offsets) - 1)]


def main():
    tool, outdir, quick = studytool.parse_args("compare_models.py")
    strands, duration = (12, 1.0) if quick else (60, 3.0)
    rows, files = [], {}
    for model, elements, step in MODELS:
        path, wall, cpu = run(tool, outdir, model, elements, strands, duration)
        files[model] = path
        with h5py.File(path, "r") as f:
            frames = f["time"].shape[0]
            energy = {k: f["energy"][k][-1] for k in f["energy"].keys()}
            depth = f["frames/contact_depth"][frames - 1]
        steps = strands * (frames - 1)  # strand-frames of 1/30 s computed
        rows.append({
            "model": model, "elements": elements, "strands": strands, "frames": frames,
            "wall_s": wall, "cpu_s": cpu, "ms_per_strand_frame": 1e3 * wall / steps,
            "own_step_s": step, "kinetic": energy["kinetic"], "elastic": energy["elastic"],
            "gravitational": energy["gravitational"], "dissipated": energy["dissipated"],
            "external_work": energy["external_work"], "residual": energy["residual"],
            "nodes_inside": int(np.sum(depth > 0)), "max_depth_m": float(np.max(depth)),
        })
    keys = list(rows[0].keys())
    with open(os.path.join(outdir, "compare_models.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(str(r[k]) for k in keys) + "\n")
    lines = [f"{strands} demo guides, {duration} s of the demo's shake, 2 threads"]
    for r in rows:
        lines.append(
            f"{r['model']:>22}: {r['elements']:3d} elements, {r['wall_s']:7.1f} s wall, "
            f"{r['cpu_s']:7.1f} s CPU, {r['ms_per_strand_frame']:7.2f} ms per strand-frame; "
            f"last frame: kinetic {r['kinetic']:.3g} J, elastic {r['elastic']:.3g} J, "
            f"residual {r['residual']:.3g} J, {r['nodes_inside']} nodes inside "
            f"(deepest {1e3 * r['max_depth_m']:.2f} mm)")
    studytool.write_summary(outdir, "compare_models.txt", lines)

    # The strands at three instants, one row per model, seen from the front (x right, y up).
    with h5py.File(files[MODELS[0][0]], "r") as f:
        times = f["time"][:]
    instants = [0, len(times) // 2, len(times) - 1]
    fig, axes = plt.subplots(len(MODELS), len(instants), figsize=(11, 3.6 * len(MODELS)),
                             sharex=True, sharey=True)
    for row, (model, _, _) in enumerate(MODELS):
        with h5py.File(files[model], "r") as f:
            for col, frame in enumerate(instants):
                ax = axes[row][col]
                for s in strands_at(f, frame):
                    ax.plot(s[:, 0], s[:, 1], lw=0.8, color=f"C{row}")
                ax.set_aspect("equal")
                ax.set_title(f"{model}, t = {f['time'][frame]:.2f} s", fontsize=9)
                if col == 0:
                    ax.set_ylabel("y (m)")
                if row == len(MODELS) - 1:
                    ax.set_xlabel("x (m)")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "compare_models.png"), dpi=110)

    fig, axes = plt.subplots(1, 4, figsize=(15, 3.6))
    for row, (model, _, _) in enumerate(MODELS):
        with h5py.File(files[model], "r") as f:
            t = f["time"][:]
            for ax, term in zip(axes, ["kinetic", "elastic", "gravitational", "residual"]):
                values = f["energy"][term][:]
                if term == "gravitational":
                    values = values - values[0]
                ax.plot(t, values, color=f"C{row}", label=model)
                ax.set_title(term + (" − its value at t = 0" if term == "gravitational" else "")
                             + " (J)", fontsize=9)
                ax.set_xlabel("t (s)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "compare_energy.png"), dpi=110)


if __name__ == "__main__":
    main()
