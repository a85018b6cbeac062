#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Where the whole process of a small mesh goes (issue 12, item 2): `oraclemesh mesh` on two coarse
cases of about 15-20k tetrahedra, each run in its own process, and what it spends outside the mesher.

Cases (the peer benchmark's criteria, Benchmarks/peer_benchmark.py, h = its smallest size):
  labels  the demo's tibia label map (Data/demo/tibia_labels.vti), h = 4, no feature lines
  cad     the demo's implant (Data/demo/implant.vtp) with its sharp edges at 60 degrees, h = 2

Per case, medians of --repeat runs:
  process        `oraclemesh mesh SCENE -o OUT.vtu` (mesh, report, .vtu): wall and CPU seconds
                 (user + system, from the child's rusage) and peak RSS
  floor          `python3 -c "import oraclemesh.__main__"`: what the command costs before any input
                 is read (interpreter, the package, VTK, the wrapped module)
  mesher         the meshing call inside (statistics time.total; CPU: cpu.refinement + cpu.optimisation)
  rest           process - floor - mesher: reading, the oracle, feature lines, report, writers

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/small_cases.py \\
        --oraclemesh build/bin/oraclemesh [--work DIR] [--repeat 5] [--cases labels cad]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(HERE), "Data", "demo")


def scenes(work):
    criteria = {"facet_angle": 25, "cell_radius_edge_ratio": 3}
    labels = {"domains": [{"name": "tibia", "type": "labelmap", "file": os.path.join(DATA, "tibia_labels.vti"),
                           "array": "labels", "background": 0}],
              "mesh": {"criteria": dict(criteria, cell_size=4, facet_size=4, facet_distance=1), "seed": 1}}
    cad = {"domains": [{"name": "implant", "type": "surface", "file": os.path.join(DATA, "implant.vtp"), "material": 1}],
           "mesh": {"criteria": dict(criteria, cell_size=2, facet_size=2, facet_distance=0.5, edge_size=1),
                    "features": {"from_surface": "implant", "feature_angle": 60}, "seed": 1}}
    paths = {}
    for name, scene in (("labels", labels), ("cad", cad)):
        paths[name] = os.path.join(work, name + ".json")
        with open(paths[name], "w") as f:
            json.dump(scene, f, indent=1)
    return paths


def run(args, env=None):
    """Wall seconds, CPU seconds (user + system) and peak RSS (bytes) of one child process."""
    started = time.perf_counter()
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - started
    err = p.stderr.read().decode()
    p.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("failed: %s\n%s" % (" ".join(args), err[-2000:]))
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024


def mesher_seconds(vtu):
    from oraclemesh.meshfiles import read_mesh
    from oraclemesh.report import statistics as stats

    s = stats(read_mesh(vtu))
    return s["time.total"], s.get("cpu.refinement", 0.0) + s.get("cpu.optimisation", 0.0), int(s["tetrahedra"])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--oraclemesh", required=True, help="build/bin/oraclemesh")
    ap.add_argument("--work", default=None, help="folder for the scenes and meshes (default: a temporary one)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--cases", nargs="+", default=["labels", "cad"], choices=["labels", "cad"])
    a = ap.parse_args()
    if a.work is None:  # never into the caller's working directory
        import tempfile

        a.work = tempfile.mkdtemp(prefix="small_cases_")
    os.makedirs(a.work, exist_ok=True)
    paths = scenes(a.work)
    python = sys.executable
    floor = [run([python, "-c", "import oraclemesh.__main__"]) for _ in range(a.repeat)]
    med = lambda rows, i: statistics.median(r[i] for r in rows)  # noqa: E731
    print("| case | tets | process wall s | process CPU s | peak RSS MiB | floor wall / CPU s | floor RSS MiB "
          "| mesher wall / CPU s | rest wall / CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for case in a.cases:
        out = os.path.join(a.work, case + ".vtu")
        rows, inner = [], []
        for _ in range(a.repeat):
            rows.append(run([a.oraclemesh, "mesh", paths[case], "-o", out]))
            inner.append(mesher_seconds(out))
        pw, pc, pr = med(rows, 0), med(rows, 1), med(rows, 2)
        fw, fc, fr = med(floor, 0), med(floor, 1), med(floor, 2)
        mw, mc = med(inner, 0), med(inner, 1)
        print("| %s | %s | %.2f | %.2f | %.0f | %.2f / %.2f | %.0f | %.2f / %.2f | %.2f / %.2f |" % (
            case, f"{inner[0][2]:,}", pw, pc, pr / 2**20, fw, fc, fr / 2**20, mw, mc, pw - fw - mw, pc - fc - mc),
            flush=True)
    print("(medians of %d runs; load average %.1f)" % (a.repeat, os.getloadavg()[0]))


if __name__ == "__main__":
    main()
