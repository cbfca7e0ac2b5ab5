"""Strong scaling of Hair Simulation under MPI: the same run on 1 and 2 ranks (whole mpirun
processes alternated round after round) and a table of the time of a frame, the parallel
write to the shared state file included.

  /usr/bin/python3 Scripts/bench_mpi.py core build/Testing/bench_mpi_simulation [options]
  /usr/bin/python3 Scripts/bench_mpi.py pvbatch build/.../HairDynamics.so [options]
  options: [--guides 2000] [--frames 20] [--rounds 3] [--ranks 1 2] [--threads 1] [--points 16 (pvbatch: drawn per element)]
           [--out DIR] [--no-file] [--hair wavy|quadrants] [--baseline OTHER_BUILD [--baseline-args ARGS]]

`core` runs Testing/Benchmarks/bench_mpi_simulation (Core's hair::Simulation alone) and
prints where each rank's time went (stepping, waiting for the other ranks, the frame's
record, storing it); `pvbatch` runs Scripts/mpi_frames.py through pvbatch (the filter, with
ParaView's pieces and ghost strands). Both: the demo's scene (wavy guides combed on the
bundled body, the head and trunk tables, the shake and the wind, body contacts).

Per run: the median wall time of its timed frames (rank 0, between barriers); per number of
ranks, the smallest median over the rounds (the least disturbed run). Speed-up: wall time
on 1 rank over wall time on N. On a machine shared with other work the wall times carry its
load: the 1-minute load average before each run is printed.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys

parser = argparse.ArgumentParser()
parser.add_argument("kind", choices=["core", "pvbatch"])
parser.add_argument("target", help="bench_mpi_simulation (core) or the plugin (pvbatch)")
parser.add_argument("--guides", type=int, default=2000)
parser.add_argument("--frames", type=int, default=20)
parser.add_argument("--rounds", type=int, default=3)
parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
parser.add_argument("--threads", type=int, default=1)
parser.add_argument("--points", type=int, default=16)
parser.add_argument("--out", default="Output/bench_mpi")
parser.add_argument("--no-file", action="store_true", help="no state file (the frames kept in memory)")
parser.add_argument("--hair", choices=["wavy", "quadrants"], default="wavy",
                    help="core only: every guide wavy, or the four presets by quadrant of the scalp")
parser.add_argument("--baseline", help="core only: another build's bench_mpi_simulation, run alternated "
                    "with the target (before and after, side by side)")
parser.add_argument("--baseline-args", default="",
                    help="its last arguments instead of --hair (a build of format version 1-2 takes the "
                    "points per element: '16')")
args = parser.parse_args()
os.makedirs(args.out, exist_ok=True)
HERE = os.path.dirname(os.path.abspath(__file__))
mpirun = shutil.which("mpirun")

variants = [("this build", args.target, [args.hair] if args.kind == "core" else [str(args.points)])]
if args.baseline:
    variants.append(("baseline", args.baseline, args.baseline_args.split()))
results = {(v, n): [] for v, _, _ in variants for n in args.ranks}
sizes = {}
for r in range(args.rounds):
    for v, target, extra in variants:
        for n in args.ranks:
            load = os.getloadavg()[0]
            state = "-" if args.no_file else os.path.join(args.out, f"{'base_' if v == 'baseline' else ''}ranks_{n}.h5")
            cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(n)]
            if args.kind == "core":
                cmd += [target]
            else:
                cmd += [shutil.which("pvbatch"), "--symmetric", os.path.join(HERE, "mpi_frames.py"), target]
            cmd += [str(args.guides), str(args.frames), state, str(args.threads)] + extra
            done = subprocess.run(cmd, capture_output=True, text=True)
            line = [x for x in done.stdout.splitlines() if x.startswith("{")]
            if done.returncode != 0 or not line:
                sys.exit(f"the run on {n} ranks failed:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
            run = json.loads(line[-1])
            run["load"] = load
            run["median_ms"] = 1000 * statistics.median(run["wall"])
            results[(v, n)].append(run)
            if state != "-":
                sizes[(v, n)] = os.path.getsize(state)
            print(f"round {r + 1}, {v}, {n} rank(s): {run['median_ms']:.1f} ms per frame (median of "
                  f"{len(run['wall'])}), load {load:.2f}", flush=True)

for v, _, _ in variants:
    best = {n: min(results[(v, n)], key=lambda x: x["median_ms"]) for n in args.ranks}
    base = best[args.ranks[0]]
    print()
    print(f"{v}, {args.kind}: {args.guides} {args.hair if args.kind == 'core' else 'wavy'} guides, N = 10, "
          f"{'16 points per element drawn' if args.kind == 'pvbatch' else 'frames as the build stores them'}, body contacts, "
          f"{args.threads} thread(s) per rank, {len(base['wall'])} frames timed, {args.rounds} rounds alternated, "
          f"state file: {'none' if args.no_file else 'yes'}")
    print()
    print("| ranks | frame, wall (ms), best run | every run's median | speed-up | load before the best run | state file, bytes per strand per frame |")
    print("|---|---|---|---|---|---|")
    for n in args.ranks:
        b = best[n]
        runs = ", ".join("%.1f" % x["median_ms"] for x in results[(v, n)])
        per = sizes.get((v, n), 0) / args.guides / (args.frames + 1)
        print(f"| {n} | {b['median_ms']:.1f} | {runs} | {base['median_ms'] / b['median_ms']:.2f} | {b['load']:.2f} | {per:.0f} |")
    if args.kind == "core":
        print()
        print("Where each rank's time went in the best run (ms per frame, wall / CPU):")
        print()
        print("| ranks | rank | strands | step cost (model's estimate, ms) | step | waiting for the others | record | store |")
        print("|---|---|---|---|---|---|---|---|")
        for n in args.ranks:
            for k, p in enumerate(best[n]["per_rank"]):
                ms = lambda w, c=None: "%.1f" % (1000 * p[w]) + ("" if c is None else " / %.1f" % (1000 * p[c]))
                print(f"| {n} | {k} | {int(p['strands'])} | {p['cost_us'] / 1000:.1f} | {ms('step_wall', 'step_cpu')} | "
                      f"{ms('wait_wall')} | {ms('record_wall', 'record_cpu')} | {ms('store_wall', 'store_cpu')} |")
