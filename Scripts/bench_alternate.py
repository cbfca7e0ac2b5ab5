#!/usr/bin/python3
"""Two (or more) builds of a Google Benchmark executable, side by side on a noisy machine.

Usage: /usr/bin/python3 Scripts/bench_alternate.py ROUNDS FILTER EXE_A EXE_B [EXE_C ...]

Runs the executables in turn, ROUNDS times (A, B, A, B, ...), each with
--benchmark_filter=FILTER, 3 repetitions of at least 0.3 s, and prints per benchmark the
minimum CPU time in µs (wall time in parentheses) of each executable. Alternating whole
processes spreads this shared machine's slow periods over all of them; the minimum is the
least disturbed figure (docs/benchmarks.md, "Machine and method").
"""
import json
import subprocess
import sys


def main(argv):
    if len(argv) < 4:
        sys.exit(__doc__)
    try:
        rounds = int(argv[0])
    except ValueError:
        sys.exit(f"ROUNDS must be a whole number, not {argv[0]!r}\n\n{__doc__}")
    flt, exes = argv[1], argv[2:]
    # One column per argument, not per path: the same executable given twice is a control
    # that shows the noise between runs.
    best = [{} for _ in exes]
    for _ in range(rounds):
        for i, exe in enumerate(exes):
            run = subprocess.run([exe, f"--benchmark_filter={flt}", "--benchmark_min_time=0.3",
                                  "--benchmark_repetitions=3", "--benchmark_format=json"],
                                 capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"{exe} failed (exit {run.returncode}):\n{run.stderr}")
            for bm in json.loads(run.stdout)["benchmarks"]:
                if bm.get("run_type") != "iteration":
                    continue
                unit = {"ns": 1e-3, "us": 1.0, "ms": 1e3}[bm["time_unit"]]
                cpu, wall = bm["cpu_time"] * unit, bm["real_time"] * unit
                old = best[i].get(bm["run_name"], (float("inf"), float("inf")))
                best[i][bm["run_name"]] = (min(old[0], cpu), min(old[1], wall))
    names = list(best[0].keys())
    if not names:
        sys.exit(f"no benchmark matches {flt!r}")
    print("benchmark".ljust(40) + "".join(f"{'executable ' + str(i + 1):>22}" for i in range(len(exes))))
    for n in names:
        cells = (b.get(n, (float("nan"), float("nan"))) for b in best)
        print(n.ljust(40) + "".join(f"{c:>12.2f} ({w:>7.1f})" for c, w in cells))


if __name__ == "__main__":
    main(sys.argv[1:])
