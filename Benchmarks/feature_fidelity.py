#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Fidelity of the curves where inputs meet (issue 13, item 3): each scene's true intersection
curves are known analytically; the one-sided Hausdorff distance from them (sampled at 2000 points a
curve) to the mesh's interface edges that may cover it is printed (an edge counts for a curve only where it
lies on interface triangles of the curve's materials: a triple line on triangles of at least two
of its interfaces, a rim or a crease on one of the interfaces it bounds; a tetrahedron edge beside
the curve, or an edge of one interface running past the rim, does not), meshed with the given features only (none here)
and with the automatic ones (Features = Automatic), with tetrahedra, min dihedral and seconds; and
the largest distance from the centroids of the interface triangles within 2 facet distances of a
curve to the nearest input surface.
Aim: deviation <= 0.1 x facet distance, tetrahedra <= 1.2 x. The screw's rims and the box implant's
edges are creases of one input (Domain::creases), kept by Automatic too.

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/feature_fidelity.py [--scale 1]
"""
import argparse
import math
import time

import oraclemesh as om


def circle(center, normal_z, radius, n=2000):
    """A circle in the plane z = normal_z around (center x, y)."""
    return [(center[0] + radius * math.cos(2 * math.pi * k / n), center[1] + radius * math.sin(2 * math.pi * k / n),
             normal_z) for k in range(n)]


def cut_ball(h):
    c, r, z = (0.1, 0.2, 0.3), 10.0, 6.5
    scene = {"domains": [{"name": "cut", "type": "plane", "origin": [0, 0, z], "normal": [0, 0, -1], "cut": True},
                         {"name": "ball", "type": "sphere", "center": list(c), "radius": r, "material": 1}]}
    surfaces = lambda p: min(abs(math.dist(p, c) - r), abs(p[2] - z))  # noqa: E731
    return scene, [(circle(c, z, math.sqrt(r * r - (z - c[2]) ** 2)), [(-1, 1)], 1)], surfaces


def screw_in_ball(h):
    r, a, rs = 10.0, (0.5, 0.3), 3.0
    scene = {"domains": [{"name": "screw", "type": "cylinder", "center": [a[0], a[1], 0], "axis": [0, 0, 1],
                          "radius": rs, "height": 30, "material": 2},
                         {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": r, "material": 1}]}
    curves = []
    for sign in (1, -1):
        pts = []
        for k in range(2000):
            t = 2 * math.pi * k / 2000
            x, y = a[0] + rs * math.cos(t), a[1] + rs * math.sin(t)
            pts.append((x, y, sign * math.sqrt(r * r - x * x - y * y)))
        curves.append((pts, [(1, 2), (-1, 1), (-1, 2)], 2))  # where the screw enters the ball: a triple line
        curves.append((circle(a, sign * 15, rs), [(-1, 2)], 1))  # the screw's rims (creases of the cylinder)
    surfaces = lambda p: min(abs(math.dist(p, (0, 0, 0)) - r), abs(math.hypot(p[0] - a[0], p[1] - a[1]) - rs),  # noqa: E731
                             abs(abs(p[2]) - 15))
    return scene, curves, surfaces


def box_in_ball(h):
    """A box implant (first) half inside a ball: its 12 edges are creases of the box alone, seen
    beside the ball or the outside; the curve where it enters the ball is not measured here."""
    r, lo, hi = 10.0, (-3.0, -2.5, 4.0), (3.5, 2.5, 14.0)
    scene = {"domains": [{"name": "implant", "type": "box", "bounds": [lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]],
                          "material": 2},
                         {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": r, "material": 1}]}
    corners = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
    curves = []
    for c in range(8):
        for axis in range(3):
            if not c & (1 << axis):
                a, b = corners[c], corners[c | (1 << axis)]
                # a crease of the box: on its faces, beside the ball or the outside
                curves.append(([tuple(a[i] + (b[i] - a[i]) * k / 500 for i in range(3)) for k in range(501)],
                               [(1, 2), (-1, 2)], 1))

    def box_distance(p):
        d = [max(lo[i] - p[i], p[i] - hi[i]) for i in range(3)]
        outside = math.sqrt(sum(max(x, 0.0) ** 2 for x in d))
        return outside if outside > 0 else -max(d)

    surfaces = lambda p: min(abs(math.dist(p, (0, 0, 0)) - r), box_distance(p))  # noqa: E731
    return scene, curves, surfaces


def lid_on_ball(h):
    r, c2, r2 = 10.0, 12.0, 5.0
    z = (r * r + c2 * c2 - r2 * r2) / (2 * c2)
    scene = {"domains": [{"name": "lid", "type": "sphere", "center": [0, 0, c2], "radius": r2, "material": 2},
                         {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": r, "material": 1}]}
    surfaces = lambda p: min(abs(math.dist(p, (0, 0, 0)) - r), abs(math.dist(p, (0, 0, c2)) - r2))  # noqa: E731
    return scene, [(circle((0, 0), z, math.sqrt(r * r - z * z)), [(1, 2), (-1, 1), (-1, 2)], 2)], surfaces


def interface_edges(interfaces, pairs, needed):
    """The edges of the mesh's interface triangles (the mesher's port 1, cell data Materials) that
    lie on triangles of at least `needed` of the material pairs `pairs`, as an (n, 2, 3) array."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    points = vtk_to_numpy(interfaces.GetPoints().GetData())
    tris = vtk_to_numpy(interfaces.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    materials = vtk_to_numpy(interfaces.GetCellData().GetArray("Materials"))
    wanted = {tuple(sorted(p)) for p in pairs}
    on = {}
    for tri, mats in zip(tris, materials):
        pair = tuple(sorted(int(m) for m in mats))
        if pair in wanted:
            for i in range(3):
                on.setdefault(tuple(sorted((int(tri[i]), int(tri[(i + 1) % 3])))), set()).add(pair)
    edges = [e for e, kinds in on.items() if len(kinds) >= needed]
    return points[np.array(edges, dtype=int).reshape(-1, 2)]


def deviation(interfaces, curves):
    """One-sided Hausdorff distance from each curve's samples to the interface edges that may cover
    it (interface_edges); infinite when there are none."""
    import numpy as np

    worst = 0.0
    for samples, pairs, needed in curves:
        edges = interface_edges(interfaces, pairs, needed)
        if not len(edges):
            return math.inf
        a, d = edges[:, 0], edges[:, 1] - edges[:, 0]
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        for p in np.asarray(samples):
            t = np.clip(np.einsum("ij,ij->i", p - a, d) / dd, 0.0, 1.0)
            worst = max(worst, float(np.sqrt(np.min(np.sum((a + t[:, None] * d - p) ** 2, axis=1)))))
    return worst


def boundary_deviation(interfaces, curves, surfaces, near):
    """Largest distance from an interface triangle's centroid within `near` of a curve to the
    nearest input surface: how well the boundary follows the inputs next to the curves."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    points = vtk_to_numpy(interfaces.GetPoints().GetData())
    tris = vtk_to_numpy(interfaces.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    centroids = points[tris].mean(axis=1)
    samples = np.array([p for curve, _, _ in curves for p in curve[::10]])
    worst = 0.0
    for c in centroids:
        if np.min(np.linalg.norm(samples - c, axis=1)) <= near:
            worst = max(worst, surfaces(tuple(c)))
    return worst


def run(name, make, h):
    scene, curves, surfaces = make(h)
    scene["mesh"] = {"criteria": {"cell_size": h, "facet_size": h, "facet_distance": h / 4, "edge_size": h},
                     "seed": 1}
    rows = []
    for features in ("Given", "Automatic"):
        started = time.perf_counter()
        mesher = om.meshing.mesher_for(om.meshing.as_scene(scene), None, features=features)
        grid = om.update(mesher)
        seconds = time.perf_counter() - started

        interfaces = mesher.GetOutputDataObject(1)
        dev = deviation(interfaces, curves)
        near = boundary_deviation(interfaces, curves, surfaces, 2 * h / 4)
        dihedral = grid.GetCellData().GetArray("MinDihedralAngle").GetRange()[0]
        rows.append((features, grid.GetNumberOfCells(), dihedral, dev, near, seconds))
    base = rows[0][1]
    for features, tets, dihedral, dev, near, seconds in rows:
        print(f"| {name} | {features} | {tets} | {tets / base:.2f} | {dihedral:.1f} | {dev:.2e} | "
              f"{dev / (h / 4):.3f} | {near / (h / 4):.3f} | {seconds:.1f} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=float, default=1.5, help="cell, facet and edge size h (facet distance h/4)")
    args = parser.parse_args()
    print("| scene | features | tets | x | min dihedral | curve deviation | / facet distance "
          "| boundary near the curve / facet distance | s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, make in (("ball cut by a plane", cut_ball), ("screw through a ball", screw_in_ball),
                       ("lid on a ball", lid_on_ball), ("box implant in a ball", box_in_ball)):
        run(name, make, args.size)


if __name__ == "__main__":
    main()
