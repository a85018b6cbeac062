#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the minimal scenes of the defects the CAD-assembly study found (see README.md here).
    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/cad_defects/make_defect_scenes.py"""
import json
import os

from oraclemesh_cases import cad_cases
from oraclemesh_cases import cases

HERE = os.path.dirname(os.path.abspath(__file__))


def box(lo, hi):
    part = {"shape": "box", "axis": 2, "poly": [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])],
            "extent": (lo[2], hi[2]), "rects": [(lo[0], hi[0], lo[1], hi[1])]}
    return part


def wedge(a, b, length):
    """Axis z; triangle (0,0), (a,0), (a,b): an edge of atan(b/a) along z."""
    return {"shape": "wedge", "axis": 2, "poly": [(0.0, 0.0), (a, 0.0), (a, b)], "extent": (0.0, length), "rects": None}


def write(name, parts, housing_bounds, mesh_extra=None, features="Given"):
    folder = os.path.join(HERE, name)
    os.makedirs(folder, exist_ok=True)
    domains = []
    for k, p in enumerate(parts):
        points, tris = cad_cases.part_surface(p)
        cases.write_surface(os.path.join(folder, f"part{k + 1}.vtp"), points, tris)
        domains.append({"name": f"part{k + 1}", "type": "surface", "file": f"part{k + 1}.vtp", "material": k + 2})
    domains.append({"name": "housing", "type": "box", "bounds": housing_bounds, "material": 1})
    scene = {"domains": domains,
             "mesh": {"criteria": {**cad_cases.CRITERIA, "cell_radius_edge_ratio": 2.0},
                      "features": {"use": features, "from_surface": [d["name"] for d in domains[:-1]],
                                   "feature_angle": cad_cases.FEATURE_ANGLE, "resample": False},
                      "seed": 1, **(mesh_extra or {})}}
    with open(os.path.join(folder, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


# 1. Two boxes face to face whose edges cross on the shared plane z = 2: the sharp edges the scene
#    asks for (from_surface of both) are refused as crossing feature lines.
write("crossing_edges", [box((0, 0, 0), (4, 2, 2)), box((1, -1, 2), (3, 3, 4))], [-3, 7, -3, 5, -2, 6])
# 2. A wedge prism with an 18.4 degree edge (every edge a feature line, 100 % covered): the thin
#    part along the edge loses volume (circumcentre labelling gives its slivers to the housing).
write("acute_wedge", [wedge(3.0, 1.0, 3.0)], [-3, 6, -3, 4, -3, 6])
