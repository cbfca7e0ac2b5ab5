"""Study 3 of issue 6 (buckling), two parts: (1) Euler buckling of a clamped-free Super-Helix
column under a dead axial load at its tip, for several N; (2) the clump: a clump of guides held
apart by hair-hair contacts whose root disc oscillates vertically, for several internal
frictions gamma (Super-Helices paper, Bertails et al. 2006, figs. 6-7), its span over time.

Run: /usr/bin/python3 Scripts/study_buckling.py build/bin/hair_study <output dir> [--quick]

A straight, round strand (smooth preset, ellipticity 1, L = 10 cm, its internal friction and
air drag), clamped at the origin with tangent +x, no gravity. `hair_study buckling`
(Tools/studies/buckling.cxx) puts a dead load P at the tip (StrandSpec::tipForce) pointing along -x
and tilted by 1e-4 rad towards +y: the imperfection is a transverse tip load of 1e-4 P
(small enough that the geometric nonlinearity below P_cr, O((delta/L)^2) < 3e-6, is negligible). For
each P (increasing, in units of the Euler load P_cr = pi^2 EI / (4 L^2) of a clamped-free
column), it steps with dt = 100 s from the previous load's equilibrium until the tip moves
by less than 1e-13 L in a step: the semi-implicit step's fixed point is the static
equilibrium, and steps much longer than the rod's period (0.8 s) reach it like a fixed-point
iteration (quasi-static continuation).

Estimator of the critical load (Southwell, 1932; e.g. Timoshenko & Gere, Theory of Elastic
Stability, 2nd ed., 1961, ch. 2): below P_cr the lateral tip deflection of an imperfect
column is delta ~ a P / (1 - P/P_cr) (the first mode dominates; the imperfection's effect
here grows with P), so delta/P = a + delta/P_cr: the least-squares slope of delta/P against
delta over P = 0.5 ... 0.95 P_cr is 1/P_cr. Measured for every N, compared with the formula.

References drawn on the plot:
  - linear beam-column under axial P and transverse Q = 1e-4 P (Timoshenko & Gere ch. 1):
    delta = 1e-4 (tan(kL)/k - L), k = sqrt(P/EI), below P_cr;
  - the elastica of the perfect column above P_cr (Timoshenko & Gere ch. 2):
    P/P_cr = (2 K(m)/pi)^2, delta/L = 2 sqrt(m) / K(m), with K the complete elliptic integral
    of the first kind, m = sin^2(theta_tip/2).

Clump part: `hair_study clump` (Tools/studies/clump.cxx; 50 guides of 30 cm, 20 in --quick) is run
for gamma = 5e-11, 1e-10, 2e-10, 5e-10 kg m^3/s with contacts, and once at 1e-10 without them.
The clump is squeezed by an air flow converging on its axis (ramped over 3 s, 1.5 s quick), then
its root disc oscillates vertically (1 cm, 3 Hz) until 6 s (3 s quick). Span l_A: the largest
distance between two tips projected on the horizontal plane (docs/hair-analysis.md).

Writes to the output dir: study_buckling.csv (hair_study's columns, all N), study_buckling.png
(deflection against P/P_cr for several N; Southwell plot at N = 10), study_clump.csv
(hair_study clump's rows, with contacts; study_clump_nocontact.csv without), study_clump.png
and study_buckling.txt (both parts' summaries).
"""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import studytool  # noqa: E402

LENGTH = 0.1
TILT = 1e-4  # rad: the transverse tip load is 1e-4 P
SOUTHWELL = (0.5, 0.95)  # load window of the Southwell fit, in units of the formula's P_cr
REFERENCE_N = 10
PCR_TOLERANCE = 0.05  # issue 6: P_cr within 5 % of the formula at N = 10

# Clump part (hair_study clump): see clump() below and docs/study-buckling.md.
CLUMP_GAMMAS = [5e-11, 1e-10, 2e-10, 5e-10]  # kg m^3/s: the Super-Helices paper's range
CLUMP_REFERENCE_GAMMA = 1e-10  # the run without hair-hair contacts (the reference)
CLUMP_THICKNESS = 1.2e-3  # m: hair_study clump's default contact thickness
CLUMP_FREQUENCY = 3.0  # Hz: hair_study clump's default root oscillation


elastica = studytool.elastica


def beam_column(ratio):
    """Linear beam-column: tip deflection / L under P and the transverse TILT * P, P < P_cr."""
    u = np.pi / 2 * np.sqrt(ratio)
    return TILT * (np.tan(u) / u - 1)


def southwell(ratio, load, delta):
    """P_cr from the slope of delta/P against delta over the SOUTHWELL window."""
    w = (ratio >= SOUTHWELL[0] - 1e-9) & (ratio <= SOUTHWELL[1] + 1e-9)
    s, c = np.polyfit(delta[w], delta[w] / load[w], 1)
    return 1 / s, c, w


def main():
    tool, outdir, quick = studytool.parse_args("study_buckling.py")
    ns = [5, 10, 20] if quick else [2, 3, 5, 10, 20, 40]
    if quick:
        loads = [0.1, 0.3, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 1.0, 1.1, 1.5]
    else:
        loads = ([round(0.05 * i, 2) for i in range(1, 20)]
                 + [0.97, 0.99, 1.0, 1.01, 1.02, 1.05, 1.1, 1.2, 1.3, 1.5, 1.75, 2.0])
    runs = {}
    for n in ns:
        path = os.path.join(outdir, f"study_buckling_N{n}.csv")
        studytool.run(tool, "buckling", out=path, n=n, tilt=TILT, length=LENGTH,
                      loads=",".join(map(str, loads)))
        runs[n] = studytool.read_csv(path)
        os.remove(path)
    # one CSV with every N
    with open(os.path.join(outdir, "study_buckling.csv"), "w") as f:
        cols = list(runs[ns[0]].keys())
        f.write(",".join(cols) + "\n")
        for n in ns:
            d = runs[n]
            for i in range(len(d["N"])):
                f.write(",".join(f"{d[c][i]:.10g}" for c in cols) + "\n")

    pcr = runs[ns[0]]["Pcr_N"][0]
    results = {}
    for n in ns:
        d = runs[n]
        est, intercept, w = southwell(d["load_ratio"], d["P_N"], d["tip_y_m"])
        results[n] = dict(pcr=est, intercept=intercept, window=w,
                          unconverged=int((d["converged"] == 0).sum()))

    # --- plot ------------------------------------------------------------------------
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.5), gridspec_kw=dict(width_ratios=[1.3, 1]))
    colours = plt.cm.viridis(np.linspace(0, 0.85, len(ns)))
    for n, c in zip(ns, colours):
        d = runs[n]
        ax.plot(d["load_ratio"], d["tip_y_m"] / LENGTH, "o-", ms=3.5, color=c,
                label=f"N = {n}: Southwell P_cr = {results[n]['pcr'] / pcr:.4f} × formula")
    r_lo = np.linspace(0.02, 0.985, 200)
    ax.plot(r_lo, beam_column(r_lo), "k--", lw=1,
            label="linear beam-column, transverse load 10⁻⁴ P (below P_cr)")
    r_hi = np.linspace(1.0005, max(loads), 200)
    ax.plot(r_hi, [elastica(r) for r in r_hi], "k:", lw=1.5,
            label="elastica of the perfect column (above P_cr)")
    ax.axvline(1.0, color="0.5", lw=0.8)
    ax.text(0.985, 0.97, "P = P_cr", rotation=90, fontsize=8, color="0.3", ha="right", va="top",
            transform=ax.get_xaxis_transform())
    ax.set_yscale("log")
    ax.set_ylim(1e-6, 1.5)
    ax.set_xlabel("axial tip load P / P_cr (P_cr = π²EI/(4L²) = "
                  f"{pcr * 1e6:.4g} µN)")
    ax.set_ylabel("lateral tip deflection δ / L (–)")
    ax.set_title("Clamped–free strand, L = 10 cm, dead axial tip load\n"
                 "tilted by 10⁻⁴ rad (the imperfection); static equilibria")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")

    d = runs[REFERENCE_N] if REFERENCE_N in runs else runs[ns[len(ns) // 2]]
    nref = int(d["N"][0])
    res = results[nref]
    w = res["window"]
    delta_mm = d["tip_y_m"] * 1e3
    bx.plot(delta_mm[w], d["tip_y_m"][w] / d["P_N"][w], "o", color="tab:blue",
            label=f"N = {nref}, P = {SOUTHWELL[0]}…{SOUTHWELL[1]} P_cr (fitted)")
    pre = (d["load_ratio"] < SOUTHWELL[0] - 1e-9)
    bx.plot(delta_mm[pre], d["tip_y_m"][pre] / d["P_N"][pre], "o", mfc="none", color="tab:blue",
            label=f"N = {nref}, lower loads (not fitted)")
    x = np.linspace(0, delta_mm[w].max() * 1.05, 50)
    bx.plot(x, res["intercept"] + x * 1e-3 / res["pcr"], "r-", lw=1,
            label=f"least squares: slope 1/P_cr, P_cr = {res['pcr'] * 1e6:.4g} µN\n"
                  f"({100 * (res['pcr'] / pcr - 1):+.2f} % against the formula)")
    bx.set_xlabel("lateral tip deflection δ (mm)")
    bx.set_ylabel("δ / P (m/N)")
    bx.set_title(f"Southwell plot, N = {nref}: δ/P = a + δ/P_cr")
    bx.grid(True, alpha=0.3)
    bx.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_buckling.png"), dpi=110)

    # --- summary ---------------------------------------------------------------------
    lines = ["Euler buckling of a clamped-free Super-Helix strand (smooth preset, round, L = 0.1 m)",
             f"P_cr = pi^2 EI / (4 L^2) = {pcr:.6g} N; imperfection: the load tilted by {TILT:g} rad",
             f"N = {', '.join(map(str, ns))}" + (" (quick)" if quick else "")
             + f"; loads {min(loads)} ... {max(loads)} P_cr",
             f"estimator: Southwell, slope of delta/P against delta over P = {SOUTHWELL[0]} ... "
             f"{SOUTHWELL[1]} P_cr", "",
             f"{'N':>4}{'P_cr (N)':>14}{'/ formula - 1':>15}{'unconverged loads':>19}"]
    for n in ns:
        r = results[n]
        lines.append(f"{n:>4}{r['pcr']:>14.6g}{r['pcr'] / pcr - 1:>+15.3e}{r['unconverged']:>19}")
    ref_err = results[nref]["pcr"] / pcr - 1
    lines += ["", f"at N = {nref}: P_cr {100 * ref_err:+.3f} % from the formula "
              f"(required: within {100 * PCR_TOLERANCE:.0f} %): "
              + ("PASS" if abs(ref_err) <= PCR_TOLERANCE else "FAIL")]
    # The Southwell estimator's own bias, on the exact linear beam-column curve (higher modes
    # make delta/P against delta slightly curved); the same window and load levels.
    rr = np.array([r for r in loads if SOUTHWELL[0] - 1e-9 <= r <= SOUTHWELL[1] + 1e-9])
    est, _, _ = southwell(rr, rr * pcr, beam_column(rr) * LENGTH)
    bias = est / pcr - 1
    lines.append(f"the estimator's own bias (on the exact linear beam-column curve, same loads): "
                 f"{100 * bias:+.4f} %")
    conv = [n for n in ns if n >= 5]
    if len(conv) >= 2:
        err = np.array([results[n]["pcr"] / pcr - 1 for n in conv])
        raw = -studytool.slope(np.array(conv, float), err)
        order = -studytool.slope(np.array(conv, float), err - bias)
        lines.append(f"order in 1/N of the discretization error of P_cr (measured - formula - bias), "
                     f"N = {conv[0]} ... {conv[-1]}: {order:.3f} (expected 2, as for the frequencies "
                     f"of study 1; without removing the bias: {raw:.2f})")
    post = [r for r in (1.1, 1.5, 2.0) if r in loads]
    if post:
        lines.append("post-buckling, delta/L against the perfect elastica:")
        for n in ns:
            dd = runs[n]
            parts = []
            for r in post:
                i = int(np.argmin(np.abs(dd["load_ratio"] - r)))
                parts.append(f"{r} P_cr: {dd['tip_y_m'][i] / LENGTH:.5f} vs {elastica(r):.5f}")
            lines.append(f"  N = {n:>2}: " + "; ".join(parts))
    lines += [""] + clump(tool, outdir, quick)
    studytool.write_summary(outdir, "study_buckling.txt", lines)


def clump_metrics(d, start):
    """Per-run numbers: initial span, mean span and its oscillation during the shaking (t >
    start), smallest span / initial over the whole run, deepest overlap, 3 Hz component."""
    t, span = d["time_s"], d["span_m"]
    w = t > start + 1e-9
    ts, ss = t[w], span[w]
    # the span's response at the drive frequency: |(2/T) sum span(t) exp(-i w t) dt|
    dt = np.diff(t).mean()
    phase = np.exp(-2j * np.pi * CLUMP_FREQUENCY * ts)
    harmonic = abs(2 * np.sum((ss - ss.mean()) * phase) * dt / (ts[-1] - ts[0] + dt))
    return dict(initial=span[0], mean=ss.mean(), half_range=(ss.max() - ss.min()) / 2,
                harmonic=harmonic, min_ratio=span.min() / span[0],
                min_ratio_squeezed=span[(t >= start / 3) & (t <= start + 1e-9)].min() / span[0],
                mean_radius=d["mean_radius_m"][w].mean(),
                deepest=d["max_penetration_m"].max(), contacts=d["contacts"][w].mean())


def clump(tool, outdir, quick):
    """The clump part: runs hair_study clump, plots study_clump.png, returns summary lines."""
    path = os.path.join(outdir, "study_clump.csv")
    ref_path = os.path.join(outdir, "study_clump_nocontact.csv")
    size = dict(quick=1) if quick else {}
    studytool.run(tool, "clump", out=path, gammas=",".join(map(str, CLUMP_GAMMAS)), **size)
    studytool.run(tool, "clump", out=ref_path, gammas=CLUMP_REFERENCE_GAMMA, contacts=0, **size)
    rows, ref = studytool.read_csv(path), studytool.read_csv(ref_path)
    runs = {g: {k: v[np.isclose(rows["gamma"], g, rtol=1e-6, atol=0)] for k, v in rows.items()}
            for g in CLUMP_GAMMAS}
    first = runs[CLUMP_GAMMAS[0]]
    t = first["time_s"]
    start = t[np.nonzero(np.abs(first["root_y_m"]) > 1e-9)[0][0] - 1]  # the oscillation starts
    metrics = {g: clump_metrics(runs[g], start) for g in CLUMP_GAMMAS}
    mref = clump_metrics(ref, start)
    count = 20 if quick else 50

    # --- plot ------------------------------------------------------------------------
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(11, 7.5), sharex=True,
                                 gridspec_kw=dict(height_ratios=[2.2, 1]))
    colours = plt.cm.plasma(np.linspace(0, 0.8, len(CLUMP_GAMMAS)))
    for g, c in zip(CLUMP_GAMMAS, colours):
        d = runs[g]
        ax.plot(d["time_s"], d["span_m"] * 1e3, color=c, lw=1.4,
                label=f"γ = {g:.0e} kg·m³/s, contacts")
        bx.plot(d["time_s"], d["max_penetration_m"] * 1e3, color=c, lw=1)
    ax.plot(ref["time_s"], ref["span_m"] * 1e3, color="0.45", lw=1.2, ls="--",
            label=f"γ = {CLUMP_REFERENCE_GAMMA:.0e} kg·m³/s, no hair–hair contacts")
    ax.axvspan(start, t[-1], color="0.9", zorder=0)
    ax.text(start / 2, 0.47, "squeezed: converging air flow\nramped up", ha="center",
            va="center", fontsize=8, color="0.3", transform=ax.get_xaxis_transform())
    ax.text((start + t[-1]) / 2, 0.47, "root disc oscillating vertically, 1 cm, "
            f"{CLUMP_FREQUENCY:g} Hz (flow kept)", ha="center", va="center", fontsize=8,
            color="0.3", transform=ax.get_xaxis_transform())
    ax.set_ylabel("span ℓ_A of the tips (mm)")
    ax.set_ylim(0, 1.4 * first["span_m"][0] * 1e3)  # room for the legend above the spans
    ax.grid(True, alpha=0.3)
    rx = ax.twinx()
    rx.plot(t, first["root_y_m"] * 1e3, color="tab:green", lw=0.8, alpha=0.8,
            label="root disc's vertical position (right axis)")
    rx.set_ylabel("root disc's vertical position (mm)", color="tab:green")
    rx.tick_params(axis="y", colors="tab:green")
    rx.set_ylim(-12, 60)  # keeps the root's trace below the spans
    rx.set_yticks([-10, -5, 0, 5, 10])
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = rx.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper right", ncol=2, framealpha=0.9)
    ax.set_title(f"Clump of {count} guides (30 cm, smooth, round), hair–hair contacts of "
                 f"thickness {CLUMP_THICKNESS * 1e3:g} mm, 4 contact updates per 1/30 s\n"
                 "span ℓ_A = largest horizontal distance between two tips, for several "
                 "internal frictions γ")
    bx.axhline(0.3 * 2 * CLUMP_THICKNESS * 1e3, color="k", lw=0.8, ls=":")
    bx.text(0.01, 0.3 * 2 * CLUMP_THICKNESS * 1e3, " 30 % of the contact distance", fontsize=8,
            va="bottom", transform=bx.get_yaxis_transform())
    bx.axvspan(start, t[-1], color="0.9", zorder=0)
    bx.set_ylabel("deepest overlap in the\nframe (mm; colours above)")
    bx.set_ylim(0, 0.45 * 2 * CLUMP_THICKNESS * 1e3)
    bx.set_xlabel("time (s)")
    bx.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_clump.png"), dpi=110)

    # --- summary ---------------------------------------------------------------------
    lines = [f"Clump of {count} guides under a vertical root oscillation (1 cm, "
             f"{CLUMP_FREQUENCY:g} Hz from t = {start:.3g} s to {t[-1]:.3g} s)"
             + (" (quick)" if quick else ""),
             "span l_A: largest horizontal distance between two tips; 'oscillation': t > "
             f"{start:.3g} s; contact distance 2 x thickness = {2e3 * CLUMP_THICKNESS:g} mm", "",
             f"{'gamma':>8}{'initial':>9}{'min/initial':>12}{'mean span':>11}{'half range':>11}"
             f"{'3 Hz amp.':>10}{'mean radius':>12}{'contacts':>9}{'deepest':>9}",
             f"{'kg m3/s':>8}{'mm':>9}{'squeezed':>12}{'osc., mm':>11}{'osc., mm':>11}"
             f"{'mm':>10}{'osc., mm':>12}{'osc.':>9}{'mm':>9}"]

    def row(name, m):
        return (f"{name:>8}{m['initial'] * 1e3:>9.2f}{m['min_ratio_squeezed']:>12.3f}"
                f"{m['mean'] * 1e3:>11.2f}{m['half_range'] * 1e3:>11.2f}"
                f"{m['harmonic'] * 1e3:>10.2f}{m['mean_radius'] * 1e3:>12.2f}"
                f"{m['contacts']:>9.0f}{m['deepest'] * 1e3:>9.3f}")
    for g in CLUMP_GAMMAS:
        lines.append(row(f"{g:.0e}", metrics[g]))
    lines.append(row("no cont.", mref) + f"   (gamma {CLUMP_REFERENCE_GAMMA:.0e}, no contacts)")
    return lines


if __name__ == "__main__":
    main()
