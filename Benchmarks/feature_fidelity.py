#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Fidelity of the curves where inputs meet (issue 13, item 3): each scene's true intersection
curves are known analytically; the one-sided Hausdorff distance from them (sampled at 2000 points a
curve) to the mesh's interface edges is printed, meshed with the given features only (none here)
and with the automatic ones (Features = Automatic), with tetrahedra, min dihedral and seconds.
Aim: deviation <= 0.1 x facet distance, tetrahedra <= 1.2 x.

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
    return scene, [circle(c, z, math.sqrt(r * r - (z - c[2]) ** 2))]


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
        curves.append(pts)
    return scene, curves


def lid_on_ball(h):
    r, c2, r2 = 10.0, 12.0, 5.0
    z = (r * r + c2 * c2 - r2 * r2) / (2 * c2)
    scene = {"domains": [{"name": "lid", "type": "sphere", "center": [0, 0, c2], "radius": r2, "material": 2},
                         {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": r, "material": 1}]}
    return scene, [circle((0, 0), z, math.sqrt(r * r - z * z))]


def interface_edges(interfaces):
    """A locator over the edges of the mesh's interface triangles (the mesher's port 1)."""
    from vtkmodules.vtkCommonDataModel import vtkCellLocator, vtkGenericCell
    from vtkmodules.vtkFiltersCore import vtkExtractEdges

    edges = vtkExtractEdges()
    edges.SetInputData(interfaces)
    edges.Update()
    locator = vtkCellLocator()
    locator.SetDataSet(edges.GetOutput())
    locator.BuildLocator()
    return locator, vtkGenericCell(), edges  # the filter keeps its output alive


def deviation(locator_cell, curves):
    """One-sided Hausdorff distance from the curves' samples to the edges."""
    from vtkmodules.vtkCommonCore import reference

    locator, cell, _ = locator_cell
    worst = 0.0
    closest = [0.0, 0.0, 0.0]
    for curve in curves:
        for p in curve:
            cid, sid, dist2 = reference(0), reference(0), reference(0.0)
            locator.FindClosestPoint(p, closest, cell, cid, sid, dist2)
            worst = max(worst, math.sqrt(float(dist2)))
    return worst


def run(name, make, h):
    scene, curves = make(h)
    scene["mesh"] = {"criteria": {"cell_size": h, "facet_size": h, "facet_distance": h / 4, "edge_size": h},
                     "seed": 1}
    rows = []
    for features in ("Given", "Automatic"):
        started = time.perf_counter()
        mesher = om.meshing.mesher_for(om.meshing.as_scene(scene), None, features)
        grid = om.update(mesher)
        seconds = time.perf_counter() - started

        dev = deviation(interface_edges(mesher.GetOutputDataObject(1)), curves)
        dihedral = grid.GetCellData().GetArray("MinDihedralAngle").GetRange()[0]
        rows.append((features, grid.GetNumberOfCells(), dihedral, dev, seconds))
    base = rows[0][1]
    for features, tets, dihedral, dev, seconds in rows:
        print(f"| {name} | {features} | {tets} | {tets / base:.2f} | {dihedral:.1f} | {dev:.2e} | "
              f"{dev / (h / 4):.3f} | {seconds:.1f} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=float, default=1.5, help="cell, facet and edge size h (facet distance h/4)")
    args = parser.parse_args()
    print("| scene | features | tets | x | min dihedral | curve deviation | / facet distance | s |")
    print("|---|---|---|---|---|---|---|---|")
    for name, make in (("ball cut by a plane", cut_ball), ("screw through a ball", screw_in_ball),
                       ("lid on a ball", lid_on_ball)):
        run(name, make, args.size)


if __name__ == "__main__":
    main()
