# SPDX-License-Identifier: GPL-3.0-or-later
"""Linear against quadratic tetrahedra (issue 11 item 2): on a unit ball, a ball in a box and the demo
scene, the volume error per material, the mid-edge nodes snapped and relaxed, the smallest Jacobian
ratio and the time the quadratic step adds (statistic time.quadratic against time.total). Prints a
Markdown table; not a test.

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/quadratic_benchmark.py [--demo]
"""
import argparse
import math
import os
import time

import oraclemesh as om

BALL = {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": 2}


def scenes(demo):
    for size in (0.3, 0.15, 0.08):
        criteria = {"cell_size": size, "facet_size": size, "facet_distance": size / 15}
        yield (f"ball, cell size {size}", {"domains": [BALL], "mesh": {"strategy": "None", "criteria": criteria,
                                                                          "seed": 1}},
               {2: 4 / 3 * math.pi})
        yield (f"ball in box, cell size {size}",
               {"domains": [BALL, {"name": "box", "type": "box", "bounds": [-1.5, 1.5] * 3, "material": 1}],
                "mesh": {"strategy": "None", "criteria": criteria, "seed": 1}},
               {2: 4 / 3 * math.pi, 1: 27 - 4 / 3 * math.pi})
    if demo:
        data = os.environ.get("ORACLEMESH_DATA", os.path.join(os.path.dirname(__file__), "..", "Data"))
        yield "demo scene", os.path.join(data, "demo", "scene.json"), {}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--demo", action="store_true", help="also the demo scene (about 160,000 tetrahedra)")
    args = parser.parse_args()
    print("| scene | tets | material | volume error linear | quadratic | snapped | relaxed | min J ratio "
          "| mesh s | quadratic s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for title, scene, exact in scenes(args.demo):
        linear = om.mesh(scene)
        started = time.perf_counter()
        quadratic = om.mesh(scene, element_order=2)
        elapsed = time.perf_counter() - started
        s = quadratic.statistics
        for m in exact or {m: None for m in quadratic.quality["materials"]}:
            lin = linear.quality["materials"][m]["volume"]
            quad = quadratic.quality["materials"][m]["volume"]
            errors = (f"{(lin - exact[m]) / exact[m]:+.2e} | {(quad - exact[m]) / exact[m]:+.2e}" if exact
                      else f"{lin:.6g} | {quad:.6g} (volumes)")
            print(f"| {title} | {quadratic.quality['tets']} | {m} | {errors} | {int(s['quadratic.snapped_nodes'])} "
                  f"| {int(s['quadratic.relaxed_nodes'])} | {s['quadratic.min_jacobian_ratio']:.3f} "
                  f"| {elapsed:.2f} | {s['time.quadratic']:.3f} |")


if __name__ == "__main__":
    main()
