#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The quality step (improve_angles) against its peers on the same inputs (issue 34, item 5).

The inputs of peer_benchmark.py (the demo's tibia label map; an organic closed surface of 100k
triangles; the demo's implant with its sharp edges at 60 degrees as given feature segments), at one
mesh size h per case (cell size = facet size = h, facet distance h/4, facet angle 25, radius-edge 3,
edge size h/2 for the CAD part), each tool in its own process:

  OracleMesh without the step  PeerOracleMesh --improve off (refinement and the optimisers)
  OracleMesh                   PeerOracleMesh (defaults: the quality step on, window [15, 155])
  CGAL                         PeerCgal --opt default (make_mesh_3's defaults)
  CGAL + remeshing             PeerCgal --opt remesh (then Tetrahedral_remeshing, 3 iterations, at
                               the mesh's mean edge length)
  TetGen                       tetgen -pq1.4/15 -a<V> -O9/7 on the surface (surface and CAD only)
  Gmsh                         the surface filled at edge length ~h, Gmsh's optimiser (surface and
                               CAD only; Debian's Gmsh has no Netgen optimiser)
TetGen and Gmsh keep the input's triangles (they do not remesh the surface, so near a finely
triangulated surface their tetrahedra follow its triangles, not h).

Per tool: tetrahedra, min / max dihedral angle, tetrahedra outside [15, 155], wall seconds of the
whole run, feature coverage (CAD: the sharp edges present as chains of mesh edges), volume against
OracleMesh without the step. Angles and coverage are computed here from every written mesh by the
same code.

    /usr/bin/python3 Benchmarks/quality_step.py --cgal build/bin/PeerCgal \\
        --oraclemesh build/bin/PeerOracleMesh --data Data/demo --work build/quality_step \\
        [--cases labels surface cad] [--size-factor 1]

Needs `tetgen` and `gmsh` (scripts/setup-debian.sh installs both) and PeerCgal (`cmake --build
build --target PeerCgal`).
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from label_fidelity import read_mesh as read_peer_mesh  # noqa: E402
from peer_benchmark import SIZES, criteria, prepare  # noqa: E402

WINDOW = (15.0, 155.0)
TIMEOUT = 300  # seconds for each peer run outside this project (TetGen, Gmsh)


def dihedral_range(points, tets):
    """Smallest and largest dihedral angle of each tetrahedron, degrees."""
    p = points[tets]
    faces = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))
    normals = []
    for f, (a, b, c) in enumerate(faces):
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        outward = np.einsum("ij,ij->i", n, p[:, f] - p[:, a]) > 0
        n[outward] *= -1
        normals.append(n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None])
    cosines = np.stack([-np.einsum("ij,ij->i", normals[i], normals[j]) for i in range(4) for j in range(i + 1, 4)], 1)
    angles = np.degrees(np.arccos(np.clip(cosines, -1, 1)))
    return angles.min(1), angles.max(1)


def volume(points, tets):
    p = points[tets]
    return float(np.abs(np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])).sum() / 6)


def coverage(points, tets, segments, tolerance=1e-6):
    """Share of the feature segments' length present as chains of mesh edges: the mesh vertices on
    each segment (within tolerance x its length), consecutive ones joined by a tetrahedron edge."""
    from scipy.spatial import cKDTree

    edges = set()
    for i in range(4):
        for j in range(i + 1, 4):
            a, b = np.minimum(tets[:, i], tets[:, j]), np.maximum(tets[:, i], tets[:, j])
            edges.update(zip(a.tolist(), b.tolist()))
    tree = cKDTree(points)
    total = present = 0.0
    for a, b in segments:
        length = np.linalg.norm(b - a)
        total += length
        near = tree.query_ball_point((a + b) / 2, length / 2 * (1 + 1e-9) + tolerance * length)
        on = []
        for k in near:
            t = np.dot(points[k] - a, b - a) / length ** 2
            if -tolerance <= t <= 1 + tolerance and np.linalg.norm(points[k] - (a + t * (b - a))) <= tolerance * length:
                on.append((t, k))
        on.sort()
        if not on or on[0][0] > tolerance or on[-1][0] < 1 - tolerance:
            continue
        for (t0, k0), (t1, k1) in zip(on, on[1:]):
            if (min(k0, k1), max(k0, k1)) in edges:
                present += (t1 - t0) * length
    return present / total if total else -1.0


def read_segments(path):
    rows = np.loadtxt(path)[:, 1:]
    return [(r[:3], r[3:]) for r in rows]


def run_peer(exe, case, paths, h, work, name, extra):
    out = os.path.join(work, f"{case}_{name}.bin")
    args = [exe, case, paths[case]] + ([paths["cad_features"]] if case == "cad" else []) + criteria(case, h) + \
        ["--seed", "1", "--write", out] + extra
    t0 = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True, timeout=7200)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"failed: {' '.join(args)}\n{p.stderr[-2000:]}")
    points, tets, materials = read_peer_mesh(out)
    return points, tets, materials, wall, json.loads(p.stdout.strip().splitlines()[-1])


def read_off(path):
    with open(path) as f:
        assert f.readline().strip() == "OFF"
        n, m, _ = map(int, f.readline().split())
        points = np.array([list(map(float, f.readline().split())) for _ in range(n)])
        tris = np.array([list(map(int, f.readline().split()))[1:] for _ in range(m)])
    return points, tris


def run_tetgen(off, h, work):
    """TetGen with quality (radius-edge 1.4, min dihedral 15) and its optimiser at its highest level,
    the volume bound of a regular tetrahedron of circumradius h."""
    base = os.path.join(work, "tetgen_" + os.path.basename(off))
    subprocess.run(["cp", off, base], check=True)
    max_volume = (h * (8 / 3) ** 0.5) ** 3 / (6 * 2 ** 0.5)
    t0 = time.perf_counter()
    try:
        subprocess.run(["tetgen", "-pq1.4/15", f"-a{max_volume:.6g}", "-O9/7", "-Q", base], check=True,
                       timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return None, None, TIMEOUT
    wall = time.perf_counter() - t0
    stem = base[:-4] + ".1"
    nodes = np.loadtxt(stem + ".node", skiprows=1, comments="#")[:, 1:4]
    eles = np.loadtxt(stem + ".ele", skiprows=1, comments="#", dtype=np.int64)[:, 1:5]
    first = int(np.loadtxt(stem + ".node", skiprows=1, comments="#", max_rows=1)[0])
    return nodes, eles - first, wall


def run_gmsh(off, h, work):
    """Gmsh on the input triangles as they are (Debian's Gmsh has no Netgen and cannot reparametrise
    the annular faces of the CAD part): the volume filled at edge length ~h, Gmsh's optimiser."""
    import meshio

    points, tris = read_off(off)
    stl = os.path.join(work, "gmsh_" + os.path.basename(off)[:-4] + ".stl")
    meshio.write_points_cells(stl, points, [("triangle", tris)])
    geo = stl[:-4] + ".geo"
    with open(geo, "w") as f:
        f.write(f'Merge "{os.path.basename(stl)}";\n'
                "Surface Loop(1) = {1};\nVolume(1) = {1};\n"
                f"Mesh.MeshSizeMax = {1.633 * h};\nMesh.Optimize = 1;\n")
    msh = stl[:-4] + ".msh"
    t0 = time.perf_counter()
    try:
        subprocess.run(["gmsh", geo, "-3", "-o", msh, "-v", "1"], check=True, timeout=TIMEOUT, cwd=work)
    except subprocess.TimeoutExpired:
        return None, None, TIMEOUT
    wall = time.perf_counter() - t0
    m = meshio.read(msh)
    return m.points, m.get_cells_type("tetra"), wall


def row(name, points, tets, wall, reference_volume, segments):
    if tets is None:
        return {"tool": name, "timeout": wall}
    lo, hi = dihedral_range(points, tets)
    outside = int(((lo < WINDOW[0]) | (hi > WINDOW[1])).sum())
    cov = coverage(points, tets, segments) if segments else None
    v = volume(points, tets)
    return {"tool": name, "tets": len(tets), "min": float(lo.min()), "max": float(hi.max()), "outside": outside,
            "seconds": wall, "coverage": cov, "volume": v,
            "volume_vs_reference": (v / reference_volume - 1) if reference_volume else 0.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cgal", required=True)
    ap.add_argument("--oraclemesh", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--cases", nargs="+", default=["labels", "surface", "cad"])
    ap.add_argument("--size-factor", type=float, default=1.0, help="h = SIZES[case][0] / factor")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    paths = prepare(args.data, args.work)
    results = []
    for case in args.cases:
        h = SIZES[case][0] / args.size_factor
        segments = read_segments(paths["cad_features"]) if case == "cad" else None
        rows = []
        p, t, _, wall, off = run_peer(args.oraclemesh, case, paths, h, args.work, "off", ["--improve", "off"])
        reference = volume(p, t)
        rows.append(row("OracleMesh without the step", p, t, wall, reference, segments))
        p, t, _, wall, on = run_peer(args.oraclemesh, case, paths, h, args.work, "on", [])
        rows.append(row("OracleMesh (quality step)", p, t, wall, reference, segments))
        rows[-1]["step_seconds"] = on.get("improve", 0.0)
        rows[-1]["outside_held"] = int(on.get("outside_held", 0))
        for opt, name in (("default", "CGAL Mesh_3"), ("remesh", "CGAL Mesh_3 + Tetrahedral_remeshing")):
            p, t, _, wall, _ = run_peer(args.cgal, case, paths, h, args.work, "cgal_" + opt, ["--opt", opt])
            rows.append(row(name, p, t, wall, reference, segments))
        if case != "labels":
            p, t, wall = run_tetgen(paths[case], h, args.work)
            rows.append(row("TetGen -q1.4/15 -O9/7", p, t, wall, reference, segments))
            p, t, wall = run_gmsh(paths[case], h, args.work)
            rows.append(row("Gmsh -optimize", p, t, wall, reference, segments))
        print(f"\n### {case} (h = {h:g})\n")
        print("| tool | tetrahedra | min ° | max ° | outside [15, 155] | seconds | feature coverage | volume vs OracleMesh without the step |")
        print("|---|---|---|---|---|---|---|---|")
        for r in rows:
            if "timeout" in r:
                print(f"| {r['tool']} | did not end within {r['timeout']} s | | | | | | |")
                continue
            cov = "–" if r["coverage"] is None else f"{100 * r['coverage']:.1f} %"
            print(f"| {r['tool']} | {r['tets']:,} | {r['min']:.2f} | {r['max']:.2f} | {r['outside']:,} | "
                  f"{r['seconds']:.2f} | {cov} | {100 * r['volume_vs_reference']:+.3f} % |")
        off_row, on_row = rows[0], rows[1]
        print(f"\nthe step: {on_row['tets'] / off_row['tets']:.3f}x the tetrahedra, "
              f"{on_row['seconds'] / off_row['seconds']:.2f}x the wall time ({on_row['step_seconds']:.2f} s in the step); "
              f"of the tetrahedra left outside the window, {on_row['outside_held']} have every vertex held (on feature "
              "lines, corners or where interfaces meet)")
        results.append({"case": case, "h": h, "rows": rows})
        sys.stdout.flush()
    with open(os.path.join(args.work, "results.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
