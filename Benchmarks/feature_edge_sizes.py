#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""What the per-feature edge size saves (global < per material < per feature, MeshCriteria.h): an
implant (a box, material 3, its 12 edges given as feature lines) in a bone (a ball, material 1) cut
by a plane, whose rim is found automatically (Features = Both). Meshed once with one global edge
size fine enough for the implant, once with that size on the implant's material only and a coarse
global one for the bone's rim. Prints tetrahedra, feature points, the longest piece on the implant's
edges and on the rim, coverage and seconds.

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/feature_edge_sizes.py [--fine 0.25 --coarse 2]
"""
import argparse
import math
import os
import tempfile
import time

import oraclemesh as om

BALL_CENTER, BALL_RADIUS, CUT_Z = (0.1, 0.2, 0.3), 10.0, 6.5
BOX = (-2.0, 2.0, -1.5, 1.5, -4.0, 2.0)


def box_edges(path):
    """The implant's 12 edges as one polyline file."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    x, y, z = BOX[0:2], BOX[2:4], BOX[4:6]
    corners = [(x[i & 1], y[(i >> 1) & 1], z[(i >> 2) & 1]) for i in range(8)]
    points, cells = vtkPoints(), vtkCellArray()
    for c in corners:
        points.InsertNextPoint(c)
    for i in range(8):
        for bit in (1, 2, 4):
            if not i & bit:
                cells.InsertNextCell(2, [i, i | bit])
    lines = vtkPolyData()
    lines.SetPoints(points)
    lines.SetLines(cells)
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(lines)
    writer.Write()
    return path


def scene(edges_file, criteria, materials, edges_edge_size=None):
    return {"domains": [{"name": "implant", "type": "box", "bounds": list(BOX), "material": 3},
                        {"name": "cut", "type": "plane", "origin": [0, 0, CUT_Z], "normal": [0, 0, -1], "cut": True},
                        {"name": "bone", "type": "sphere", "center": list(BALL_CENTER), "radius": BALL_RADIUS,
                         "material": 1}],
            "mesh": {"seed": 1, "criteria": criteria, "materials": materials,
                     "features": {"use": "Both", "files": [edges_file if edges_edge_size is None else
                                                           {"file": edges_file, "edge_size": edges_edge_size}]}}}


def longest_feature_pieces(grid):
    """Longest mesh edge between two feature-line vertices (point data Dimension <= 1), on the
    implant's box edges and on the rim (z = CUT_Z)."""
    dimension = grid.GetPointData().GetArray("Dimension")
    on_box, on_rim = 0.0, 0.0
    seen = set()
    for c in range(grid.GetNumberOfCells()):
        ids = [grid.GetCell(c).GetPointId(k) for k in range(4)]
        for i in range(4):
            for j in range(i + 1, 4):
                a, b = sorted((ids[i], ids[j]))
                if (a, b) in seen or dimension.GetValue(a) > 1 or dimension.GetValue(b) > 1:
                    continue
                seen.add((a, b))
                p, q = grid.GetPoint(a), grid.GetPoint(b)
                length = math.dist(p, q)
                if abs(p[2] - CUT_Z) < 1e-6 and abs(q[2] - CUT_Z) < 1e-6:
                    on_rim = max(on_rim, length)
                elif len(on_box_edge(p) & on_box_edge(q)) >= 2:  # both on one box edge
                    on_box = max(on_box, length)
    return on_box, on_rim


def on_box_edge(p):
    """The box faces p lies on, as (axis, side) pairs: two or more on an edge."""
    return {(axis, side) for axis in range(3) for side in range(2) if abs(p[axis] - BOX[2 * axis + side]) < 1e-9}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fine", type=float, default=0.25, help="edge size on the implant's edges")
    parser.add_argument("--coarse", type=float, default=2.0, help="edge size on the bone's rim")
    args = parser.parse_args()
    sizes = {"cell_size": 2.0, "facet_size": 2.0, "facet_distance": 0.5}
    implant = {"cell_size": 1.0, "facet_size": 1.0, "facet_distance": 0.1}
    with tempfile.TemporaryDirectory() as folder:
        edges = box_edges(os.path.join(folder, "implant_edges.vtp"))
        runs = [("one global edge size", dict(sizes, edge_size=args.fine), {"3": implant}, None),
                ("per material (implant fine, global coarse)", dict(sizes, edge_size=args.coarse),
                 {"3": dict(implant, edge_size=args.fine)}, None),
                ("per feature (the implant's edge file fine, global coarse)", dict(sizes, edge_size=args.coarse),
                 {"3": implant}, args.fine)]
        print("| edge sizes | tetrahedra | feature points | longest piece on implant edges / rim | coverage | s |")
        print("|---|---|---|---|---|---|")
        for name, criteria, materials, own in runs:
            start = time.perf_counter()
            result = om.mesh(scene(edges, criteria, materials, own))
            seconds = time.perf_counter() - start
            st = result.statistics
            on_box, on_rim = longest_feature_pieces(result.grid)
            dimension = result.grid.GetPointData().GetArray("Dimension")
            feature_points = sum(dimension.GetValue(i) <= 1 for i in range(result.grid.GetNumberOfPoints()))
            print(f"| {name} | {int(st['tetrahedra']):,} | {feature_points:,} | "
                  f"{on_box:.3f} / {on_rim:.3f} | {100 * st['feature_coverage']:.2f} % | {seconds:.1f} |")


if __name__ == "__main__":
    main()
