"""Study 1 of issue 6: convergence of the Super-Helix cantilever with the number of
elements N, against Euler-Bernoulli beam theory.

Run: /usr/bin/python3 Scripts/study_convergence.py build/bin/hair_study <output dir> [--quick]

A straight, round clamped rod (smooth preset, ellipticity 1, L = 10 cm, no friction, no drag)
for N = 1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40 (--quick: 2, 3, 5, 10, 20, 40),
computed by `hair_study convergence` (Tools/studies/convergence.cxx) through SuperHelix's public API:
  f1, f2   bending frequencies of the linearization about the straight rod: the
           eigenvalues of M^-1 K restricted to kappa1 (mass matrix from SuperHelix::assemble,
           K = diag(EI l_Q)); reference f = (beta L)^2 / (2 pi L^2) sqrt(EI / rho S),
           beta1 L = 1.8751041, beta2 L = 4.6940911 (Rao, Vibration of Continuous Systems,
           2007, section 11.5);
  delta    static tip deflection of the horizontal rod under gravity, E raised so that
           delta / L = 1e-3 (linear regime), reached by steps of 1 s (the semi-implicit
           step's fixed point is the static equilibrium); reference rho S g L^4 / (8 EI)
           (Gere, Mechanics of Materials, cantilever table).
Expected orders: 2 for the frequencies (piecewise-constant curvature is a midpoint-like
discretization); for the deflection the discrete equilibrium has, in linear theory, the
exact relative error -1 / (3 N^2) (derived in docs/study-convergence.md), so order 2 too,
and the script compares the measured error with that formula.

Writes to the output dir: study_convergence.csv (hair_study's columns), study_convergence.png
(relative errors against N, log-log, fitted slopes) and study_convergence.txt (summary).
"""
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import studytool  # noqa: E402

EXPECTED_SLOPE = -2.0
FIT_FROM = 5  # the fit uses N >= 5: below, the error is not yet in its asymptotic regime


def main():
    tool, outdir, quick = studytool.parse_args("study_convergence.py")
    ns = [2, 3, 5, 10, 20, 40] if quick else [1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40]
    csv_path = os.path.join(outdir, "study_convergence.csv")
    studytool.run(tool, "convergence", out=csv_path, ns=",".join(map(str, ns)))
    d = studytool.read_csv(csv_path)
    n = d["N"]
    e1 = d["f1_hz"] / d["f1_eb_hz"] - 1
    e2 = d["f2_hz"] / d["f2_eb_hz"] - 1  # NaN at N = 1 (one bending unknown)
    ed = d["deflection_m"] / d["deflection_eb_m"] - 1
    predicted = -1 / (3 * n ** 2)
    fit = n >= FIT_FROM
    s1 = studytool.slope(n[fit], e1[fit])
    s2 = studytool.slope(n[fit], e2[fit])
    sd = studytool.slope(n[fit], ed[fit])
    gap = np.max(np.abs((1 + ed) / (1 + predicted) - 1))

    # --- plot ------------------------------------------------------------------------
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    ax.loglog(n, np.abs(e1), "o-", color="tab:blue",
              label=f"first frequency f1, too high (fitted slope {s1:.3f})")
    ok2 = np.isfinite(e2)
    ax.loglog(n[ok2], np.abs(e2[ok2]), "s-", color="tab:orange",
              label=f"second frequency f2, too high (fitted slope {s2:.3f})")
    ax.loglog(n, np.abs(ed), "^-", color="tab:green",
              label=f"static tip deflection under gravity, too small (fitted slope {sd:.3f})")
    ax.loglog(n, np.abs(predicted), "k:", lw=1.5,
              label="deflection, linear theory of the discrete rod: 1/(3N²)")
    x = np.array([FIT_FROM, n.max()], float)
    y0 = 3 * np.abs(e2[fit])[0]
    ax.loglog(x, y0 * (x / x[0]) ** EXPECTED_SLOPE, "k-", lw=1, alpha=0.6,
              label="reference slope −2")
    ax.axvspan(FIT_FROM, n.max(), color="0.94", zorder=0, label=f"fit range N ≥ {FIT_FROM}")
    ax.set_xlabel("number of elements N")
    ax.set_ylabel("|relative error| against Euler–Bernoulli (–)")
    ax.set_title("Super-Helix cantilever, L = 10 cm: convergence with N\n"
                 "(frequencies of the linearization; static deflection at δ/L = 10⁻³)")
    ax.set_xticks(ns)
    ax.set_xticklabels([str(v) for v in ns])
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_convergence.png"), dpi=120)

    # --- summary ---------------------------------------------------------------------
    lines = ["Super-Helix cantilever against Euler-Bernoulli (smooth preset, round, L = 0.1 m)",
             f"N = {', '.join(str(int(v)) for v in n)}" + (" (quick)" if quick else ""),
             f"f1_EB = {d['f1_eb_hz'][0]:.6g} Hz, f2_EB = {d['f2_eb_hz'][0]:.6g} Hz, "
             f"delta_EB = {d['deflection_eb_m'][0]:.6g} m (delta/L = 1e-3)", "",
             f"{'N':>4}{'f1 err':>13}{'f2 err':>13}{'delta err':>13}{'-1/(3N^2)':>13}{'steps':>7}"]
    for i in range(len(n)):
        lines.append(f"{int(n[i]):>4}{e1[i]:>13.4e}{e2[i]:>13.4e}{ed[i]:>13.4e}"
                     f"{predicted[i]:>13.4e}{int(d['static_steps'][i]):>7}")
    lines += ["",
              f"fitted slopes of log|relative error| against log N, N >= {FIT_FROM} "
              f"(expected {EXPECTED_SLOPE:.0f}):",
              f"  f1 {s1:.3f}, f2 {s2:.3f}, static deflection {sd:.3f}",
              "deflection against the discrete rod's linear theory delta_N = delta_EB (1 - 1/(3N^2)):",
              f"  largest |delta_N / (delta_EB (1 - 1/(3N^2))) - 1| = {gap:.2e} "
              "(geometric nonlinearity O((delta/L)^2) = 1e-6 and the stopping test)"]
    studytool.write_summary(outdir, "study_convergence.txt", lines)


if __name__ == "__main__":
    main()
