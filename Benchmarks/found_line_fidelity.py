#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""How far the feature lines the mesher used run from the interfaces they are tagged to separate
(issue 13): every found segment of the tetrahedralizer's port 2 (Origin 1: the mesher's own
segments after its network simplification, cut at the mesh vertices on them) is sampled at its
ends and quarters, and at each sample the deviation is the radius of the smallest ball
around it that holds every material of the segment's Materials tag (-1: outside), found by sampling
the oracle (vtkOracleSampler) on boxes around the point, the smallest first (half size a twentieth
of the facet distance, then 4x larger up to 2 mm or 4 facet distances): a point on a triple line
has all three materials at once, a point on an interface both of its materials. The resolution is
an eighth of the box's half size (the finest: 0.6% of the facet distance). Per case it
prints tetrahedra, validity defects (the mesh checked again), whether the vertex budget was hit,
the found segments and how many run farther than a tenth of their facet distance (the smallest of
their materials' own, else the global one: the aim), and the worst deviation over that facet
distance with where it is and the segment's materials.

    PYTHONPATH=<build>/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/found_line_fidelity.py \
        [--cases 3] [--special face_on_voxel_boundary bbox_centre_on_face] [--radius-edge 1.3] \
        [--features Automatic] [--set KEY=VALUE] [--work DIR] [--write] [SCENE.json ...]
"""
import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np

import oraclemesh as om
from oraclemesh import fieldkeys
from oraclemesh_cases import cases
from oraclemesh.fielddata import strings
from oraclemesh.meshing import mesher_for
from oraclemesh.report import validity
from oraclemesh.scene import load_scene

SPECIAL = ("bbox_centre_on_face", "face_on_cut_plane", "face_on_voxel_boundary", "inside", "outside")
SAMPLES = 4  # pieces a segment is sampled in (its ends and quarters)
GRID = 9  # sample points per axis of a box (odd: the point itself is one)


class OracleProbe:
    """The oracle's materials on small boxes around points (one vtkOracleSampler, bounds moved)."""

    def __init__(self, scene):
        from oraclemesh import vtkOracleSampler
        self.sampler = vtkOracleSampler()
        self.sampler.SetInputConnection(scene.oracle.GetOutputPort())
        self.sampler.SetDimensions(GRID, GRID, GRID)
        t = np.linspace(-1.0, 1.0, GRID)
        # x fastest, as vtkImageData orders its points
        z, y, x = np.meshgrid(t, t, t, indexing="ij")
        self.unit = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
        self.queries = 0

    def materials(self, p, half):
        from vtkmodules.util.numpy_support import vtk_to_numpy
        self.sampler.SetBounds(p[0] - half, p[0] + half, p[1] - half, p[1] + half, p[2] - half, p[2] + half)
        self.sampler.Update()
        self.queries += GRID ** 3
        return vtk_to_numpy(self.sampler.GetOutput().GetPointData().GetArray("Material"))

    def deviation(self, p, wanted, start, largest):
        """Radius of the smallest ball around p holding every material of `wanted` (within the
        grid's resolution), from boxes of half size start, 4 start, ... up to `largest`; inf beyond."""
        half = start
        while half <= largest * (1 + 1e-9):
            labels = self.materials(p, half)
            dist = np.linalg.norm(self.unit, axis=1) * half
            inside = dist <= half
            worst = 0.0
            for m in wanted:
                hit = dist[inside & (labels == m)]
                if not len(hit):
                    worst = None
                    break
                worst = max(worst, float(hit.min()))
            if worst is not None:
                return worst
            half *= 4.0
        return float("inf")


def facet_distances(scene):
    """{material: facet distance} of the scene's mesh block, and the global one."""
    spec = scene.mesh
    default = spec.get("criteria", {}).get("facet_distance", 0.0) or 0.0
    own = {int(m): c["facet_distance"] for m, c in spec.get("materials", {}).items() if c.get("facet_distance")}
    return own, default


def segment_tolerance(materials, own, default):
    values = [own[m] for m in materials if m in own]
    return min(values) if values else default


def _setting(text):
    """KEY=VALUE -> (key, value parsed as JSON where it is JSON, else the string)."""
    key, _, value = text.partition("=")
    try:
        return key, json.loads(value)
    except json.JSONDecodeError:
        return key, value


def measure(scene_path, features, settings, write, near=None):
    """Meshes one scene in-process; returns its row (tets, defects, budget, worst deviation ...)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    scene = load_scene(scene_path, mesh_settings=dict(_setting(s) for s in settings))
    mesher = mesher_for(scene, features=features)
    started = time.perf_counter()
    grid = om.update(mesher)
    seconds = time.perf_counter() - started
    lines = mesher.GetOutputDataObject(2)
    warnings = strings(grid.GetFieldData(), "Warnings")
    row = {"scene": scene_path, "tets": grid.GetNumberOfCells(), "seconds": seconds,
           "defects": int(validity(grid)["validity.defects"]),
           "budget": any("refinement stopped at MaximumNumberOfVertices" in w for w in warnings)}
    if write:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
        out = os.path.join(os.path.dirname(scene_path), f"mesh_{features or 'scene'}.vtu")
        writer = vtkXMLUnstructuredGridWriter()
        writer.SetFileName(out)
        writer.SetInputData(grid)
        writer.Write()
        row["mesh"] = out
    points = vtk_to_numpy(lines.GetPoints().GetData()).astype(float)
    cells = vtk_to_numpy(lines.GetLines().GetData()).reshape(-1, 3)[:, 1:]
    origin = vtk_to_numpy(lines.GetCellData().GetArray(fieldkeys.ORIGIN))
    tags = vtk_to_numpy(lines.GetCellData().GetArray(fieldkeys.MATERIALS))
    own, default = facet_distances(scene)
    probe = OracleProbe(scene)
    worst = {"ratio": 0.0}
    over = 0
    seen = {}
    found = np.flatnonzero(origin == 1)
    for s in found:
        materials = [int(m) for m in tags[s] if m != -2]
        distance = segment_tolerance(materials, own, default)
        tolerance = 0.1 * distance
        a, b = points[cells[s, 0]], points[cells[s, 1]]
        n = SAMPLES
        segment_worst = 0.0
        for k in range(n + 1):
            p = a + (b - a) * (k / n)
            key = (tuple(p), tuple(materials))
            if key not in seen:  # segments share their ends
                seen[key] = probe.deviation(p, materials, 0.5 * tolerance, max(4.0 * distance, 2.0))
            d = seen[key]
            segment_worst = max(segment_worst, d)
            if d / distance > worst["ratio"]:
                worst = {"ratio": d / distance, "at": p.tolist(), "materials": materials, "distance": d,
                         "facet_distance": distance}
        over += segment_worst > tolerance * (1 + 1e-9)
    row.update(found_segments=int(len(found)), segments_over=int(over), worst=worst, queries=probe.queries)
    if near is not None:
        centre, radius = np.array(near[:3]), near[3]
        close = [(d, k) for k, d in seen.items() if np.linalg.norm(np.array(k[0]) - centre) <= radius]
        row["near"] = max(close, default=(0.0, None))[0]
    return row


def print_rows(rows):
    print(f"{'case':<28} {'tets':>8} {'defects':>7} {'budget':>6} {'found':>6} {'over':>5} {'worst/fd':>8}  where (materials)")
    for r in rows:
        w = r["worst"]
        where = (f"({w['at'][0]:.3f}, {w['at'][1]:.3f}, {w['at'][2]:.3f}) {w['materials']}, "
                 f"{w['distance']:.4f} of fd {w['facet_distance']:g}") if "at" in w else "-"
        name = os.path.basename(os.path.dirname(r["scene"])) or r["scene"]
        print(f"{name:<28} {r['tets']:>8} {r['defects']:>7} {'yes' if r['budget'] else 'no':>6} "
              f"{r['found_segments']:>6} {r['segments_over']:>5} {w['ratio']:>8.3f}  {where}"
              + (f"; near the point: {r['near']:.4f} mm" if "near" in r else ""))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", help="scene files (else generated cases)")
    parser.add_argument("--cases", type=int, default=0, help="random cases (seeds 0..N-1)")
    parser.add_argument("--special", nargs="*", default=[], choices=SPECIAL)
    parser.add_argument("--radius-edge", type=float, default=1.3)
    parser.add_argument("--features", default="Automatic", choices=["Given", "Automatic", "Both"])
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a key of the scenes' mesh block, as `oraclemesh mesh --set`")
    parser.add_argument("--work", help="folder for generated cases (default: a temporary one)")
    parser.add_argument("--write", action="store_true", help="write each mesh beside its scene (mesh_FEATURES.vtu)")
    parser.add_argument("--json", help="also write the rows to this file")
    parser.add_argument("--near", type=float, nargs=4, metavar=("X", "Y", "Z", "R"),
                        help="also print the worst deviation (mm) of the samples within R of (X, Y, Z)")
    args = parser.parse_args()
    tmp = None if args.work else tempfile.TemporaryDirectory()
    work = args.work or tmp.name
    scenes = list(args.scenes)
    specs = [(f"random_{seed:02d}", seed, "random") for seed in range(args.cases)]
    specs += [(v, 100 + SPECIAL.index(v), v) for v in args.special]  # the study's seeds
    for name, seed, variant in specs:
        scenes.append(cases.make_case(os.path.join(work, name), seed, variant=variant, radius_edge=args.radius_edge))
    rows = [measure(s, args.features, args.set, args.write, args.near) for s in scenes]
    print(f"Found-line fidelity, features {args.features}{''.join(', ' + s for s in args.set)}, "
          f"radius-edge of the scenes (generated: {args.radius_edge}); worst deviation / facet distance (aim 0.1)")
    print_rows(rows)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
