"""Accuracy against cost of the Super-Helix time steps, and their order in contact
(docs/study-accuracy.md).

Run: /usr/bin/python3 Scripts/study_accuracy.py build/bin/hair_study <output dir> [--quick]

(a) The demo's head (`hair_study accuracy`: 200 wavy guides of 10 elements grown on the
    bundled body's scalp, head and trunk tables, the hair grid, the head shaking +-0.5 rad at
    1 Hz, wind 0.5 m/s, 2 s, two threads) with every integrator at fixed frame steps and
    with tolerances, against a run of the semi-implicit step with a tolerance of 1 mm/s:
    each strand's largest tip distance from the reference over the frames (median and 95th
    percentile over the strands), the energy closure |residual| / (|work| + |dissipated|)
    at the end, and the wall time as a multiple of the default's (semi-implicit, fixed
    steps). --quick: 40 guides, 1 s, fewer runs.
(c) Work against precision over N (`hair_study workprecision`): the released strand (30 cm,
    smooth, air drag 1e-5, 1 s) with N = 5, 10, 20, 40 elements (--quick: 5, 10), every step
    with tolerances 0.05 ... 0.005 m/s, against the midpoint step at 1/7680 s with that N.
(b) A smooth 25 cm strand falling onto a still sphere (its table cast on the exact sphere)
    and onto the bundled head's tables (`hair_study order`), 1 s, friction 0.3: the tip's
    largest distance from a run at 1/(30 * 2048) s of the same step, for steps of
    1/(30 k) s, k = 1 ... 256 (--quick: 64), and the observed order.

Writes study_accuracy_scene.csv, study_accuracy_order_<body>.csv,
study_accuracy_workprecision.csv, study_accuracy.png (work against precision and closure on
the head, the order plots, work against precision over N) and study_accuracy.txt.
"""
import csv
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import studytool  # noqa: E402

FULL_RUNS = ["semi-implicit:0", "midpoint:0", "bdf2:0", "semi-implicit:0:4", "bdf2:0:4",
             "semi-implicit:0.05", "semi-implicit:0.02", "semi-implicit:0.01",
             "midpoint:0.05", "midpoint:0.02",
             "bdf2:0.1", "bdf2:0.07", "bdf2:0.05", "bdf2:0.03", "bdf2:0.02"]
QUICK_RUNS = ["semi-implicit:0", "bdf2:0", "semi-implicit:0.02", "bdf2:0.05"]
COLOURS = {"semi-implicit": "tab:blue", "midpoint": "tab:orange", "bdf2": "tab:green"}


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def label(r):
    tol = float(r["tolerance_m_per_s"])
    per = int(r["steps_per_frame"])
    if tol > 0:
        return f"{tol:g} m/s"
    return "fixed" if per == 1 else f"{per}/frame"


def main():
    tool, out, quick = studytool.parse_args("study_accuracy.py")
    scene = os.path.join(out, "study_accuracy_scene.csv")
    studytool.run(tool, "accuracy", out=scene,
                  runs=",".join(QUICK_RUNS if quick else FULL_RUNS),
                  reference="semi-implicit:0.001",
                  cache=os.path.join(out, "study_accuracy_reference.csv"),
                  guides=40 if quick else 200, seconds=1 if quick else 2, threads=2)
    orders = {}
    for body in ("sphere", "head"):
        path = os.path.join(out, f"study_accuracy_order_{body}.csv")
        studytool.run(tool, "order", out=path, body=body, finest=64 if quick else 256,
                      reference=512 if quick else 2048, integrators="semi-implicit,bdf2")
        orders[body] = rows(path)

    wp_path = os.path.join(out, "study_accuracy_workprecision.csv")
    studytool.run(tool, "workprecision", out=wp_path, ns="5,10" if quick else "5,10,20,40")
    wp = rows(wp_path)

    runs = rows(scene)
    lines = ["(a) the demo's head, 2 s (--quick: 1 s); reference: semi-implicit, 1 mm/s",
             f"{'integrator':<14}{'step':>12}{'wall':>8}{'tip median':>12}{'tip 95 %':>10}"
             f"{'closure':>9}{'sub-steps':>11}{'rejected':>10}{'1st order':>11}"]
    for r in runs:
        lines.append(f"{r['integrator']:<14}{label(r):>12}{float(r['wall_ratio']):>7.2f}x"
                     f"{1000 * float(r['tip_error_median_m']):>10.1f}mm"
                     f"{1000 * float(r['tip_error_p95_m']):>8.1f}mm"
                     f"{100 * float(r['closure']):>8.1f}%"
                     f"{float(r['substeps_per_frame']):>11.2f}"
                     f"{float(r['rejected_per_frame']):>10.2f}"
                     f"{float(r['first_order_share']):>11.2f}")
    lines.append("")
    lines.append("(b) a strand falling onto a body: tip error against the step, observed order")
    for body, rs in orders.items():
        for integrator in ("semi-implicit", "bdf2"):
            sel = [r for r in rs if r["integrator"] == integrator]
            errs = ", ".join(f"{1000 * float(r['tip_error_m']):.3g}" for r in sel)
            ks = [int(r["steps_per_frame"]) for r in sel]
            lines.append(f"{body:<7}{integrator:<14} k = {ks[0]}..{ks[-1]}: {errs} mm")
            lines.append(" " * 21 + "orders: " +
                         ", ".join(f"{float(r['order']):.2f}" for r in sel if r["order"]))
    lines.append("")
    lines.append("(c) the released strand, 1 s: tip error (mm) and steps per second, by N")
    for r in wp:
        lines.append(f"N = {int(r['n']):>2}  {r['integrator']:<14}{float(r['tolerance_m_per_s']):>7g} m/s"
                     f"{1000 * float(r['tip_error_m']):>10.3g} mm{int(r['steps']):>7} steps"
                     f" (+{int(r['rejected'])}){1000 * float(r['wall_s']):>9.1f} ms")
    studytool.write_summary(out, "study_accuracy.txt", lines)

    fig, axes = plt.subplots(1, 5, figsize=(25, 4.8))
    ax, axc = axes[0], axes[1]
    for integrator, colour in COLOURS.items():
        sel = [r for r in runs if r["integrator"] == integrator]
        if not sel:
            continue
        x = [float(r["wall_ratio"]) for r in sel]
        y = [1000 * float(r["tip_error_median_m"]) for r in sel]
        c = [100 * float(r["closure"]) for r in sel]
        ax.plot(x, y, "o", color=colour, label=integrator)
        axc.plot(x, c, "o", color=colour, label=integrator)
        for xi, yi, ci, r in zip(x, y, c, sel):
            ax.annotate(label(r), (xi, yi), fontsize=7, xytext=(3, 3), textcoords="offset points")
            axc.annotate(label(r), (xi, ci), fontsize=7, xytext=(3, 3), textcoords="offset points")
    for a, goal, what in ((ax, 30, "tip error median (mm)"), (axc, 10, "energy closure (%)")):
        a.axhline(goal, color="grey", lw=0.8, ls="--")
        a.axvline(3, color="grey", lw=0.8, ls=":")
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("wall time / default's (semi-implicit, fixed steps)")
        a.set_ylabel(what)
        a.legend(fontsize=8)
    ax.set_title("demo's head: work against precision\n(dashed: the issue's goal; dotted: 3x)")
    axc.set_title("demo's head: energy closure against work")
    aw = axes[4]
    markers = {5: "v", 10: "o", 20: "s", 40: "D"}
    for integrator, colour in COLOURS.items():
        for n in sorted({int(r["n"]) for r in wp}):
            sel = [r for r in wp if r["integrator"] == integrator and int(r["n"]) == n]
            aw.loglog([float(r["steps"]) for r in sel],
                      [1000 * float(r["tip_error_m"]) for r in sel],
                      marker=markers.get(n, "o"), color=colour, lw=0.8,
                      label=f"{integrator}, N = {n}")
    aw.set_xlabel("steps per simulated second (tolerances 0.05 ... 0.005 m/s)")
    aw.set_ylabel("tip error (mm)")
    aw.set_title("released strand: work against precision over N")
    aw.legend(fontsize=6, ncol=2)
    for a, (body, rs) in zip(axes[2:4], orders.items()):
        for integrator in ("semi-implicit", "bdf2"):
            sel = [r for r in rs if r["integrator"] == integrator]
            dt = np.array([float(r["dt_s"]) for r in sel])
            e = np.array([1000 * float(r["tip_error_m"]) for r in sel])
            a.loglog(dt, e, "o-", color=COLOURS[integrator], label=integrator)
        ref, eref = dt[-1], e[-1]  # the guides through the finest step
        a.loglog(dt, eref * (dt / ref), "k:", lw=0.8, label="slope 1")
        a.loglog(dt, eref * (dt / ref) ** 2, "k--", lw=0.8, label="slope 2")
        a.set_xlabel("step (s)")
        a.set_ylabel("tip error (mm)")
        a.set_title(f"a strand falling onto the {body}: order in contact")
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "study_accuracy.png"), dpi=90)


if __name__ == "__main__":
    main()
