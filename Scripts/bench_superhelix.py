#!/usr/bin/python3
"""Where the time of a Super-Helix step goes, as a picture: runs bench_superhelix
(Testing/Benchmarks/bench_superhelix.cxx) for one step against N for the four presets and
for the phases of a step (wavy strand), prints the two tables and draws

  left:  CPU µs per step against N (log-log), the four presets, the issue's goal of 25 µs
         at N = 10, and slopes N¹, N², N³ for reference;
  right: the share of each phase of one step of the wavy strand against N.

Usage: /usr/bin/python3 Scripts/bench_superhelix.py [build-dir] [output.png] [--runs K]
                                                    [--json FILE]
  build-dir   default build (the benchmark is <build>/Testing/bench_superhelix)
  output.png  default docs/images/bench-superhelix.png
  --runs K    run the whole benchmark K times (default 3), about a minute each
  --json FILE read the results of an earlier run instead of running the benchmark, e.g.
              bench_superhelix --benchmark_filter='BM_Step/|BM_Phase' --benchmark_format=json

Each figure is the minimum CPU time over K runs of 3 repetitions. This machine is shared
and its disturbances come in bursts of seconds: within one run, the three repetitions of a
benchmark follow each other and a burst can spoil all three (measured: smooth at N = 10
read 21.7 µs in one run and 36.1 µs in the next). Whole runs apart are disturbed at other
places, so the minimum over runs is the least disturbed figure.
"""
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PRESETS = ["smooth", "wavy", "curly", "fuzzy"]
NS = [1, 2, 5, 10, 20, 40]
PHASES = [("Reconstruct", "reconstruction"), ("AssembleMassAndForce", "M and f"),
          ("VelocityJacobian", "velocity Jacobian C"), ("TensionStiffness", "tension stiffness K_T"),
          ("Solve", "LU solve")]


def option(argv, name):
    """The value after --name (and argv without both), or None."""
    if name not in argv:
        return None, argv
    i = argv.index(name)
    if i + 1 >= len(argv):
        sys.exit(f"{name} needs a value")
    return argv[i + 1], argv[:i] + argv[i + 2:]


def load(argv):
    json_file, argv = option(argv, "--json")
    runs, argv = option(argv, "--runs")
    try:
        runs = 3 if runs is None else int(runs)
    except ValueError:
        runs = 0
    if runs < 1:
        sys.exit("--runs needs a whole number >= 1")
    args = [a for a in argv if not a.startswith("--")]
    build = args[0] if args else "build"
    png = args[1] if len(args) > 1 else os.path.join("docs", "images", "bench-superhelix.png")
    if json_file:
        with open(json_file) as f:
            return [json.load(f)], png
    exe = os.path.join(build, "Testing", "bench_superhelix")
    if not os.path.exists(exe):
        sys.exit(f"{exe} is missing: build it first (cmake --build {build} --target bench_superhelix)")
    results = []
    for r in range(runs):
        print(f"run {r + 1} of {runs} ...", file=sys.stderr, flush=True)
        out = subprocess.run([exe, "--benchmark_filter=BM_Step/|BM_Phase",
                              "--benchmark_min_time=0.2", "--benchmark_repetitions=3",
                              "--benchmark_format=json"],
                             check=True, capture_output=True, text=True).stdout
        results.append(json.loads(out))
    return results, png


def minima(runs):
    best = {}
    for results in runs:
        for b in results["benchmarks"]:
            if b.get("run_type") != "iteration":
                continue
            scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}[b["time_unit"]]
            name = b["run_name"]
            best[name] = min(best.get(name, float("inf")), b["cpu_time"] * scale)
    return best


def main():
    results, png = load(sys.argv[1:])
    t = minima(results)
    step = {p: [t.get(f"BM_Step/{i}/{n}") for n in NS] for i, p in enumerate(PRESETS)}
    phase = {key: [t.get(f"BM_Phase_{key}/{n}") for n in NS] for key, _ in PHASES}
    if any(v is None for row in step.values() for v in row):
        sys.exit("the results lack some BM_Step/<preset>/<N>; run the benchmark with "
                 "--benchmark_filter='BM_Step/|BM_Phase'")
    print(f"CPU µs per step (minimum over {len(results)} run(s) of 3 repetitions)")
    print(f"{'N':>4}" + "".join(f"{p:>10}" for p in PRESETS))
    for j, n in enumerate(NS):
        print(f"{n:>4}" + "".join(f"{step[p][j]:>10.1f}" for p in PRESETS))
    have_phases = all(v is not None for row in phase.values() for v in row)
    if have_phases:
        print("\nphases of one step, wavy strand, CPU µs")
        print(f"{'N':>4}" + "".join(f"{label[:14]:>16}" for _, label in PHASES))
        for j, n in enumerate(NS):
            print(f"{n:>4}" + "".join(f"{phase[key][j]:>16.2f}" for key, _ in PHASES))

    fig, axes = plt.subplots(1, 2, figsize=(12, 5.4))
    ax = axes[0]
    for p in PRESETS:
        ax.loglog(NS, step[p], "o-", label=p)
    ref = step["wavy"][NS.index(10)]
    for power, style, name in ((1, ":", "∝ N"), (2, "--", "∝ N²"), (3, "-.", "∝ N³")):
        ax.loglog(NS, [ref * (n / 10) ** power for n in NS], "k" + style, lw=0.8, label=name)
    ax.axhline(25, color="red", lw=0.8)
    ax.plot([10], [25], "r*", ms=12, label="goal: 25 µs at N = 10")
    ax.set_xlabel("elements N (30 cm strand)")
    ax.set_ylabel("CPU µs per step of 1/30 s")
    ax.set_title("One Super-Helix step (head shaking ±30° at 3 Hz)")
    ax.set_ylim(2, 2000)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    if have_phases:
        x = list(range(len(NS)))
        totals = [sum(phase[key][j] for key, _ in PHASES) for j in range(len(NS))]
        bottom = [0.0] * len(NS)
        for key, label in PHASES:
            share = [100 * v / tot for v, tot in zip(phase[key], totals)]
            ax.bar(x, share, bottom=bottom, label=label)
            bottom = [b + v for b, v in zip(bottom, share)]
        for j, tot in enumerate(totals):
            ax.text(j, 101, f"{tot:.0f} µs", ha="center", va="bottom", fontsize=8)
        ax.set_xticks(x)
        ax.set_xticklabels([str(n) for n in NS])
        ax.set_ylim(0, 112)
        ax.set_xlabel("elements N")
        ax.set_ylabel("share of the step's phases (%)")
        ax.set_title("Where the time goes (wavy strand; sum of the phases on top)")
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3)
    fig.tight_layout()
    os.makedirs(os.path.dirname(png) or ".", exist_ok=True)
    fig.savefig(png, dpi=110)
    print(f"\npicture: {png}")


if __name__ == "__main__":
    main()
