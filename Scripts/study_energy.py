"""Study 4 of issue 6: the energy budget over time, and how well it closes.

Run: /usr/bin/python3 Scripts/study_energy.py build/bin/hair_study <output dir> [--quick]
                                              [--state <file.h5> ...]

The budget of docs/super-helix.md, per strand and summed over strands:
    (kinetic - kinetic0) + (elastic - elastic0) + friction + air dissipated
        = work done on the hair + residual,
    work done on the hair = gravity's work -(gravitational - gravitational0)
                            + root + wind + contact + tip-load work,
where the residual is what the time integrator itself adds (< 0: numerical dissipation).
The step is first order in dt, so the residual must fall like dt. Closure of the budget:
max_t |residual| / max_t |work done on the hair|.

(a) A released strand, from Core through `hair_study release` (Tools/studies/release.cxx): the
    wavy preset, 30 cm, N = 10, clamped horizontally (tangent +x) at a fixed root, in its
    natural shape and at rest at t = 0, falling under gravity with its internal friction and
    air drag, for 2 s (--quick: 1 s) at dt = 1/30 s and finer (down to 1/3840 s; --quick:
    1/960 s).
(b) The demo scene: the state files that `bash Scripts/demo.sh` writes (Output/super-helix.h5
    and Output/projective.h5; layout in docs/state-file.md, read with h5py), or the files
    given with --state. If they are absent the script says how to make them and uses a small
    scene instead, made by `hair_study scene` (6 wavy strands on a shaking head with wind, no
    body, 1 s: Super-Helix at dt = 1/30 and 1/120 s, and projective with 40 segments, whose
    explicit steps are at most 1 ms); --quick always uses that one.

Writes to the output dir: study_energy_release.csv (every dt, every step),
study_energy_release.png (stacked budget at dt = 1/30 s and at a fine dt; residual over time;
closure against the step), study_energy_scene.png (stacked budget of each state file),
study_energy.txt (closures, fitted order, tolerances).
(c) Full mode only (about 7 minutes): the demo's projective run (`hair_study demo`, the scene of
    Scripts/demo.sh through Core: 200 guides, 40 segments, head and trunk tables, 5 s) at steps
    of about 1, 0.5 and 0.25 ms: its residual against the step (study_energy_contact.png).
"""
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import studytool  # noqa: E402

DEMO_FILES = [os.path.join(studytool.ROOT, "Output", "super-helix.h5"),
              os.path.join(studytool.ROOT, "Output", "projective.h5")]
EXPECTED_ORDER = 1.0  # the step is first order in dt (docs/super-helix.md, "The time step")


def budget(e):
    """The budget's pieces from a dict of energy series (J): stack terms, work, residual."""
    n = len(e["kinetic"])
    zero = np.zeros(n)
    # relative to the start: a shaking head's strands move at t = 0 already
    stack = [("kinetic" if e["kinetic"][0] == 0 else "kinetic (relative to start)",
              e["kinetic"] - e["kinetic"][0]),
             ("elastic (relative to start)", e["elastic"] - e["elastic"][0])]
    if "friction_dissipated" in e:
        stack.append(("dissipated by internal friction", e["friction_dissipated"]))
        stack.append(("dissipated by air drag", e["air_dissipated"]))
        # hair–hair interaction (docs/hair-hair-interaction.md): the grid's drag, the pairs'
        for key, label in (("hair_grid_dissipated", "dissipated by the hair grid's friction"),
                           ("hair_hair_dissipated", "dissipated by hair–hair pairs")):
            if key in e and np.any(e[key] != 0):
                stack.append((label, e[key]))
    else:  # the projective model: its air drag is in wind_work
        # (state files written before issue 23 have its angular damping as "dissipated")
        stack.append(("dissipated by angular damping", e.get("damping_dissipated", e["dissipated"])))
        if "contact_dissipated" in e and np.any(e["contact_dissipated"] != 0):
            stack.append(("dissipated at contact events", e["contact_dissipated"]))
    projective = "friction_dissipated" not in e
    works = [("gravity's work −(gravitational − start)", -(e["gravitational"] - e["gravitational"][0]))]
    for key, label in (("root_work", "root"), ("body_work", "root (body motion)"),
                       ("wind_work", "air drag (net, wind included)" if projective else "wind"),
                       ("contact_work", "contact"),
                       ("hair_grid_work", "hair grid"),
                       ("hair_hair_work", "hair–hair pairs"),
                       ("load_work", "tip load")):
        if key in e and np.any(e[key] != 0):
            works.append((f"{label} work", e[key]))
    if "external_work" in e:  # a state file: external_work is the sum; whatever it has beyond
        named = sum((w for k, w in works[1:]), zero)  # the named terms is the tip load's
        rest = e["external_work"] - named
        if np.any(np.abs(rest) > 1e-12 * max(1e-300, np.abs(e["external_work"]).max())):
            works.append(("other external work (tip load)", rest))
    work = sum((w for _, w in works), zero)
    residual = e["residual"]
    return stack, works, work, residual


def closure(residual, work):
    return float(np.abs(residual).max() / np.abs(work).max())


def bookkeeping(stack, work, residual):
    """|sum of the stack - work - residual| relative to the work: the identity to round-off."""
    total = sum(v for _, v in stack)
    return float(np.abs(total - work - residual).max() / np.abs(work).max())


STACK_COLOURS = ["tab:blue", "tab:green", "tab:orange", "tab:purple"]


def unit(values):
    """(scale, name) that puts the largest of `values` between 1 and 1000."""
    top = float(np.abs(values).max())
    for scale, name in ((1, "J"), (1e3, "mJ"), (1e6, "µJ"), (1e9, "nJ")):
        if top * scale >= 1:
            return scale, name
    return 1e12, "pJ"


def stacked(ax, t, stack, works, work, title, legend="lower right"):
    """Stacked areas (negative parts stacked downwards) against the work done on the hair."""
    k, name = unit(work)
    stack = [(label, k * v) for label, v in stack]
    works = [(label, k * w) for label, w in works]
    work = k * work
    up, down = np.zeros_like(t), np.zeros_like(t)
    for (label, v), c in zip(stack, STACK_COLOURS):
        pos, neg = np.maximum(v, 0), np.minimum(v, 0)
        ax.fill_between(t, up, up + pos, color=c, alpha=0.55, lw=0, label=label)
        if np.any(neg < 0):
            ax.fill_between(t, down + neg, down, color=c, alpha=0.55, lw=0)
        up, down = up + pos, down + neg
    ax.plot(t, work, "k-", lw=2, label="work done on the hair" + (
        f" = {works[0][0]}" if len(works) == 1 else ", the sum of:"))
    if len(works) > 1:
        for (label, w), ls, c in zip(works, ["--", ":", "-.", "--", ":", "-."],
                                     ["0.35", "tab:brown", "tab:cyan", "tab:red", "tab:olive",
                                      "tab:pink"]):
            ax.plot(t, w, color=c, ls=ls, lw=1.2, label=f"  {label}")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"energy ({name})")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc=legend, framealpha=0.9)


# --- (a) the released strand -------------------------------------------------------------

def release(tool, outdir, quick):
    duration = 1.0 if quick else 2.0
    rates = [30, 60, 120, 240, 480, 960] + ([] if quick else [1920, 3840])
    runs = {}
    for k in rates:
        path = os.path.join(outdir, f"release_{k}.csv")
        studytool.run(tool, "release", out=path, dt=f"1/{k}", duration=duration, n=10,
                      length=0.3, preset="wavy")
        runs[k] = studytool.read_csv(path)
    with open(os.path.join(outdir, "study_energy_release.csv"), "w") as f:
        cols = list(runs[rates[0]].keys())
        f.write("dt_s," + ",".join(cols) + "\n")
        for k in rates:
            d = runs[k]
            for i in range(len(d["time_s"])):
                f.write(f"{1 / k:.10g}," + ",".join(f"{d[c][i]:.17g}" for c in cols) + "\n")
    for k in rates:
        os.remove(os.path.join(outdir, f"release_{k}.csv"))
    rows = []
    for k in rates:
        d = runs[k]
        stack, works, work, res = budget(d)
        substeps = float(d["substeps"][1:].mean())
        rows.append(dict(rate=k, dt=1 / k, h=1 / k / substeps, substeps=substeps,
                         closure=closure(res, work), residual_end=float(res[-1]),
                         work_max=float(np.abs(work).max()),
                         bookkeeping=bookkeeping(stack, work, res)))
    h = np.array([r["h"] for r in rows])
    c = np.array([r["closure"] for r in rows])
    order = studytool.slope(h, c)
    return runs, rows, order, duration


def plot_release(outdir, runs, rows, order):
    fine = rows[-1]["rate"] if rows[-1]["rate"] <= 480 else 480
    fig, axes = plt.subplots(2, 2, figsize=(13, 9))
    for ax, k in zip(axes[0], (30, fine)):
        d = runs[k]
        stack, works, work, res = budget(d)
        r = next(r for r in rows if r["rate"] == k)
        stacked(ax, d["time_s"], stack, works, work,
                f"(a) wavy strand, 30 cm, N = 10, released horizontally: dt = 1/{k} s\n"
                f"closure max|residual| / max|work| = {100 * r['closure']:.2f} %")
    ax = axes[1][0]
    cmap = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
    for r, col in zip(rows, cmap):
        d = runs[r["rate"]]
        ax.plot(d["time_s"], d["residual"] * 1e9, color=col, label=f"dt = 1/{r['rate']} s")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("residual (nJ)  (< 0: numerical dissipation)")
    ax.set_title("residual of the budget over time, every dt", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax = axes[1][1]
    h = np.array([r["h"] for r in rows])
    c = np.array([r["closure"] for r in rows])
    ax.loglog(h, 100 * c, "o-", color="tab:red",
              label=f"closure (fitted slope {order:.2f}; first-order step: 1)")
    ax.loglog(h, 100 * c[-1] * (h / h[-1]) ** EXPECTED_ORDER, "k--", lw=1,
              label="reference slope 1")
    labels = {}
    for r in rows:  # sub-steps are labelled if a step ever takes more than one
        text = f"dt = 1/{r['rate']}" + (f" ({r['substeps']:.0f} sub-steps)" if r["substeps"] > 1.01 else "")
        key = round(r["h"], 12)
        labels[key] = (r, labels[key][1] + ", " + text if key in labels else text)
    for r, text in labels.values():
        ax.annotate(text, (r["h"], 100 * r["closure"]), textcoords="offset points",
                    xytext=(-8, -4), ha="right", fontsize=7)
    ax.set_xlabel("step actually taken h = dt / sub-steps (s)")
    ax.set_ylabel("max|residual| / max|work done| (%)")
    ax.set_title("closure of the budget against the step", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_energy_release.png"), dpi=100)


# --- (b) the demo scene --------------------------------------------------------------------

def read_state(path):
    import h5py

    with h5py.File(path, "r", swmr=True) as f:
        n = f["time"].shape[0]
        t = f["time"][:n]
        e = {k: f["energy"][k][:n] for k in f["energy"].keys()}
        model = f.attrs.get("model", b"")
        model = model.decode() if isinstance(model, bytes) else str(model)
        strands = f["strands/offsets"].shape[0] - 1
    return t, e, model, strands


def scene(tool, outdir, quick, states):
    notes = []
    if not states and not quick:
        states = [p for p in DEMO_FILES if os.path.exists(p)]
        if not states:
            notes.append("the demo's state files (Output/super-helix.h5, Output/projective.h5) "
                         "are not there: make them with `bash Scripts/demo.sh` (a few minutes) "
                         "and run this study again; meanwhile the small scene of hair_study is used.")
            print("study_energy: " + notes[-1], file=sys.stderr)
    labelled = [(p, os.path.basename(p)) for p in states]
    if not labelled:
        for model, n, k in (("super-helix", 10, 30), ("super-helix", 10, 120), ("projective", 40, 30)):
            path = os.path.join(outdir, f"study_energy_scene_{model}_{k}.h5")
            studytool.run(tool, "scene", out=path, strands=6, n=n, duration=1, dt=f"1/{k}",
                          model=model)
            step = f"dt = 1/{k} s" if model == "super-helix" else "steps of 1 ms"
            labelled.append((path, f"small scene (hair_study scene), {step}"))
    results = []
    for path, label in labelled:
        t, e, model, strands = read_state(path)
        if len(t) < 2:
            sys.exit(f"{path} has fewer than two whole frames: nothing to plot")
        stack, works, work, res = budget(e)
        results.append(dict(path=path, label=label, model=model, strands=strands, t=t,
                            stack=stack, works=works, work=work, residual=res,
                            closure=closure(res, work), bookkeeping=bookkeeping(stack, work, res)))
    fig, axes = plt.subplots(2, len(results), figsize=(6.5 * len(results), 8.5), squeeze=False,
                             gridspec_kw=dict(height_ratios=[2, 1]))
    for j, r in enumerate(results):
        stacked(axes[0][j], r["t"], r["stack"], r["works"], r["work"],
                f"(b) {r['label']}: {r['model']}, {r['strands']} strands\n"
                f"closure max|residual| / max|work| = {100 * r['closure']:.2f} %", legend="upper left")
        ax = axes[1][j]
        k, name = unit(r["residual"])
        ax.plot(r["t"], r["residual"] * k, color="tab:red")
        ax.axhline(0, color="0.6", lw=0.6)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"residual ({name})")
        ax.set_title("residual of the budget (< 0: numerical dissipation)", fontsize=10)
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_energy_scene.png"), dpi=100)
    return results, notes


# --- (c) the projective demo's contact budget against its step ------------------------------

CONTACT_RATES = [1000, 2000, 4000]  # dt = 1/k s: projective steps of 1/30/ceil(k/30) s


def contact_steps(tool, outdir):
    """The demo's projective run (hair_study demo: 200 guides, 40 segments, the bundled body,
    5 s) at three steps; the budget of each."""
    rows = []
    for k in CONTACT_RATES:
        path = os.path.join(outdir, f"study_energy_contact_{k}.h5")
        studytool.run(tool, "demo", out=path, model="projective", dt=f"1/{k}", duration=5)
        t, e, model, strands = read_state(path)
        stack, works, work, res = budget(e)
        throughput = e["dissipated"][-1] - min(0.0, float(e["wind_work"][-1]))
        h = 1 / 30 / np.ceil(k / 30 - 1e-9)
        rows.append(dict(k=k, h=h, t=t, residual=res, closure=closure(res, work),
                         bookkeeping=bookkeeping(stack, work, res),
                         contact_work=float(e["contact_work"][-1]),
                         contact_dissipated=float(e["contact_dissipated"][-1]),
                         damping=float(e["damping_dissipated"][-1]),
                         wind=float(e["wind_work"][-1]), kinetic=float(e["kinetic"][-1]),
                         throughput=throughput, per_throughput=float(res[-1]) / throughput))
        os.remove(path)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.8))
    for r, c in zip(rows, ["tab:red", "tab:orange", "tab:purple"]):
        ax.plot(r["t"], 1e3 * r["residual"], color=c, label=f"h = {1e3 * r['h']:.3f} ms")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("residual (mJ)")
    ax.set_title("(c) the demo's projective run: residual of the budget at three steps", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    h = np.array([r["h"] for r in rows])
    for key, label, m in (("contact_work", "contact work", "o-"),
                          ("contact_dissipated", "dissipated at contact events", "s-"),
                          ("throughput", "energy dissipated (damping, contacts, air)", "^-")):
        bx.loglog(1e3 * h, [1e3 * r[key] for r in rows], m, label=label + " at 5 s")
    bx.loglog(1e3 * h, [-1e3 * float(r["residual"][-1]) for r in rows], "kD-", label="−residual at 5 s")
    bx.set_xlabel("step h (ms)")
    bx.set_ylabel("energy (mJ)")
    bx.set_title("the flows at 5 s against the step", fontsize=10)
    bx.grid(True, which="both", alpha=0.3)
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_energy_contact.png"), dpi=100)
    return rows


def main():
    argv = sys.argv[1:]
    states = []
    while "--state" in argv:
        i = argv.index("--state")
        if i + 1 >= len(argv):
            sys.exit("--state needs a file name")
        states.append(argv[i + 1])
        del argv[i:i + 2]
    for s in states:
        if not os.path.exists(s):
            sys.exit(f"no state file at {s}: make the demo's with `bash Scripts/demo.sh`")
    sys.argv[1:] = argv
    tool, outdir, quick = studytool.parse_args(
        "study_energy.py", " [--state <file.h5> ...]")
    runs, rows, order, duration = release(tool, outdir, quick)
    plot_release(outdir, runs, rows, order)
    results, notes = scene(tool, outdir, quick, states)

    lines = ["Energy budget: (kinetic - start) + (elastic - start) + dissipated = work done on the hair "
             "+ residual",
             "work done on the hair = gravity's work -(gravitational - start) + root + wind + "
             "contact + tip load",
             "closure = max_t |residual| / max_t |work done on the hair|", "",
             f"(a) released wavy strand, 30 cm, N = 10, fixed root, friction and drag, "
             f"{duration:g} s" + (" (quick)" if quick else ""),
             f"{'dt (s)':>10}{'sub-steps':>11}{'h (s)':>12}{'closure':>10}{'residual end (J)':>18}"
             f"{'max work (J)':>14}{'identity':>10}"]
    for r in rows:
        lines.append(f"{'1/' + str(r['rate']):>10}{r['substeps']:>11.2f}{r['h']:>12.3e}"
                     f"{100 * r['closure']:>9.3f}%{r['residual_end']:>18.4e}{r['work_max']:>14.4e}"
                     f"{r['bookkeeping']:>10.1e}")
    lines += [f"fitted order of the closure against h: {order:.3f} (expected {EXPECTED_ORDER:.0f}: "
              "the step is first order in dt)",
              "'identity': max |stack - work - residual| / max |work|, the bookkeeping to round-off;",
              "the tolerance on the closure is the integrator's first-order error: it has no fixed",
              "value, it must fall like h (h = dt: the step takes no stability sub-steps).", "",
              "(b) " + ("demo scene" if not quick else "small scene (quick)")]
    for r in results:
        lines.append(f"  {r['label']} ({r['model']}, {r['strands']} strands, {r['t'][-1]:.2f} s): "
                     f"closure {100 * r['closure']:.3f} %, identity {r['bookkeeping']:.1e}")
    lines += notes
    if not quick:
        lines += ["", "(c) the demo's projective run (200 guides, 40 segments, 5 s) at three steps:",
                  f"{'h (ms)':>9}{'closure':>10}{'residual (mJ)':>15}{'contact work':>14}"
                  f"{'contact diss.':>15}{'damping':>10}{'air (net)':>11}{'res./dissipated':>17}"]
        for r in contact_steps(tool, outdir):
            lines.append(f"{1e3 * r['h']:>9.4f}{100 * r['closure']:>9.2f}%{1e3 * r['residual'][-1]:>15.4f}"
                         f"{1e3 * r['contact_work']:>14.3f}{1e3 * r['contact_dissipated']:>15.3f}"
                         f"{1e3 * r['damping']:>10.3f}{1e3 * r['wind']:>11.3f}"
                         f"{100 * r['per_throughput']:>16.2f}%")
        lines.append("res./dissipated: the residual at 5 s over the energy dissipated by then "
                     "(angular damping, contacts and the air's net drag)")
    studytool.write_summary(outdir, "study_energy.txt", lines)


if __name__ == "__main__":
    main()
