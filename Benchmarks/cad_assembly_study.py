#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Generated CAD-assembly study: cases from fixed seeds (oraclemesh_cases.cad_cases: 2-4 flat-faced parts
-- boxes, stepped blocks, 8/12/16-gon cylinders, thin plates, wedges with 18-27 degree edges -- on
a 1 mm grid, face to face, along edges, overlapping, nested, a cylinder's axis on a box's edge, on
the housing's faces, in a box or sphere housing, sometimes an axis-aligned cut plane through a
part's face), each meshed with `oraclemesh mesh` and every mesh checked on its own.

Per case it prints tetrahedra, vertices, min/max dihedral angle (from the written mesh; before
optimisation from the statistics), validity defects, feature coverage, the worst volume error of
the parts and of the housing against their exact volumes, the warnings, wall time.

    /usr/bin/python3 Benchmarks/cad_assembly_study.py [--cases 20] [--first 0] [--radius-edge 2]
        [--features Given|Both|...] [--set threads=2] [--jobs 2] [--work DIR] [--check]

Needs PYTHONPATH=<build>/lib/python3.11/site-packages and the `oraclemesh` command (ORACLEMESH_COMMAND,
else `python3 -m oraclemesh`). --check (the ctest version) exits 1 unless every mesh is made, has no
validity defect, keeps 100 % of its feature lines, has no tetrahedron below the sliver angle (1
degree: what refinement guarantees, docs/REFERENCE.md, "Meshing: guarantees and limits"; the optimisers never
lower the minimum), no warning about its inputs (the parts are well placed), and every material's
volume within its tolerance (see volume_tolerance).
"""
import argparse
import json
import os
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bone_implant_study import run_and_measure  # noqa: E402

from oraclemesh_cases import cad_cases  # noqa: E402
from oraclemesh.fielddata import strings  # noqa: E402

SLIVER_ANGLE = 1.0  # the mesher's default sliver_angle: no tetrahedron below it, before or after optimisation
FLAT_TOLERANCE = 1e-6  # rounding: the least tolerance of any material (see volume_tolerance)


def boundary_facets(points, tets, material, m):
    """Triangles (n x 3 x 3) bounding material m in the mesh."""
    cells = tets[material == m]
    faces = np.sort(np.concatenate([cells[:, [1, 2, 3]], cells[:, [0, 2, 3]], cells[:, [0, 1, 3]],
                                    cells[:, [0, 1, 2]]]), axis=1)
    faces, counts = np.unique(faces, axis=0, return_counts=True)
    return points[faces[counts == 1]]


def sagitta_bound(tris, radius):
    """What chords of a sphere of this radius may cut off it: a triangle inscribed with circumradius
    r lies at most r^2 / (2 R) inside (the sagitta); summed area x that."""
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    ab, ac, bc = (np.linalg.norm(v, axis=1) for v in (b - a, c - a, c - b))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    circumradius = ab * ac * bc / np.maximum(4 * area, 1e-300)
    return float(np.sum(area * circumradius ** 2 / (2 * radius)))


def volume_tolerance(case, m, tris, facet_distance, features):
    """(lower, upper) bound of the relative volume error of material m.

    - The sphere housing's facets are chords of the sphere: it may lose what they cut off (the
      sagitta bound over its boundary facets with all three vertices on the sphere), never gain.
    - Flat boundaries: every vertex the mesher puts on a face is on that plane (exact oracle
      intersections) and every sharp edge of a part is a given line, so a part alone would be exact
      up to rounding. Creases that are no given line (the box housing's edges with --features
      Given; where a part's face crosses another's or the cut plane; the lines Both finds, which
      are sampled, not exact) let a facet cut a crease; each boundary facet deviates from the
      true surface by about the facet distance at most, so the bound is facet_distance x the
      material's boundary area / its volume. Generous (measured errors are 5-50x smaller except
      at acute edges, see docs/journal/2026-12-02-performance-studies.md), but it holds by construction and catches lost or
      doubled regions.
    """
    volume = case["expected_volumes"][str(m)]
    area = float(np.sum(0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)))
    lower = upper = max(FLAT_TOLERANCE, facet_distance * area / volume)
    housing = case["housing"]
    if m == cad_cases.HOUSING_MATERIAL and housing["type"] == "sphere":
        r = np.linalg.norm(tris - np.asarray(housing["center"]), axis=2)
        on = np.all(np.abs(r - housing["radius"]) < 1e-6 * housing["radius"], axis=1)
        lower = max(lower, sagitta_bound(tris[on], housing["radius"]) / volume)
    return -lower, upper


def mesh_case(case, timeout, features=None, settings=(), tag=""):
    out = os.path.join(case["dir"], f"mesh{tag}.vtu")
    summary = os.path.join(case["dir"], f"summary{tag}.json")
    extra = ["--features", features] if features else []
    for setting in settings:
        extra += ["--set", setting]
    row = {"case": case["name"]}
    m = run_and_measure(["mesh", case["scene"], "-o", out, "--summary", summary] + extra, out, summary, timeout, row)
    if m is None:
        return row
    grid, points, tets, material, vol, stats = m["grid"], m["points"], m["tets"], m["material"], m["vol"], m["stats"]
    with open(case["scene"]) as f:
        fd = json.load(f)["mesh"]["criteria"]["facet_distance"]
    errors, bad_volumes = {}, []
    for key, exact in case["info"]["expected_volumes"].items():
        m = int(key)
        err = float(vol[material == m].sum()) / exact - 1
        lower, upper = volume_tolerance(case["info"], m, boundary_facets(points, tets, material, m), fd, features)
        errors[m] = err
        if not lower <= err <= upper:
            bad_volumes.append(f"material {m}: {100 * err:+.4f}% outside [{100 * lower:+.4f}%, {100 * upper:+.4f}%]")
    parts = [e for m, e in errors.items() if m != cad_cases.HOUSING_MATERIAL]
    row.update(part_error=max(parts, key=abs) if parts else None, housing_error=errors.get(cad_cases.HOUSING_MATERIAL),
               bad_volumes=bad_volumes, input_warnings=strings(grid.GetFieldData(), "InputWarnings"),
               warnings=strings(grid.GetFieldData(), "Warnings"),
               picking=stats.get("refinement.picking_sliver_angle"))
    return row


def make_cases(work, first, count, radius_edge):
    made = []
    for seed in range(first, first + count):
        name = f"cad_{seed:03d}"
        folder = os.path.join(work, name)
        scene = cad_cases.make_case(folder, seed, radius_edge=radius_edge)
        with open(os.path.join(folder, "case.json")) as f:
            info = json.load(f)
        made.append({"name": name, "dir": folder, "scene": scene, "info": info})
    return made


def fmt(x, spec, empty="-"):
    return empty if x is None else format(x, spec)


def describe(case):
    i = case["info"]
    parts = ",".join(f"{p['shape'][:3]}{'/thin' if p.get('thin') else ''}:{p['placement']}" for p in i["parts"])
    return f"{i['housing']['type'][:3]} {parts}{' cut' if i['cut'] else ''}"


def print_table(rows, made):
    by = {c["name"]: c for c in made}
    print(f"{'case':<8} {'tets':>7} {'verts':>6} {'min°':>6} {'before':>6} {'max°':>6} {'defects':>7} {'cover':>6} "
          f"{'parts %':>9} {'housing %':>9} {'time s':>6}  scene / notes")
    for r in rows:
        if r["error"]:
            print(f"{r['case']:<8} failed: {r['error'][:110]}   [{describe(by[r['case']])}]")
            continue
        cover = fmt(None if r["coverage"] is None else 100 * r["coverage"], ".1f")
        notes = [describe(by[r["case"]])] + r["bad_volumes"] + [f"INPUT WARNING: {w}" for w in r["input_warnings"]]
        notes += [f"warning: {w[:140]}" for w in r["warnings"] if w not in r["input_warnings"]]
        print(f"{r['case']:<8} {r['tets']:>7} {r['vertices']:>6} {r['min_dihedral']:>6.2f} {fmt(r['min_before'], '.2f'):>6} "
              f"{r['max_dihedral']:>6.1f} {r['defects']:>7} {cover:>6} {fmt(None if r['part_error'] is None else 100 * r['part_error'], '+.4f'):>9} "
              f"{fmt(None if r['housing_error'] is None else 100 * r['housing_error'], '+.4f'):>9} {r['seconds']:>6.1f}  "
              + " | ".join(notes))


def summarise(rows):
    ok = [r for r in rows if not r["error"]]
    valid = [r for r in ok if r["defects"] == 0]
    full = [r for r in ok if r["coverage"] is None or r["coverage"] >= 1 - 1e-9]
    parts = [abs(r["part_error"]) for r in ok if r["part_error"] is not None]
    housing = [abs(r["housing_error"]) for r in ok if r["housing_error"] is not None]
    return [f"{len(ok)}/{len(rows)} meshed, {len(valid)} valid, {len(full)} with 100% feature coverage, "
            f"{sum(1 for r in ok if r['input_warnings'])} with input warnings, "
            f"{sum(1 for r in ok if r['bad_volumes'])} with a volume outside its tolerance; min dihedral "
            f"{min((r['min_dihedral'] for r in ok), default=float('nan')):.2f}° (median "
            f"{np.median([r['min_dihedral'] for r in ok]) if ok else float('nan'):.2f}°; before optimisation "
            f"{min((r['min_before'] for r in ok if r['min_before'] is not None), default=float('nan')):.2f}°), "
            f"worst |volume error| parts {100 * max(parts, default=0):.2e}%, housing {100 * max(housing, default=0):.2e}%, "
            f"time {sum(r['seconds'] for r in ok):.0f} s (max {max((r['seconds'] for r in ok), default=0):.1f} s)"]


def check(rows, min_before=None):
    failures = []
    for r in rows:
        name = r["case"]
        if r["error"]:
            failures.append(f"{name}: meshing failed: {r['error']}")
            continue
        if r["defects"]:
            failures.append(f"{name}: {r['defects']} validity defects")
        if r["coverage"] is None or r["coverage"] < 1 - 1e-9:
            failures.append(f"{name}: feature coverage {r['coverage']} < 100%")
        if r["min_dihedral"] < SLIVER_ANGLE:
            failures.append(f"{name}: min dihedral {r['min_dihedral']:.3f}° < the sliver angle {SLIVER_ANGLE}°")
        if min_before is not None and (r["min_before"] is None or r["min_before"] < min_before - 1e-6):
            failures.append(f"{name}: min dihedral before optimisation {r['min_before']} < {min_before}°")
        for b in r["bad_volumes"]:
            failures.append(f"{name}: volume of {b}")
        for w in r["input_warnings"]:
            failures.append(f"{name}: warning about its inputs: {w}")
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cases", type=int, default=20, help="cases (seeds FIRST..FIRST+N-1; default 20)")
    parser.add_argument("--first", type=int, default=0, help="first seed (default 0)")
    parser.add_argument("--seeds", type=int, nargs="+", help="these seeds instead of --first/--cases")
    parser.add_argument("--radius-edge", type=float, default=2.0)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--work", help="folder for cases and meshes (default: a temporary one)")
    parser.add_argument("--check", action="store_true", help="assert validity, coverage, angles, volumes, warnings")
    parser.add_argument("--check-min-before", type=float, metavar="DEG",
                        help="with --check: also assert this smallest dihedral angle before optimisation")
    parser.add_argument("--features", choices=["None", "Given", "Automatic", "Both"],
                        help="which feature lines the mesher keeps (default: the scenes' own, Given)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a key of the scenes' mesh block, as `oraclemesh mesh --set` (repeat for several)")
    args = parser.parse_args()
    tmp = None if args.work else tempfile.TemporaryDirectory()
    work = args.work or tmp.name
    started = time.perf_counter()
    if args.seeds:
        made = [c for s in args.seeds for c in make_cases(work, s, 1, args.radius_edge)]
    else:
        made = make_cases(work, args.first, args.cases, args.radius_edge)
    tag = "_" + "_".join([args.features or "scene"] + [s.replace("=", "-") for s in args.set])
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        rows = list(pool.map(lambda c: mesh_case(c, args.timeout, args.features, args.set, tag), made))
    print(f"CAD-assembly study: {len(made)} cases, radius-edge {args.radius_edge}, criteria "
          f"{json.dumps(cad_cases.CRITERIA)}, parts {json.dumps(cad_cases.PART_CRITERIA)}, feature angle "
          f"{cad_cases.FEATURE_ANGLE}{', features ' + args.features if args.features else ''}"
          f"{''.join(', ' + s for s in args.set)}; {args.jobs} jobs at once ({time.perf_counter() - started:.0f} s in all)")
    print_table(rows, made)
    for line in summarise(rows):
        print(line)
    if args.check:
        failures = check(rows, args.check_min_before)
        for f in failures:
            print("FAILED:", f)
        return 1 if failures else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
