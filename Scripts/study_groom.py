"""Issue 25's measurements of sag-free grooms (docs/study-groom.md).

Run: /usr/bin/python3 Scripts/study_groom.py build/bin/groom_study <output dir> [--quick]

For each model (Super-Helix, projective) and hair type (smooth, wavy, curly, fuzzy), computed
by `groom_study` (Tools/groom_study.cxx) through Core's public API: 200 guides grown on the
bundled body's scalp as Hair Strands grows them by default, shaken 0.5 s as Hair Simulation
shakes by default, and that frame given back as the groom; then, with the head and trunk
tables and dt = 1/30 s:
  sag-free  the groom made sag-free, no motion, 10 s: each strand's largest distance from the
            groom at any point and frame, and what the model reported of it (held, unstable,
            beyond the elastic range);
  as grown  the same groom as grown (what happens today): how far it falls;
  release   the sag-free groom shaken briefly (+-0.2 rad at 1 Hz, one cycle from 0.2 s) and
            released: its distance from the groom at 10 s.
--quick: 24 guides, smooth and curly, 3 s of hold and release (the CTest check,
Testing/Python/check_study_groom.py). --plot-only: the table and figure again from the CSV
already in the output dir (groom_study run with the same arguments).

Writes to the output dir: study_groom.csv (one row per model, preset and strand),
study_groom_curves.csv (the groom and each run's last frame, for Scripts/groom_pictures.py),
study_groom.png (the share of strands within a distance of the groom, sag-free against as
grown) and study_groom.txt (the summary table of docs/study-groom.md).
"""
import csv
import os
import subprocess
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PRESETS = ["smooth", "wavy", "curly", "fuzzy"]
MODELS = ["super-helix", "projective"]
STATUS = {0: "as grown", 1: "held", 2: "unstable", 3: "beyond elastic range"}


def main():
    args = [a for a in sys.argv[1:] if a not in ("--quick", "--plot-only")]
    quick = "--quick" in sys.argv[1:]
    plot_only = "--plot-only" in sys.argv[1:]
    if len(args) != 2:
        sys.exit("usage: /usr/bin/python3 Scripts/study_groom.py <build>/bin/groom_study <output dir> [--quick]")
    tool, outdir = args
    if not (os.path.isfile(tool) and os.access(tool, os.X_OK)):
        sys.exit(f"no groom_study program at {tool!r}: build it with "
                 "`cmake --build build --target groom_study` (it lands in build/bin/)")
    os.makedirs(outdir, exist_ok=True)
    csv_path = os.path.join(outdir, "study_groom.csv")
    curves = os.path.join(outdir, "study_groom_curves.csv")
    presets = ["smooth", "curly"] if quick else PRESETS
    cmd = [tool, f"out={csv_path}", f"curves={curves}", f"presets={','.join(presets)}",
           "models=" + ",".join(MODELS)]
    cmd += ["strands=24", "hold=3", "release=3"] if quick else ["strands=200", "hold=10", "release=10"]
    if not plot_only:
        r = subprocess.run(cmd, capture_output=True, text=True)
        sys.stderr.write(r.stderr)
        if r.returncode != 0:
            sys.exit(f"{' '.join(cmd)} failed (exit status {r.returncode})")
    rows = list(csv.DictReader(open(csv_path)))

    lines = ["| model | hair | strands | held (reported) | held: within 1 mm | unstable: Hessian / slides | "
             "beyond elastic range | sag-free: within 1 mm | sag-free: median | as grown: within 1 mm | "
             "as grown: median | as grown: largest | release: back within 1 mm (of those held) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    colours = dict(smooth="tab:blue", wavy="tab:orange", curly="tab:green", fuzzy="tab:red")
    for ax, model in zip(axes, MODELS):
        for preset in presets:
            sel = [x for x in rows if x["model"] == model and x["preset"] == preset]
            if not sel:
                continue
            status = np.array([int(x["rest_status"]) for x in sel])
            sf = np.array([float(x["sag_free_max_m"]) for x in sel])
            ag = np.array([float(x["as_grown_max_m"]) for x in sel])
            back = np.array([float(x["release_final_m"]) for x in sel])
            stability = np.array([float(x["stability"]) for x in sel])
            held = status == 1
            n = len(sel)
            # Unstable by the Hessian (its smallest eigenvalue at most the margin of
            # Core/model/GroomReport.h, 1e-6) or, the Hessian positive, sliding away when pushed.
            hessian = (status == 2) & ~(stability > 1e-6)
            slides = (status == 2) & (stability > 1e-6)
            lines.append(
                f"| {model} | {preset} | {n} | {held.sum()} ({100 * held.mean():.0f} %) | "
                f"{(sf[held] <= 1e-3).sum()} of {held.sum()} | "
                f"{hessian.sum()} / {slides.sum()} | {(status == 3).sum()} | "
                f"{(sf <= 1e-3).sum()} ({100 * np.mean(sf <= 1e-3):.0f} %) | {np.nanmedian(sf) * 1e3:.3g} mm | "
                f"{(ag <= 1e-3).sum()} ({100 * np.mean(ag <= 1e-3):.0f} %) | {np.nanmedian(ag) * 1e3:.3g} mm | "
                f"{np.nanmax(ag) * 1e3:.3g} mm | "
                f"{(back[held] <= 1e-3).sum()} of {held.sum()} |")
            for values, style, label in ((sf, "-", "sag-free"), (ag, "--", "as grown")):
                v = np.sort(np.where(np.isfinite(values), values, np.inf))
                ax.step(np.maximum(v, 1e-12), np.arange(1, n + 1) / n, style, color=colours[preset],
                        where="post", label=f"{preset}, {label}")
        ax.axvline(1e-3, color="0.5", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlim(1e-12, 1)
        ax.set_xlabel("largest distance from the groom over 10 s (m)")
        ax.set_title(model)
        ax.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel("share of strands within it")
    axes[1].legend(fontsize=7, loc="lower right")
    fig.suptitle("A shaken groom on the bundled body, held for 10 s: sag-free (solid) and as grown (dashed)")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_groom.png"), dpi=110)
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, "study_groom.txt"), "w") as f:
        f.write(text)
    print(text, end="")


if __name__ == "__main__":
    main()
