#!/usr/bin/env python3
"""Runs the collision benchmark and prints the side-by-side table: table look-up against
CGAL's exact answer (AABB-tree closest point + inside test) on the same random points, on
the bundled body and on its refined copy, with their ratio.

Usage: Scripts/bench_collision.py [build-dir]   (default: build)
"""
import json
import os
import subprocess
import sys

build = sys.argv[1] if len(sys.argv) > 1 else "build"
exe = os.path.join(build, "Testing", "bench_collision")
if not os.path.exists(exe):
    sys.exit(f"{exe} is missing: build first (bash Scripts/test.sh builds it)")
out = subprocess.run([exe, "--benchmark_format=json", "--benchmark_repetitions=3",
                      "--benchmark_report_aggregates_only=true"],
                     check=True, capture_output=True, text=True).stdout
runs = {b["name"]: b for b in json.loads(out)["benchmarks"] if b.get("aggregate_name") == "median"}


def get(name):
    return runs[name + "_median"]


print(f"{'mesh':<28}{'triangles':>10}{'table ns/query':>16}{'CGAL ns/query':>15}{'ratio':>8}{'table build ms':>16}")
for arg, label in ((1, "bundled body"), (6, "refined copy (x36)")):
    t, c, b = get(f"BM_TableLookup/{arg}"), get(f"BM_CgalExact/{arg}"), get(f"BM_TableBuild40x40/{arg}")
    print(f"{label:<28}{int(t['triangles']):>10}{t['cpu_time']:>16.1f}{c['cpu_time']:>15.0f}"
          f"{c['cpu_time'] / t['cpu_time']:>8.0f}{b['cpu_time']:>16.1f}")
print("(CPU time, median of 3 repetitions; points: 4096 random points around the head and neck)")
