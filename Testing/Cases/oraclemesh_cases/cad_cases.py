# SPDX-License-Identifier: GPL-3.0-or-later
"""Deterministic synthetic CAD-assembly scenes: the inputs where meshers break (flat faces,
axis-aligned round coordinates, coincident faces, shared edges, a cut plane through faces).

``make_case(folder, seed, radius_edge=2.0, strategy="Conforming")`` writes into ``folder``:

  part<k>.vtp  2-4 closed, outward-oriented triangle surfaces (double precision), each a prism
               along x, y or z: a box, a stepped (L-shaped) block, a regular 8/12/16-gon
               "cylinder" (a vertex on each axis direction), or a wedge with an 18.4 or 26.6
               degree edge; sizes 0.5 (thin plates) to 8 mm, all corners of boxes, blocks and
               wedges and the cylinders' axes on a 1 mm grid (0.5 for the thin ones)
  scene.json   the parts (surfaces, materials 2.., in priority order; placed against each
               other: face to face, along an edge, overlapping, nested, a cylinder's axis on a
               box's edge, on the housing's faces), optionally an axis-aligned cut plane through
               a part's face, axis or bounding plane somewhere in the priority order, then the
               housing (material 1: a box whose faces the parts touch, or a sphere holding
               them); every part's sharp edges as feature lines (feature angle 20: the 16-gon's
               22.5 degree side edges are sharp too, so every part is exactly representable),
               Conforming, criteria scaled to the parts, and `reference_volumes`
  case.json    the parts, cut and housing, the exact volume of every material

and returns the path of scene.json. The same seed gives byte-identical files.

Exact volumes: every part is a union of convex pieces with disjoint interiors (boxes; convex
polygons extruded along one axis), the cut a half-space (a box unbounded on one side), so
priority order is resolved by inclusion-exclusion over intersections of pieces, each a box or,
when prisms along one axis take part, a convex polygon (clipped in the plane) times an interval.
Placements whose volume that cannot give (prisms along different axes overlapping) are redrawn.
The sphere housing holds the parts entirely; its volume is 4/3 pi r^3 less the cut's cap. The
only rounding is floating point (cylinder vertices are cos/sin values).

Run with the build tree's site-packages on PYTHONPATH:  python3 -m oraclemesh_cases.cad_cases OUTDIR --seed 3
                                                          python3 -m oraclemesh_cases.cad_cases --selftest
"""
import argparse
import itertools
import json
import math
import os
import sys

import numpy as np

VERSION = 1
HOUSING_MATERIAL = 1
FIRST_PART_MATERIAL = 2
FEATURE_ANGLE = 20.0  # below the 16-gon's 22.5 degree side creases: every part edge is a feature
BIG = 1.0e3  # half-spaces as boxes: far beyond every part (the parts are within 10 mm of 0)
# Where the parts go: the box housing itself (parts touch its faces), or a cube inside the sphere.
BOX_HOUSING = (-6.0, 6.0, -6.0, 6.0, -5.0, 5.0)
SPHERE_RADIUS = 10.0
SPHERE_REGION = (-5.0, 5.0, -5.0, 5.0, -5.0, 5.0)  # corners at 8.66 < 10 from the centre
MIN_LEFT = 0.15  # a part keeps at least this share of its own volume (else it is redrawn)
CRITERIA = {"facet_angle": 25.0, "facet_size": 1.5, "facet_distance": 0.1, "cell_size": 2.0, "edge_size": 1.0}
PART_CRITERIA = {"cell_size": 1.0, "facet_size": 1.0}


class NotExact(Exception):
    """Prisms along different axes overlap: their intersection is not computed here."""


# ----------------------------------------------------------------------------------------------
# Pieces: {"axis": None, "lo", "hi"} a box; {"axis": a, "poly": [(u, v)...] convex CCW, "lo", "hi"}
# a prism along axis a (u = axis a+1, v = axis a+2, cyclic, so (u, v, w) is right-handed);
# lo/hi are the bounding box.


def _box_piece(lo, hi):
    return {"axis": None, "lo": [float(v) for v in lo], "hi": [float(v) for v in hi]}


def _prism_piece(axis, poly, w0, w1):
    u, v = (axis + 1) % 3, (axis + 2) % 3
    lo, hi = [0.0] * 3, [0.0] * 3
    lo[axis], hi[axis] = float(w0), float(w1)
    lo[u], hi[u] = min(p[0] for p in poly), max(p[0] for p in poly)
    lo[v], hi[v] = min(p[1] for p in poly), max(p[1] for p in poly)
    return {"axis": axis, "poly": [(float(a), float(b)) for a, b in poly], "lo": lo, "hi": hi}


def _poly_area(poly):
    return 0.5 * sum(poly[i][0] * poly[(i + 1) % len(poly)][1] - poly[(i + 1) % len(poly)][0] * poly[i][1]
                     for i in range(len(poly)))


def _clip(subject, clipper):
    """Sutherland-Hodgman: subject polygon clipped by a convex CCW clipper polygon."""
    out = list(subject)
    for i in range(len(clipper)):
        if not out:
            return []
        a, b = clipper[i], clipper[(i + 1) % len(clipper)]

        def side(p):
            return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])

        src, out = out, []
        for j in range(len(src)):
            p, q = src[j], src[(j + 1) % len(src)]
            sp, sq = side(p), side(q)
            if sp >= 0:
                out.append(p)
            if (sp >= 0) != (sq >= 0):
                t = sp / (sp - sq)
                out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    return out


def _intersection_volume(pieces):
    lo = [max(p["lo"][k] for p in pieces) for k in range(3)]
    hi = [min(p["hi"][k] for p in pieces) for k in range(3)]
    if any(h <= l for l, h in zip(lo, hi)):
        return 0.0
    axes = {p["axis"] for p in pieces if p["axis"] is not None}
    if not axes:
        return (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])
    if len(axes) > 1:
        raise NotExact("prisms along different axes overlap")
    a = axes.pop()
    u, v = (a + 1) % 3, (a + 2) % 3
    poly = [(lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]), (lo[u], hi[v])]
    for p in pieces:
        if p["axis"] == a:
            poly = _clip(poly, p["poly"])
            if len(poly) < 3:
                return 0.0
    return max(_poly_area(poly), 0.0) * (hi[a] - lo[a])


def _common_volume(domains):
    """Volume of the intersection of domains, each a list of pieces with disjoint interiors."""
    return sum(_intersection_volume(combo) for combo in itertools.product(*domains))


def _volume_minus_union(domain, others):
    """vol(domain minus the union of others), by inclusion-exclusion."""
    total = _common_volume([domain])
    for k in range(1, len(others) + 1):
        for subset in itertools.combinations(others, k):
            total -= (-1) ** (k + 1) * _common_volume([domain, *subset])
    return total


def _union_volume(domains):
    total = 0.0
    for k in range(1, len(domains) + 1):
        for subset in itertools.combinations(domains, k):
            total += (-1) ** (k + 1) * _common_volume(list(subset))
    return total


# ----------------------------------------------------------------------------------------------
# Parts: a polygon in (u, v) extruded along an axis, its convex pieces, its triangles.


def _regular_polygon(n, r, cu, cv):
    return [(cu + r * math.cos(2 * math.pi * k / n), cv + r * math.sin(2 * math.pi * k / n)) for k in range(n)]


def part_surface(part):
    """(points, triangles) of a part: its polygon extruded along its axis, outward oriented."""
    poly, a, (w0, w1) = part["poly"], part["axis"], part["extent"]
    n = len(poly)
    local = [(x, y, w0) for x, y in poly] + [(x, y, w1) for x, y in poly]
    tris = []
    for i in range(n):
        j = (i + 1) % n
        tris += [(i, j, n + j), (i, n + j, n + i)]
    for p, q, r in _cases().ear_clip(poly):
        tris += [(p, r, q), (n + p, n + q, n + r)]
    u, v = (a + 1) % 3, (a + 2) % 3
    points = np.zeros((2 * n, 3))
    for k, (x, y, w) in enumerate(local):
        points[k, u], points[k, v], points[k, a] = x, y, w
    return points, np.array(tris, dtype=np.int64)


def _part_pieces(part):
    a, (w0, w1) = part["axis"], part["extent"]
    if part["shape"] in ("box", "stepped_block"):
        u, v = (a + 1) % 3, (a + 2) % 3
        pieces = []
        for (u0, u1, v0, v1) in part["rects"]:
            lo, hi = [0.0] * 3, [0.0] * 3
            lo[a], hi[a], lo[u], hi[u], lo[v], hi[v] = w0, w1, u0, u1, v0, v1
            pieces.append(_box_piece(lo, hi))
        return pieces
    return [_prism_piece(a, part["poly"], w0, w1)]


def _bounds(part):
    pieces = _part_pieces(part)
    return ([min(p["lo"][k] for p in pieces) for k in range(3)], [max(p["hi"][k] for p in pieces) for k in range(3)])


def _new_part(rng, shape):
    """A part at the origin (its bounding box's low corner at 0): shape, axis, poly, extent, rects."""
    axis = int(rng.integers(3))
    thin = shape in ("box", "stepped_block") and rng.random() < 0.25
    size = lambda: float(rng.choice([2.0, 3.0, 4.0, 6.0]))  # noqa: E731
    if shape == "box":
        su, sv, sw = size(), size(), (float(rng.choice([0.5, 1.0])) if thin else size())
        rects = [(0.0, su, 0.0, sv)]
        poly = [(0.0, 0.0), (su, 0.0), (su, sv), (0.0, sv)]
        extent = (0.0, sw)
        part = {"shape": "box", "thin": thin}
    elif shape == "stepped_block":
        a = float(rng.choice([4.0, 6.0]))
        a2 = a / 2
        h = float(rng.choice([0.5, 1.0])) if thin else float(rng.choice([1.0, 2.0]))
        poly = [(0.0, 0.0), (a, 0.0), (a, h), (a2, h), (a2, 2 * h), (0.0, 2 * h)]
        rects = [(0.0, a, 0.0, h), (0.0, a2, h, 2 * h)]
        extent = (0.0, size())
        part = {"shape": "stepped_block", "thin": thin}
    elif shape == "cylinder":
        n = int(rng.choice([8, 12, 16]))
        r = float(rng.choice([1.0, 2.0, 3.0]))
        poly = _regular_polygon(n, r, r, r)  # axis at (r, r): on the grid once moved by whole mm
        rects = None
        extent = (0.0, size())
        part = {"shape": "cylinder", "sides": n, "radius": r}
    elif shape == "wedge":
        a = float(rng.choice([3.0, 4.0, 6.0]))
        b = a / float(rng.choice([2.0, 3.0]))  # tip angle atan(1/2) = 26.6 or atan(1/3) = 18.4 degrees
        poly = [(0.0, 0.0), (a, 0.0), (a, b)]
        rects = None
        extent = (0.0, size())
        part = {"shape": "wedge", "tip_angle": math.degrees(math.atan2(b, a))}
    else:
        raise ValueError(shape)
    part.update(axis=axis, poly=poly, extent=extent, rects=rects)
    return part


def _moved(part, offset):
    """The part translated by offset (x, y, z)."""
    a = part["axis"]
    u, v = (a + 1) % 3, (a + 2) % 3
    du, dv, dw = offset[u], offset[v], offset[a]
    moved = dict(part)
    moved["poly"] = [(x + du, y + dv) for x, y in part["poly"]]
    moved["extent"] = (part["extent"][0] + dw, part["extent"][1] + dw)
    if part["rects"] is not None:
        moved["rects"] = [(u0 + du, u1 + du, v0 + dv, v1 + dv) for u0, u1, v0, v1 in part["rects"]]
    if "axis_point" in part:
        moved["axis_point"] = [p + o for p, o in zip(part["axis_point"], offset)]
    return moved


def _placement(rng, part, placed, region):
    """An offset (x, y, z) on the grid that puts the part against an earlier one (or free in the
    region), and how: face, edge, overlap, nested, axis_on_edge, housing_face, free."""
    lo, hi = _bounds(part)
    size = [h - l for l, h in zip(lo, hi)]
    modes = ["free", "housing_face"] + (["face", "face", "edge", "overlap", "nested"] if placed else [])
    if part["shape"] == "cylinder" and any(p["shape"] in ("box", "stepped_block") for p in placed):
        modes += ["axis_on_edge", "axis_on_edge"]
    mode = str(rng.choice(modes))
    step = 0.5 if part.get("thin") else 1.0
    # default: free, on the grid within the region
    offset = [float(region[2 * k] + step * rng.integers(0, int((region[2 * k + 1] - region[2 * k] - size[k]) / step) + 1)
                    if region[2 * k + 1] - region[2 * k] >= size[k] else region[2 * k]) - lo[k] for k in range(3)]
    if mode == "housing_face":
        k = int(rng.integers(3))
        offset[k] = (region[2 * k] - lo[k]) if rng.random() < 0.5 else (region[2 * k + 1] - hi[k])
    elif mode in ("face", "edge", "overlap", "nested"):
        other = placed[int(rng.integers(len(placed)))]
        olo, ohi = _bounds(other)
        k = int(rng.integers(3))
        for m in range(3):  # align the low corners (coincident edges), or the high ones
            offset[m] = (olo[m] - lo[m]) if rng.random() < 0.5 else (ohi[m] - hi[m])
        if mode in ("face", "edge"):
            offset[k] = (ohi[k] - lo[k]) if rng.random() < 0.5 else (olo[k] - hi[k])
            if mode == "edge":
                m = (k + 1 + int(rng.integers(2))) % 3
                offset[m] = (ohi[m] - lo[m]) if rng.random() < 0.5 else (olo[m] - hi[m])
        elif mode == "overlap":
            offset[k] += float(rng.choice([-1.0, 1.0])) * max(1.0, math.floor(size[k] / 2))
    elif mode == "axis_on_edge":
        boxes = [p for p in placed if p["shape"] in ("box", "stepped_block")]
        other = boxes[int(rng.integers(len(boxes)))]
        olo, ohi = _bounds(other)
        a = part["axis"]
        r = part["radius"]
        for m in range(3):
            if m == a:
                offset[m] = olo[m] - lo[m]  # the same extent start along the axis
            else:  # the axis (at lo + r) on the other's low or high edge
                offset[m] = (olo[m] if rng.random() < 0.5 else ohi[m]) - (lo[m] + r)
    return [float(o) for o in offset], mode


def _inside(part, region):
    lo, hi = _bounds(part)
    return all(region[2 * k] - 1e-12 <= lo[k] and hi[k] <= region[2 * k + 1] + 1e-12 for k in range(3))


def _cut_piece(cut):
    """The half-space a cut removes, as a box: axis, coordinate, side (+1: removes x_axis >= c)."""
    lo, hi = [-BIG] * 3, [BIG] * 3
    if cut["removes"] == "above":
        lo[cut["axis"]] = cut["coordinate"]
    else:
        hi[cut["axis"]] = cut["coordinate"]
    return [_box_piece(lo, hi)]


def _material_volumes(parts, cut, housing):
    """{material: exact volume} in priority order: parts, the cut at cut["priority"], the housing."""
    domains = [_part_pieces(p) for p in parts]
    order = list(range(len(parts)))
    if cut is not None:
        order.insert(cut["priority"], "cut")
    volumes, above = {}, []
    for item in order:
        if item == "cut":
            above.append(_cut_piece(cut))
            continue
        volumes[parts[item]["material"]] = _volume_minus_union(domains[item], above)
        above.append(domains[item])
    if housing["type"] == "box":
        volumes[HOUSING_MATERIAL] = _volume_minus_union([_box_piece(housing["bounds"][0::2], housing["bounds"][1::2])],
                                                        above)
    else:  # the sphere holds every part: minus the cut's cap, minus the parts outside the cut
        r = housing["radius"]
        v = 4.0 / 3.0 * math.pi * r ** 3
        in_parts = _union_volume(domains) if domains else 0.0
        if cut is not None:
            d = cut["coordinate"] - housing["center"][cut["axis"]]
            h = r - d if cut["removes"] == "above" else r + d  # the cap's height
            h = min(max(h, 0.0), 2 * r)
            v -= math.pi * h * h * (3 * r - h) / 3.0
            in_parts -= _union_volume_with(domains, _cut_piece(cut))
        volumes[HOUSING_MATERIAL] = v - in_parts
    return volumes


def _union_volume_with(domains, clip):
    """vol(union of domains intersected with clip)."""
    total = 0.0
    for k in range(1, len(domains) + 1):
        for subset in itertools.combinations(domains, k):
            total += (-1) ** (k + 1) * _common_volume([clip, *subset])
    return total


def _draw(rng):
    """One candidate assembly: (parts, cut, housing, placements); raises NotExact or ValueError."""
    sphere = rng.random() < 0.3
    housing = ({"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": SPHERE_RADIUS} if sphere
               else {"type": "box", "bounds": list(BOX_HOUSING)})
    region = SPHERE_REGION if sphere else BOX_HOUSING
    count = int(rng.integers(2, 5))
    parts, modes = [], []
    for k in range(count):
        shape = str(rng.choice(["box", "box", "stepped_block", "cylinder", "wedge"]))
        part = _new_part(rng, shape)
        for _ in range(20):
            offset, mode = _placement(rng, part, parts, region)
            moved = _moved(part, offset)
            if _inside(moved, region):
                break
        else:
            raise ValueError("no placement inside the region")
        moved["name"] = f"part{k + 1}_{shape}"
        moved["material"] = FIRST_PART_MATERIAL + k
        moved["placement"] = mode
        if shape == "cylinder":
            a = moved["axis"]
            u, v = (a + 1) % 3, (a + 2) % 3
            c = [0.0] * 3
            c[u] = sum(p[0] for p in moved["poly"]) / len(moved["poly"])
            c[v] = sum(p[1] for p in moved["poly"]) / len(moved["poly"])
            c[a] = moved["extent"][0]
            moved["axis_start"] = [round(x, 9) for x in c]
        parts.append(moved)
        modes.append(mode)
    cut = None
    if rng.random() < 0.5:
        part = parts[int(rng.integers(len(parts)))]
        lo, hi = _bounds(part)
        axis = int(rng.integers(3))
        where = str(rng.choice(["low face", "high face", "middle"]))
        c = {"low face": lo[axis], "high face": hi[axis], "middle": round((lo[axis] + hi[axis]) / 2 * 2) / 2}[where]
        cut = {"axis": axis, "coordinate": float(c), "removes": str(rng.choice(["above", "below"])),
               "through": f"{part['name']} {where}", "priority": int(rng.integers(0, len(parts) + 1))}
    volumes = _material_volumes(parts, cut, housing)
    for p in parts:
        own = _common_volume([_part_pieces(p)])
        if volumes[p["material"]] < max(MIN_LEFT * own, 0.25):
            raise ValueError(f"{p['name']} keeps too little of itself")
    if volumes[HOUSING_MATERIAL] < 10.0:
        raise ValueError("housing keeps too little")
    return parts, cut, housing, volumes


def _cases():
    """oraclemesh_cases.cases (its surface writer and ear clipping)."""
    from . import cases
    return cases


def _scene(seed, parts, cut, housing, radius_edge, strategy, volumes):
    domains = [{"name": p["name"], "type": "surface", "file": f"{p['name']}.vtp", "material": p["material"]}
               for p in parts]
    if cut is not None:
        normal = [0.0, 0.0, 0.0]
        # a plane domain is the half-space n . (p - origin) <= 0; a cut removes it
        normal[cut["axis"]] = -1.0 if cut["removes"] == "above" else 1.0
        origin = [0.0, 0.0, 0.0]
        origin[cut["axis"]] = cut["coordinate"]
        domains.insert(cut["priority"], {"name": "cut", "type": "plane", "origin": origin, "normal": normal,
                                         "cut": True})
    if housing["type"] == "box":
        domains.append({"name": "housing", "type": "box", "bounds": housing["bounds"], "material": HOUSING_MATERIAL})
    else:
        domains.append({"name": "housing", "type": "sphere", "center": housing["center"], "radius": housing["radius"],
                        "material": HOUSING_MATERIAL})
    return {
        "description": f"OracleMesh synthetic CAD assembly: seed {seed}, {len(parts)} parts in a {housing['type']}"
                       + (f", cut through {cut['through']}" if cut else ""),
        "domains": domains,
        "mesh": {
            "strategy": strategy,
            "criteria": {**CRITERIA, "cell_radius_edge_ratio": float(radius_edge)},
            "materials": {str(p["material"]): dict(PART_CRITERIA) for p in parts},
            # resample off: the edges are exact (resampling simplifies noisy networks; on CAD edges it
            # merges a small cylinder's corners and cuts its volume, docs/journal/2026-12-02-performance-studies.md)
            "features": {"from_surface": [p["name"] for p in parts], "feature_angle": FEATURE_ANGLE,
                         "resample": False},
            "seed": int(seed),
            "maximum_number_of_vertices": 200000,
        },
        "reference_volumes": {str(m): float(v) for m, v in sorted(volumes.items())},
    }


def make_case(folder, seed, *, radius_edge=2.0, strategy="Conforming"):
    """Writes one case into `folder` (created if needed); returns the path of its scene.json."""
    seed = int(seed)
    rng = np.random.default_rng([seed, 7])
    for attempt in range(200):
        try:
            parts, cut, housing, volumes = _draw(rng)
            break
        except (NotExact, ValueError):
            continue
    else:
        raise RuntimeError(f"seed {seed}: no exact assembly in 200 draws")  # a bug in the generator
    os.makedirs(folder, exist_ok=True)
    surfaces = {}
    for p in parts:
        points, tris = part_surface(p)
        volume = float(_cases().volume_exact(points, tris))
        own = _common_volume([_part_pieces(p)])
        if volume <= 0 or abs(volume - own) > 1e-9 * max(1.0, own):
            raise RuntimeError(f"{p['name']}: surface volume {volume} != pieces' {own}")  # a bug here
        _cases().write_surface(os.path.join(folder, f"{p['name']}.vtp"), points, tris)
        surfaces[p["name"]] = {"points": len(points), "triangles": len(tris), "volume": volume}
    scene = _scene(seed, parts, cut, housing, radius_edge, strategy, volumes)
    scene_path = os.path.join(folder, "scene.json")
    with open(scene_path, "w") as f:
        json.dump(scene, f, indent=2)
        f.write("\n")
    case = {
        "generator": "oraclemesh_cases.cad_cases", "version": VERSION, "seed": seed, "draws": attempt + 1,
        "radius_edge": float(radius_edge), "strategy": strategy, "housing": housing, "cut": cut,
        "parts": [{"name": p["name"], "material": p["material"], "shape": p["shape"], "axis": "xyz"[p["axis"]],
                   "placement": p["placement"], "bounds": [v for pair in zip(*_bounds(p)) for v in pair],
                   **{k: p[k] for k in ("thin", "sides", "radius", "tip_angle", "axis_start") if k in p},
                   **surfaces[p["name"]]} for p in parts],
        "expected_volumes": {str(m): float(v) for m, v in sorted(volumes.items())},
        "expected_volume_notes": "exact: pieces' inclusion-exclusion in priority order (floating point only)",
    }
    with open(os.path.join(folder, "case.json"), "w") as f:
        json.dump(case, f, indent=2)
        f.write("\n")
    return scene_path


# ----------------------------------------------------------------------------------------------
# Self-test: the exact volumes against Monte Carlo sampling of the written scene's priority rule.


def _inside_polyhedron(points, tris, q):
    """Ray parity along a skewed direction (points exactly on faces are measure zero)."""
    d = np.array([0.5773, 0.5774, 0.5775])
    d /= np.linalg.norm(d)
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    e1, e2 = b - a, c - a
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 1e-14
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = q[:, None, :] - a[None]
    u = np.einsum("qij,ij->qi", s, h) * inv
    qv = np.cross(s, e1[None])
    v = np.einsum("j,qij->qi", d, qv) * inv
    t = np.einsum("ij,qij->qi", e2, qv) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return (hit.sum(axis=1) % 2) == 1


def _selftest(seeds=range(30), samples=40000):
    failures = 0
    for seed in seeds:
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            make_case(tmp, seed)
            with open(os.path.join(tmp, "case.json")) as f:
                case = json.load(f)
            with open(os.path.join(tmp, "scene.json")) as f:
                scene = json.load(f)
            rng = np.random.default_rng(seed)
            h = case["housing"]
            if h["type"] == "box":
                lo, hi = np.array(h["bounds"][0::2]), np.array(h["bounds"][1::2])
            else:
                lo, hi = np.array(h["center"]) - h["radius"], np.array(h["center"]) + h["radius"]
            q = lo + (hi - lo) * rng.random((samples, 3))
            label = np.zeros(samples, dtype=int)
            free = np.ones(samples, dtype=bool)
            for d in scene["domains"]:
                if d["type"] == "surface":
                    reader = _read(os.path.join(tmp, d["file"]))
                    inside = np.concatenate([_inside_polyhedron(*reader, q[i:i + 4000])
                                             for i in range(0, samples, 4000)])
                elif d["type"] == "plane":
                    inside = (q - np.array(d["origin"])) @ np.array(d["normal"]) <= 0
                elif d["type"] == "box":
                    b = d["bounds"]
                    inside = np.all((q >= b[0::2]) & (q <= b[1::2]), axis=1)
                else:
                    inside = np.linalg.norm(q - d["center"], axis=1) <= d["radius"]
                take = free & inside
                label[take] = d.get("material", -1)
                free &= ~inside
            box_volume = float(np.prod(hi - lo))
            for m, v in case["expected_volumes"].items():
                mc = box_volume * np.count_nonzero(label == int(m)) / samples
                sigma = box_volume * math.sqrt(max(v / box_volume * (1 - v / box_volume), 1e-6) / samples)
                if abs(mc - v) > 5 * sigma + 1e-9:
                    failures += 1
                    print(f"seed {seed}: material {m}: exact {v:.4f}, sampled {mc:.4f} (5 sigma {5 * sigma:.4f})")
            print(f"seed {seed}: {len(case['parts'])} parts ({', '.join(p['placement'] for p in case['parts'])}), "
                  f"{h['type']}, cut {'yes' if case['cut'] else 'no'}: volumes "
                  + ", ".join(f"{m}: {v:.3f}" for m, v in case["expected_volumes"].items()))
    return failures


def _read(path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput()
    points = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    tris = vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return points, tris


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", nargs="?")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--radius-edge", type=float, default=2.0)
    parser.add_argument("--selftest", action="store_true", help="exact volumes against Monte Carlo, 30 seeds")
    args = parser.parse_args(argv)
    if args.selftest:
        return 1 if _selftest() else 0
    if not args.folder:
        parser.error("give a folder (or --selftest)")
    print(make_case(args.folder, args.seed, radius_edge=args.radius_edge))
    return 0


if __name__ == "__main__":
    sys.exit(main())
