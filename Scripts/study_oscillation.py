"""Study 5 (issue 23): the Super-Helices paper's own experiments (Bertails et al. 2006, §4.2,
figs. 6 and 7), with one Super-Helix standing for a clump of hair.

Run: /usr/bin/python3 Scripts/study_oscillation.py build/bin/hair_study <output dir> [--quick]

(a) Vertical oscillation of a curly clump (`hair_study oscillation`, Tools/studies/oscillation.cxx):
    the curly preset (the paper's "Caucasian 2", appendix B), 30 cm, N = 40, clamped pointing
    down at a root that first hangs in its static equilibrium and then oscillates vertically,
    d(t) = 1 cm sin(2 pi f t), grown from rest over 1 s, for gamma = 5e-11, 1e-10, 5e-10
    kg m^3/s. The clump's extent l_A (root to lowest point, along the vertical) over time; its
    amplitude (half of max - min over the last 2 s) against gamma and against the drive
    frequency (a sweep), with the heavy-spring estimate of the first axial mode.
(b) Its shape over the last period at 3 Hz for each gamma (the buckling of figure 7, left).
(c) The pendulum (`hair_study pendulum`): a smooth (disciplined) and a fuzzy strand of 30 cm
    hanging at rest, swung by one period of a 2 cm horizontal push of the root (1 Hz), then
    free; for nu = 0, 5e-6, 1e-5, 2e-5, 5e-5 kg/(m s), the damping time tau (e-folding time
    of the swing's amplitude, from a least-squares fit of log(energy above rest) = c - 2t/tau
    from the end of the push until the energy has fallen by 1e-6), against the rigid-pendulum
    estimate tau = 2 rho S / nu and against rates adding, 1/tau = 1/tau0 + nu / (2 rho S),
    tau0 the damping time at nu = 0.

--quick (CTest's study.oscillation): N = 20, dt = 1/1000 s, 5 s runs, frequencies 1, 2, 3, 4,
6 Hz; pendulum N = 10, dt = 1/1000 s, 5 s. The full run also checks convergence in dt and N.

Writes to the output dir: study_oscillation.csv (l_A over time at 3 Hz, every gamma),
study_oscillation_sweep.csv (per frequency and gamma: amplitude of l_A, width, lean),
study_oscillation_shapes.csv (the strand's points at 13 instants of the last period, every
gamma), study_pendulum.csv (tip and energy over time, every preset and nu),
study_oscillation.png, study_oscillation_buckling.png, study_pendulum.png and
study_oscillation.txt (the tables).
"""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import studytool  # noqa: E402

GAMMAS = [5e-11, 1e-10, 5e-10]  # kg m^3/s: the paper's figure 6
DRIVE = 3.0  # Hz: near the clump's first axial mode (the sweep finds it)
AMPLITUDE = 0.01  # m
NUS = [0, 5e-6, 1e-5, 2e-5, 5e-5]  # kg/(m s): 0 is the control, then the paper's range
PRESETS = ["smooth", "fuzzy"]  # disciplined and fuzzy hair
PUSH_END = 1.0  # s: the end of the pendulum's push (one period at 1 Hz)
GAMMA_COLOURS = {5e-11: "tab:blue", 1e-10: "tab:green", 5e-10: "tab:red"}


def same(values, x):
    """values == x to round-off (relative: gamma is ~1e-10, below numpy's default atol)."""
    return np.isclose(values, x, rtol=1e-9, atol=0)


def settings(quick):
    if quick:
        return dict(n=20, dt="1/1000", duration=5, window=1.5,
                    frequencies=[1, 2, 3, 4, 6], pendulum=dict(n=10, dt="1/1000", duration=5))
    return dict(n=40, dt="1/2000", duration=8, window=2,
                frequencies=[1, 1.5, 2, 2.5, 2.75, 3, 3.25, 3.5, 3.75, 4, 5, 6, 8],
                pendulum=dict(n=10, dt="1/2000", duration=8))


def oscillation(tool, outdir, s):
    """Time series and shapes at the drive frequency, and the frequency sweep."""
    gammas = ",".join(map(str, GAMMAS))
    common = dict(gammas=gammas, n=s["n"], dt=s["dt"], duration=s["duration"],
                  window=s["window"], amplitude=AMPLITUDE)
    series = os.path.join(outdir, "study_oscillation.csv")
    drive_summary = os.path.join(outdir, "drive_summary.csv")
    shapes = os.path.join(outdir, "study_oscillation_shapes.csv")
    studytool.run(tool, "oscillation", out=series, summary=drive_summary, shapes=shapes,
                  frequencies=DRIVE, **common)
    sweep = os.path.join(outdir, "study_oscillation_sweep.csv")
    scratch = os.path.join(outdir, "sweep_series.csv")
    studytool.run(tool, "oscillation", out=scratch, summary=sweep, rate=10,
                  frequencies=",".join(map(str, s["frequencies"])), **common)
    os.remove(scratch)
    os.remove(drive_summary)
    return studytool.read_csv(series), studytool.read_csv(sweep), studytool.read_csv(shapes)


def convergence(tool, outdir):
    """The amplitude of l_A at the drive, gamma = 5e-11 (the least damped), in dt and N."""
    rows = []
    for n, dt in ((40, "1/1000"), (40, "1/2000"), (40, "1/4000"), (20, "1/2000"), (80, "1/2000")):
        path = os.path.join(outdir, "convergence.csv")
        scratch = os.path.join(outdir, "convergence_series.csv")
        studytool.run(tool, "oscillation", out=scratch, summary=path, gammas="5e-11", n=n,
                      dt=dt, duration=8, window=2, amplitude=AMPLITUDE, frequencies=DRIVE, rate=10)
        d = studytool.read_csv(path)
        rows.append(dict(n=n, dt=dt, amplitude=float(d["extent_amplitude_m"][0]),
                         rest=float(d["extent_rest_m"][0])))
        os.remove(path)
        os.remove(scratch)
    return rows


def pendulum(tool, outdir, s):
    p = s["pendulum"]
    path = os.path.join(outdir, "study_pendulum.csv")
    studytool.run(tool, "pendulum", out=path, presets=",".join(PRESETS),
                  nus=",".join(map(str, NUS)), n=p["n"], dt=p["dt"], duration=p["duration"])
    import csv

    with open(path) as f:
        rows = list(csv.DictReader(f))
    runs = {}
    for r in rows:
        runs.setdefault((r["preset"], float(r["nu"])), []).append(r)
    out = {}
    for (preset, nu), v in runs.items():
        t = np.array([float(r["time_s"]) for r in v])
        energy = np.array([float(r["energy_j"]) for r in v])
        lateral = np.array([float(r["tip_x_m"]) - float(r["root_x_m"]) for r in v])
        out[(preset, nu)] = dict(t=t, energy=energy, lateral=lateral - lateral[0],
                                 rho_s=float(v[0]["linear_density"]), gamma=float(v[0]["gamma"]),
                                 tau=damping_time(t, energy))
    return out


def damping_time(t, energy):
    """tau from log(E) = c - 2 t / tau fitted from the end of the push until E has fallen by
    1e-6 (the amplitude by 1e-3)."""
    e0 = energy[np.searchsorted(t, PUSH_END)]
    m = (t >= PUSH_END) & (energy > 1e-6 * e0)
    slope = np.polyfit(t[m], np.log(energy[m]), 1)[0]
    return -2 / slope


def plot_oscillation(outdir, series, sweep, gammas_amp, quick):
    fig = plt.figure(figsize=(13, 9))
    ax = fig.add_subplot(2, 1, 1)
    t_end = series["time_s"].max()
    for g in GAMMAS:
        k = same(series["gamma"], g) & (series["time_s"] >= t_end - 2.5)
        ax.plot(series["time_s"][k], 1e3 * series["extent_m"][k], color=GAMMA_COLOURS[g],
                label=f"γ = {g:g} kg·m³/s: amplitude of ℓ_A {1e3 * gammas_amp[g]:.1f} mm")
    k = same(series["gamma"], GAMMAS[0]) & (series["time_s"] >= t_end - 2.5)
    ax2 = ax.twinx()
    ax2.plot(series["time_s"][k], 1e3 * series["root_y_m"][k], color="0.6", lw=1, ls="--")
    ax2.set_ylabel("root height (mm), dashed", color="0.4")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("ℓ_A: extent of the clump below its root (mm)")
    ax.set_title(f"(a) curly clump (one Super-Helix, curly preset, 30 cm), root oscillated "
                 f"{100 * AMPLITUDE:g} cm at {DRIVE:g} Hz" + (" (quick)" if quick else ""),
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    bx = fig.add_subplot(2, 2, 3)
    for g in GAMMAS:
        k = same(sweep["gamma"], g)
        bx.plot(sweep["frequency_hz"][k], 1e3 * sweep["extent_amplitude_m"][k], "o-",
                color=GAMMA_COLOURS[g], ms=4, label=f"γ = {g:g}")
    spring = float(sweep["spring_frequency_hz"][0])
    bx.axvline(spring, color="k", ls=":", lw=1,
               label=f"heavy-spring estimate f₁ = {spring:.2f} Hz")
    bx.axhline(1e3 * AMPLITUDE, color="0.6", lw=0.8, ls="--", label="root amplitude")
    bx.set_xlabel("drive frequency (Hz)")
    bx.set_ylabel("amplitude of ℓ_A (mm)")
    bx.set_title("amplitude of ℓ_A against the drive frequency", fontsize=10)
    bx.grid(True, alpha=0.3)
    bx.legend(fontsize=8)
    cx = fig.add_subplot(2, 2, 4)
    k = same(sweep["frequency_hz"], DRIVE)
    cx.semilogx(sweep["gamma"][k], 1e3 * sweep["extent_amplitude_m"][k], "ko-")
    cx.set_xlabel("internal friction γ (kg·m³/s)")
    cx.set_ylabel(f"amplitude of ℓ_A at {DRIVE:g} Hz (mm)")
    cx.set_title("amplitude of ℓ_A against γ (the paper's range)", fontsize=10)
    cx.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_oscillation.png"), dpi=100)


def plot_shapes(outdir, shapes):
    times = sorted(set(float(t) for t in shapes["time_s"]))
    fig, axes = plt.subplots(len(GAMMAS), len(times), figsize=(1.2 * len(times), 2.7 * len(GAMMAS)),
                             sharex=True, sharey=True, gridspec_kw=dict(wspace=0.05, hspace=0.15))
    for row, g in enumerate(GAMMAS):
        kg = same(shapes["gamma"], g)
        for col, t in enumerate(times):
            ax = axes[row][col]
            k = kg & same(shapes["time_s"], t)
            x, y = 1e3 * shapes["x_m"][k], 1e3 * shapes["y_m"][k]
            ax.plot(x, y, color=GAMMA_COLOURS[g], lw=0.9)
            ax.plot(x[:1], y[:1], "ks", ms=3)
            ax.set_aspect("equal")
            ax.set_xlim(-25, 45)
            ax.set_xticks([])
            if col == 0:
                ax.set_ylabel(f"γ = {g:g}\nheight (mm)", fontsize=8)
            if row == 0:
                ax.set_title(f"{(t - times[0]) * DRIVE:.2f} T", fontsize=8)
            ax.tick_params(labelsize=7)
    fig.suptitle(f"(b) the clump's shape over the last period T of the {DRIVE:g} Hz, "
                 f"{100 * AMPLITUDE:g} cm oscillation, seen from the side (x, y); square: the root",
                 fontsize=10)
    fig.subplots_adjust(left=0.05, right=0.99, top=0.9, bottom=0.03)
    fig.savefig(os.path.join(outdir, "study_oscillation_buckling.png"), dpi=100)


def plot_pendulum(outdir, runs):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    colours = plt.cm.viridis(np.linspace(0, 0.85, len(NUS)))
    for ax, preset in zip(axes[:2], PRESETS):
        for nu, c in zip(NUS, colours):
            r = runs[(preset, nu)]
            ax.plot(r["t"], 1e3 * r["lateral"], color=c, lw=1,
                    label=f"ν = {nu:g}: τ = {r['tau']:.3f} s")
        ax.axvline(PUSH_END, color="0.6", ls="--", lw=0.8)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("tip's horizontal distance from the root's vertical (mm)")
        ax.set_title(f"(c) {preset} preset (γ = {runs[(preset, NUS[0])]['gamma']:g}): "
                     "pushed until the dashed line, then free", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    ax = axes[2]
    nus = np.array([nu for nu in NUS if nu > 0])
    markers = {"smooth": "o", "fuzzy": "s"}
    for preset in PRESETS:
        tau = np.array([runs[(preset, nu)]["tau"] for nu in nus])
        rho_s = runs[(preset, nus[0])]["rho_s"]
        tau0 = runs[(preset, 0)]["tau"]
        ax.loglog(nus, tau, markers[preset] + "-", label=f"{preset}: measured")
        ax.loglog(nus, 1 / (1 / tau0 + nus / (2 * rho_s)), "k" + markers[preset], mfc="none",
                  ls=":", label=f"{preset}: 1/τ₀ + ν/(2ρS), τ₀ = {tau0:.3g} s")
    ax.loglog(nus, 2 * runs[("smooth", nus[0])]["rho_s"] / nus, "k--", lw=1,
              label="rigid pendulum in viscous drag: 2ρS/ν")
    ax.set_xlabel("air friction ν (kg/(m·s))")
    ax.set_ylabel("damping time τ (s)")
    ax.set_title("damping time against ν", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_pendulum.png"), dpi=100)


def main():
    tool, outdir, quick = studytool.parse_args("study_oscillation.py")
    s = settings(quick)
    series, sweep, shapes = oscillation(tool, outdir, s)
    drive = same(sweep["frequency_hz"], DRIVE)
    amp = {g: float(sweep["extent_amplitude_m"][drive & same(sweep["gamma"], g)][0])
           for g in GAMMAS}
    plot_oscillation(outdir, series, sweep, amp, quick)
    plot_shapes(outdir, shapes)
    runs = pendulum(tool, outdir, s)
    plot_pendulum(outdir, runs)

    spring = float(sweep["spring_frequency_hz"][0])
    lines = [f"(a) curly clump, 30 cm, N = {s['n']}, dt = {s['dt']} s, root oscillated "
             f"{100 * AMPLITUDE:g} cm, {s['duration']:g} s runs" + (" (quick)" if quick else ""),
             f"extent l_A at rest {1e3 * float(sweep['extent_rest_m'][0]):.2f} mm; heavy-spring "
             f"estimate of the first axial mode f1 = {spring:.3f} Hz",
             f"amplitude of l_A (mm), half of max - min over the last {s['window']:g} s:",
             f"{'f (Hz)':>8}" + "".join(f"{'gamma=' + format(g, 'g'):>16}" for g in GAMMAS)]
    for f in sorted(set(float(v) for v in sweep["frequency_hz"])):
        row = f"{f:>8g}"
        for g in GAMMAS:
            k = same(sweep["frequency_hz"], f) & same(sweep["gamma"], g)
            row += f"{1e3 * float(sweep['extent_amplitude_m'][k][0]):>16.3f}"
        lines.append(row)
    for g in GAMMAS:
        k = same(sweep["gamma"], g)
        peak = int(np.argmax(sweep["extent_amplitude_m"][k]))
        lines.append(f"gamma = {g:g}: largest amplitude {1e3 * sweep['extent_amplitude_m'][k][peak]:.2f} "
                     f"mm at {sweep['frequency_hz'][k][peak]:g} Hz")
    lines.append(f"(b) at {DRIVE:g} Hz, width and lean (centroid's distance from the root's "
                 "vertical), at rest -> largest over the last window (mm):")
    for g in GAMMAS:
        k = drive & same(sweep["gamma"], g)
        lines.append(f"  gamma = {g:g}: width {1e3 * float(sweep['width_rest_m'][k][0]):.2f} -> "
                     f"{1e3 * float(sweep['width_max_m'][k][0]):.2f}, lean "
                     f"{1e3 * float(sweep['lean_rest_m'][k][0]):.2f} -> "
                     f"{1e3 * float(sweep['lean_max_m'][k][0]):.2f}, l_A "
                     f"{1e3 * float(sweep['extent_min_m'][k][0]):.2f} ... "
                     f"{1e3 * float(sweep['extent_max_m'][k][0]):.2f}")
    if not quick:
        lines.append(f"convergence, gamma = 5e-11 at {DRIVE:g} Hz (amplitude of l_A, extent at rest):")
        for r in convergence(tool, outdir):
            lines.append(f"  N = {r['n']:>3}, dt = {r['dt']:>7}: {1e3 * r['amplitude']:.3f} mm, "
                         f"{1e3 * r['rest']:.3f} mm")
    p = s["pendulum"]
    lines += ["", f"(c) pendulum, 30 cm, N = {p['n']}, dt = {p['dt']} s, pushed 2 cm at 1 Hz for "
              f"one period, {p['duration']:g} s",
              f"{'preset':>8}{'nu':>9}{'tau (s)':>10}{'2 rhoS/nu':>11}{'additive':>10}"
              f"{'(1/tau-1/tau0)/(nu/2rhoS)':>27}"]
    for preset in PRESETS:
        tau0 = runs[(preset, 0)]["tau"]
        for nu in NUS:
            r = runs[(preset, nu)]
            est = 2 * r["rho_s"] / nu if nu > 0 else float("inf")
            add = 1 / (1 / tau0 + nu / (2 * r["rho_s"]))
            ratio = (1 / r["tau"] - 1 / tau0) / (nu / (2 * r["rho_s"])) if nu > 0 else float("nan")
            lines.append(f"{preset:>8}{nu:>9g}{r['tau']:>10.4f}{est:>11.4f}{add:>10.4f}{ratio:>27.4f}")
    studytool.write_summary(outdir, "study_oscillation.txt", lines)


if __name__ == "__main__":
    main()
