# SPDX-License-Identifier: GPL-3.0-or-later
"""Threads measured like for like: the whole call (oraclemesh.mesh: the pipeline, refinement,
optimisation, checks, output arrays), wall time, one thread against N, the same scene, criteria and
build, runs alternating (1, N, 1, N, ...) each in a fresh process so that neither gets a warm cache
or a quieter machine. Prints per case the tetrahedra, the wall seconds per 1,000 tetrahedra of
every run, the median wall seconds of each phase per thread count (statistics time.*: what stays
on one thread bounds the speed-up), and the speed-up in time per tetrahedron: the median of the
pairs' ratios and their spread (min-max). The meshes differ between thread counts (parallel refinement), hence per tet.

    /usr/bin/python3 Benchmarks/thread_scaling.py [--threads 2] [--pairs 5] [--cases demo demo_fine]

PYTHONPATH must hold the built package (build/lib/python3.11/site-packages)."""
import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DEMO = os.path.join(HERE, "..", "Data", "demo", "scene.json")

# the phases of the phase table: (column, statistic); "rest" is the wall time none of them holds
PHASES = [("oracle", "time.oracle"), ("refinement", "time.refinement"),
          ("of it sliver pass", "parallel_conforming.time_sequential_tail"), ("optimisers", "time.optimisation"),
          ("quality step", "time.improvement"), ("validity", "time.validity"), ("output", "time.output")]
TOP_LEVEL = ["time.oracle", "time.refinement", "time.optimisation", "time.improvement", "time.validity", "time.output"]

# name -> (scene file, {dotted mesh key: value} set on it)
CASES = {
    "demo": (DEMO, {}),
    "demo_fine": (DEMO, {"criteria.cell_size": 1.5, "materials.2.cell_size": 1.5}),
    "labels": (DEMO, {"criteria.cell_size": 1.2, "materials.2.cell_size": 1.2, "materials.1.cell_size": 1.2}),
}

ONE_RUN = """
import json, sys, time
import oraclemesh as om
from oraclemesh.scene import load_scene
scene = load_scene(sys.argv[1], json.loads(sys.argv[2]))
started = time.perf_counter()
result = om.mesh(scene, threads=int(sys.argv[3]))
wall = time.perf_counter() - started
s = result.statistics
print(json.dumps({"wall": wall, "tets": result.quality["tets"], "min_dihedral": result.quality["min_dihedral"],
                  "defects": s.get("validity.defects", -1), "coverage": s.get("feature_coverage", 1.0),
                  "phases": {k: v for k, v in s.items() if k.startswith("time.") or k.startswith("parallel_conforming.time")}}))
"""


def one_run(scene, settings, threads):
    out = subprocess.run([sys.executable, "-c", ONE_RUN, scene, json.dumps(settings), str(threads)],
                         capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise SystemExit(f"run failed ({threads} threads): {out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2, help="the thread count against one (default 2)")
    ap.add_argument("--pairs", type=int, default=5, help="alternating pairs of runs per case (default 5)")
    ap.add_argument("--cases", nargs="+", default=["demo", "demo_fine"], choices=sorted(CASES))
    args = ap.parse_args(argv)
    print(f"| case | threads | tets (runs) | wall s per 1,000 tets, each run | min dihedral | defects | feature coverage |")
    print("|---|---|---|---|---|---|---|")
    summary = []
    phase_rows = []
    for name in args.cases:
        scene, settings = CASES[name]
        runs = {1: [], args.threads: []}
        for _ in range(args.pairs):
            for threads in (1, args.threads):
                runs[threads].append(one_run(scene, settings, threads))
        for threads, rs in runs.items():
            phase_rows.append((name, threads, rs))
            per = [1000 * r["wall"] / r["tets"] for r in rs]
            print(f"| {name} | {threads} | {min(r['tets'] for r in rs):,}-{max(r['tets'] for r in rs):,} | "
                  + ", ".join(f"{p:.3f}" for p in per)
                  + f" | {min(r['min_dihedral'] for r in rs):.2f}° | {max(r['defects'] for r in rs):g} | "
                  f"{min(r['coverage'] for r in rs):.4f} |")
        ratios = [(a["wall"] / a["tets"]) / (b["wall"] / b["tets"]) for a, b in zip(runs[1], runs[args.threads])]
        summary.append((name, statistics.median(ratios), min(ratios), max(ratios)))
    print()
    print("Median wall seconds per phase (statistics time.*; what stays on one thread bounds the speed-up):")
    print("| case | threads | " + " | ".join(name for name, _ in PHASES) + " | rest | wall |")
    print("|---|---|" + "---|" * (len(PHASES) + 2))
    for name, threads, rs in phase_rows:
        cells = [statistics.median(r["phases"].get(key, 0.0) for r in rs) for _, key in PHASES]
        rest = statistics.median(r["wall"] - sum(r["phases"].get(k, 0.0) for k in TOP_LEVEL) for r in rs)
        print(f"| {name} | {threads} | " + " | ".join(f"{c:.2f}" for c in cells)
              + f" | {rest:.2f} | {statistics.median(r['wall'] for r in rs):.2f} |")
    print()
    print(f"| case | speed-up per tet, {args.threads} threads over 1 (median of {args.pairs} pairs) | spread |")
    print("|---|---|---|")
    for name, median, low, high in summary:
        print(f"| {name} | {median:.2f}x | {low:.2f}-{high:.2f}x |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
