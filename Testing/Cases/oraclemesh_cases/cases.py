# SPDX-License-Identifier: GPL-3.0-or-later
"""Deterministic synthetic bone/implant test scenes (for studies and regression tests).

``make_case(folder, seed, variant=..., radius_edge=1.3, strategy="Conforming")`` writes into
``folder``:

  bone_labels.vti  label map of a long-bone shaft (femur/tibia-like), 0.75 mm isotropic voxels,
                   point data "labels" (uint8): 0 background, 1 cortical shell, 2 cancellous core
  implant.vtp      closed, outward-oriented triangle surface of a CAD-like implant (flat faces,
                   sharp edges), double-precision points
  scene.json       implant (surface, material 3) > resection (plane, cut) > bone (labelmap)
                   and the mesh block (the paper's criteria in mm); implant only for "implant_only"
  case.json        the exact parameters (seed, variant, bone, cut plane, implant pose) and the
                   expected volumes (the implant's exact, the bone's approximate)

and returns the path of scene.json. The same seed gives byte-identical files. For one seed every
variant has the same bone and cut plane; "implant_only" has the "random" variant's implant.

Run with the build tree's site-packages on PYTHONPATH (the package sits beside oraclemesh there):
    python3 -m oraclemesh_cases.cases OUTDIR --seed 3 [--variant all]
    python3 -m oraclemesh_cases.cases --selftest
"""
import argparse
import json
import math
import os
import sys
from fractions import Fraction

import numpy as np

VARIANTS = ("random", "bbox_centre_on_face", "face_on_cut_plane", "face_on_voxel_boundary", "inside", "outside",
            "implant_only")
STRATEGIES = ("Conforming", "None", "ProtectingBalls")
VERSION = 1

# Label map grid. All values are dyadic, so voxel centres and voxel boundaries (centre + 0.375)
# are exact doubles.
SPACING = 0.75
ORIGIN = (-24.0, -22.5, -3.0)
DIMS = (65, 61, 101)  # x, y, z
LABEL_NAMES = {"1": "cortical bone", "2": "cancellous bone"}
IMPLANT_MATERIAL = 3
MARGIN = 1.5  # mm between the implant and the bone surface / cut for "inside" and "outside" (2 voxels)
SAMPLE_STEP = 0.5  # mm, implant interior samples for the placement checks

# Implant (local frame, mm, w up; stem pointing down -w): rectangle half-sizes (x, y) at heights w.
# Tip bottom, top of the tip's chamfer, top of the tapered stem, collar bottom, collar top.
STEM_LOOPS = (((1.5, 1.0), -12.0), ((2.25, 1.75), -11.0), ((3.5, 2.75), 0.0), ((6.0, 5.0), 0.0), ((6.0, 5.0), 2.0))
# face_on_voxel_boundary: collar sizes and stem length are multiples of the voxel size, so every
# axis-aligned face lands on a voxel boundary once one does.
VOXEL_STEM_LOOPS = (((1.5, 1.0), -12.0), ((2.25, 1.75), -11.0), ((3.5, 2.75), 0.0), ((6.0, 5.25), 0.0),
                    ((6.0, 5.25), 2.25))


# ----------------------------------------------------------------------------------------------
# Bone


def _bone_params(rng):
    u = rng.uniform
    return {
        "semi_axes": [13.0 + u(-0.75, 0.75), 11.0 + u(-0.75, 0.75)],  # shaft, before ripple and flare
        "ripple": [0.03, u(0.0, 2 * math.pi)],  # relative amplitude, phase: slow variation along z
        "flare": [u(4.0, 5.5), u(3.0, 4.5)],  # added to the semi-axes at the proximal end
        "flare_start": u(38.0, 44.0),
        "flare_length": 25.0,
        "bow": [u(-1.5, 1.5), u(-1.0, 1.0)],  # axis curvature: centre offset range (mm)
        "length": 70.0,  # distal end at z = 0, top of the dome at z = length
        "dome": 0.006,  # top(x, y) = length - dome * r^2
        "cortex": [u(2.5, 3.0), u(2.0, 2.4)],  # shell thickness in the shaft, at the flare
    }


def _smoothstep(s):
    s = np.clip(s, 0.0, 1.0)
    return s * s * (3 - 2 * s)


def _bone_geometry(p, z):
    """Axis centre (cx, cy), semi-axes (a, b) and cortex thickness at heights z."""
    z = np.asarray(z, dtype=float)
    s = z / p["length"]
    cx = p["bow"][0] * (4 * s * (1 - s) - 0.5)
    cy = p["bow"][1] * (4 * s * (1 - s) - 0.5)
    ripple = 1 + p["ripple"][0] * np.sin(2 * math.pi * s + p["ripple"][1])
    f = _smoothstep((z - p["flare_start"]) / p["flare_length"])
    a = p["semi_axes"][0] * ripple + p["flare"][0] * f
    b = p["semi_axes"][1] * ripple + p["flare"][1] * f
    wall = p["cortex"][0] + (p["cortex"][1] - p["cortex"][0]) * f
    return cx, cy, a, b, wall


def _grid_axes():
    return [ORIGIN[k] + SPACING * np.arange(DIMS[k]) for k in range(3)]


def _bone_labels(p):
    x, y, z = _grid_axes()
    cx, cy, a, b, wall = (v[:, None, None] for v in _bone_geometry(p, z))
    Z, Y, X = np.meshgrid(z, y, x, indexing="ij")  # z slowest: VTK's x-fastest point order
    dx, dy = X - cx, Y - cy
    top = p["length"] - p["dome"] * (dx * dx + dy * dy)
    outer = ((dx / a) ** 2 + (dy / b) ** 2 <= 1.0) & (Z >= 0.0) & (Z <= top)
    inner = ((dx / (a - wall)) ** 2 + (dy / (b - wall)) ** 2 <= 1.0) & (Z >= wall) & (Z <= top - wall)
    labels = np.zeros(X.shape, dtype=np.uint8)
    labels[outer] = 1
    labels[inner & outer] = 2
    return labels


def _bone_radius(p, pts):
    """Elliptic radius of points (1 on the bone's outer surface) and the smaller semi-axis there."""
    cx, cy, a, b, _ = _bone_geometry(p, pts[:, 2])
    return np.sqrt(((pts[:, 0] - cx) / a) ** 2 + ((pts[:, 1] - cy) / b) ** 2), np.minimum(a, b)


# ----------------------------------------------------------------------------------------------
# Resection plane: normal (tx, ty, -1) through (0, 0, z0), tx and ty multiples of 1/256 so that
# points on it can be exact doubles (face_on_cut_plane). A plane domain contains the side its
# normal points away from (README): this one contains, i.e. removes, the bone above it.


def _cut_params(rng):
    tilt = math.acos(rng.uniform(math.cos(math.radians(15.0)), 1.0))  # uniform on the 15 degree cap
    phi = rng.uniform(0.0, 2 * math.pi)
    tx = round(math.tan(tilt) * math.cos(phi) * 256) / 256
    ty = round(math.tan(tilt) * math.sin(phi) * 256) / 256
    z0 = round(rng.uniform(56.0, 60.0) * 8) / 8
    return {"origin": [0.0, 0.0, z0], "normal": [tx, ty, -1.0],
            "tilt_degrees": math.degrees(math.atan(math.hypot(tx, ty)))}


def _cut_height(cut, x, y):
    return cut["origin"][2] + cut["normal"][0] * x + cut["normal"][1] * y


def _below_cut(cut, pts):
    """Signed distance below the cut plane (> 0: kept bone side)."""
    n = np.asarray(cut["normal"])
    return (pts - np.asarray(cut["origin"])) @ n / np.linalg.norm(n)


# ----------------------------------------------------------------------------------------------
# Implant solids: points, triangles (outward, shared corners, no T-junctions) and convex
# hexahedral parts (VTK corner order) whose union is the solid, for sampling and inside tests.


def _rect(hx, hy, w):
    return [(-hx, -hy, w), (hx, -hy, w), (hx, hy, w), (-hx, hy, w)]  # counter-clockwise from above


def _loft(loops):
    """Closed solid through rectangles (counter-clockwise from above, bottom to top). Consecutive
    rectangles at one height make a planar annulus (the collar's underside); quads between
    axis-aligned rectangles are planar, so the faces are flat."""
    rects = [_rect(hx, hy, w) for (hx, hy), w in loops]
    points = [p for r in rects for p in r]
    tris, parts = [], []
    for k in range(len(rects) - 1):
        lo, hi = 4 * k, 4 * (k + 1)
        for i in range(4):
            j = (i + 1) % 4
            tris += [(lo + i, lo + j, hi + j), (lo + i, hi + j, hi + i)]
        if rects[k + 1][0][2] > rects[k][0][2]:
            parts.append(rects[k] + rects[k + 1])
    top = 4 * (len(rects) - 1)
    tris += [(0, 2, 1), (0, 3, 2), (top, top + 1, top + 2), (top, top + 2, top + 3)]
    return np.array(points, dtype=float), np.array(tris, dtype=np.int64), np.array(parts, dtype=float)


def ear_clip(poly):
    """Triangles (index triples, counter-clockwise) of a simple counter-clockwise polygon."""
    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    idx, tris = list(range(len(poly))), []
    while len(idx) > 3:
        for k in range(len(idx)):
            i0, i1, i2 = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            a, b, c = poly[i0], poly[i1], poly[i2]
            if cross(a, b, c) <= 0:
                continue  # reflex corner
            if any(cross(a, b, poly[m]) >= 0 and cross(b, c, poly[m]) >= 0 and cross(c, a, poly[m]) >= 0
                   for m in idx if m not in (i0, i1, i2)):
                continue
            tris.append((i0, i1, i2))
            del idx[k]
            break
        else:
            raise ValueError("polygon is not simple")
    return tris + [tuple(idx)]


def _prism(poly, z0, z1, boxes):
    """Closed solid: a counter-clockwise polygon in xy extruded from z0 to z1; `boxes` are its
    convex parts as (xmin, xmax, ymin, ymax)."""
    n = len(poly)
    points = [(x, y, z0) for x, y in poly] + [(x, y, z1) for x, y in poly]
    tris = []
    for i in range(n):
        j = (i + 1) % n
        tris += [(i, j, n + j), (i, n + j, n + i)]
    for a, b, c in ear_clip(poly):
        tris += [(a, c, b), (n + a, n + b, n + c)]
    parts = [[(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1),
              (x0, y1, z1)] for x0, x1, y0, y1 in boxes]
    return np.array(points, dtype=float), np.array(tris, dtype=np.int64), np.array(parts, dtype=float)


def _stepped_block(a, a2, h, b):
    """An L-shaped block: [0,a]x[0,h] plus [0,a2]x[h,2h] in xy, extruded over z in [0,b]. With
    a2 < a/2 its bounding-box centre (a/2, h, b/2) is inside the step face y = h, x in [a2, a]."""
    poly = [(0.0, 0.0), (a, 0.0), (a, h), (a2, h), (a2, 2 * h), (0.0, 2 * h)]
    return _prism(poly, 0.0, b, [(0.0, a, 0.0, h), (0.0, a2, h, 2 * h)])


def _loft_volume(loops):
    """Analytic volume (prismatoid rule, exact for linearly interpolated rectangles)."""
    v = 0.0
    for ((hx0, hy0), w0), ((hx1, hy1), w1) in zip(loops, loops[1:]):
        v += (w1 - w0) / 6 * (4 * hx0 * hy0 + 4 * (hx0 + hx1) * (hy0 + hy1) + 4 * hx1 * hy1)
    return v


def volume_exact(points, tris):
    """Exact signed volume of the stored polyhedron (divergence theorem in rationals)."""
    P = [tuple(Fraction(float(c)) for c in p) for p in points]
    total = Fraction(0)
    for i, j, k in tris:
        a, b, c = P[i], P[j], P[k]
        total += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                  + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return total / 6


def _centroid(points, tris):
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    v = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6
    return ((a + b + c) / 4 * v[:, None]).sum(axis=0) / v.sum()


def _samples(parts, step=SAMPLE_STEP):
    """Points filling the convex parts (trilinear maps of a grid on the unit cube)."""
    out = []
    for h in parts:
        size = max(np.linalg.norm(h[1] - h[0]), np.linalg.norm(h[3] - h[0]), np.linalg.norm(h[4] - h[0]),
                   np.linalg.norm(h[6] - h[2]))
        t = np.linspace(0.0, 1.0, max(2, int(math.ceil(size / step)) + 1))
        W, V, U = np.meshgrid(t, t, t, indexing="ij")
        U, V, W = U.ravel()[:, None], V.ravel()[:, None], W.ravel()[:, None]
        bottom = (1 - V) * ((1 - U) * h[0] + U * h[1]) + V * ((1 - U) * h[3] + U * h[2])
        top = (1 - V) * ((1 - U) * h[4] + U * h[5]) + V * ((1 - U) * h[7] + U * h[6])
        out.append((1 - W) * bottom + W * top)
    return np.concatenate(out)


_HEX_FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


def _inside_parts(parts, pts):
    """Points in the union of the convex parts (closed, up to rounding)."""
    inside = np.zeros(len(pts), dtype=bool)
    for h in parts:
        ok = np.ones(len(pts), dtype=bool)
        centre = h.mean(axis=0)
        for f in _HEX_FACES:
            n = np.cross(h[f[1]] - h[f[0]], h[f[2]] - h[f[0]])
            if n @ (centre - h[f[0]]) > 0:
                n = -n
            ok &= (pts - h[f[0]]) @ n <= 1e-12 * np.linalg.norm(n)
        inside |= ok
    return inside


def _rotation(q):
    """Rotation matrix of a quaternion (w, x, y, z); normalised here."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _axis_rotations():
    """The 24 rotations that map axes onto axes (signed permutation matrices, det +1)."""
    out = []
    for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
        for signs in range(8):
            m = np.zeros((3, 3))
            for r in range(3):
                m[r, perm[r]] = -1.0 if signs >> r & 1 else 1.0
            if np.linalg.det(m) > 0:
                out.append(m)
    return out


def _transform(points, matrix, translation):
    """matrix @ p + translation, summed term by term (exact for the dyadic variants)."""
    m, t = np.asarray(matrix, dtype=float), np.asarray(translation, dtype=float)
    return np.stack([points[:, 0] * m[r, 0] + points[:, 1] * m[r, 1] + points[:, 2] * m[r, 2] + t[r]
                     for r in range(3)], axis=1)


# ----------------------------------------------------------------------------------------------
# Variants: each returns (local points, triangles, local parts, matrix, translation, info).


def _dyadic(x, q=8):
    return round(x * q) / q


def _voxel_boundary(k, x):
    """The voxel-boundary coordinate of axis k nearest to x (halfway between two voxel centres)."""
    i = int(np.clip(math.floor((x - ORIGIN[k]) / SPACING), 0, DIMS[k] - 2))
    return ORIGIN[k] + SPACING * (i + 0.5), i


def _near_axis_on_cut(rng, bone, cut, radius):
    """A point on the cut plane within `radius` times the smaller semi-axis of the bone's axis."""
    z0 = cut["origin"][2]
    cx, cy, a, b, _ = (float(v) for v in _bone_geometry(bone, z0))
    rho, psi = radius * min(a, b) * math.sqrt(rng.uniform()), rng.uniform(0.0, 2 * math.pi)
    x, y = cx + rho * math.cos(psi), cy + rho * math.sin(psi)
    return x, y, _cut_height(cut, x, y)


def _random_pose(rng, bone, cut):
    points, tris, parts = _loft(STEM_LOOPS)
    rotation = _rotation(rng.standard_normal(4))  # uniform on SO(3)
    scale = rng.uniform(0.8, 1.2)
    anchor = np.array(_near_axis_on_cut(rng, bone, cut, 0.5))
    # The centroid on the cut plane: the plane through it splits the solid, so some of it is in the
    # resected region and some below it, in the bone (the centroid is within half a semi-axis of the
    # bone's axis; the implant pokes out through the cortex in some seeds).
    matrix = scale * rotation
    translation = anchor - matrix @ _centroid(points, tris)
    info = {"shape": "stem_with_collar", "scale": scale, "centroid_on_cut_plane": anchor.tolist()}
    return points, tris, parts, matrix, translation, info


def _placed(rng, bone, cut, want_inside, tries=500):
    """Uniform random rotation and position, kept when every interior sample is at least MARGIN
    inside (or outside) the bone's analytic surface and below the cut."""
    points, tris, parts = _loft(STEM_LOOPS)
    centroid = _centroid(points, tris)
    local = _samples(parts)
    for attempt in range(tries):
        rotation = _rotation(rng.standard_normal(4))
        scale = rng.uniform(0.8, 1.0) if want_inside else rng.uniform(0.8, 1.2)
        zc = rng.uniform(12.0, 40.0) if want_inside else rng.uniform(8.0, 35.0)
        cx, cy, a, b, _ = (float(v) for v in _bone_geometry(bone, zc))
        psi = rng.uniform(0.0, 2 * math.pi)
        if want_inside:
            rho = rng.uniform(0.0, 1.0)
        else:  # beyond the bone's outline by the implant's reach
            rho = max(a, b) + 13.0 * scale + MARGIN + rng.uniform(0.0, 3.0)
        anchor = np.array([cx + rho * math.cos(psi), cy + rho * math.sin(psi), zc])
        matrix = scale * rotation
        translation = anchor - matrix @ centroid
        pts = _transform(local, matrix, translation)
        r, ab = _bone_radius(bone, pts)
        below = _below_cut(cut, pts)
        if want_inside:
            ok = np.all(r <= 1.0 - MARGIN / ab) and np.all(pts[:, 2] >= MARGIN) and np.all(below >= MARGIN)
        else:
            ok = np.all(r >= 1.0 + MARGIN / ab) and np.all(below >= MARGIN)
        if ok:
            info = {"shape": "stem_with_collar", "scale": scale, "centroid": anchor.tolist(),
                    "placement_attempts": attempt + 1, "margin": MARGIN}
            return points, tris, parts, matrix, translation, info
    raise RuntimeError("no placement found")  # not reached for seeds 0..24 (see _selftest)


def _bbox_centre_on_face(rng, bone, cut):
    a = 0.5 * int(rng.integers(20, 25))
    a2 = 0.25 * int(rng.integers(math.ceil(1.2 * a), math.floor(1.8 * a) + 1))  # 0.3a .. 0.45a
    h = 0.25 * int(rng.integers(12, 17))
    b = 0.5 * int(rng.integers(12, 17))
    points, tris, parts = _stepped_block(a, a2, h, b)
    rotations = _axis_rotations()
    k = int(rng.integers(len(rotations)))
    x, y, _ = _near_axis_on_cut(rng, bone, cut, 0.3)
    x, y = _dyadic(x), _dyadic(y)
    centre = np.array([x, y, _dyadic(_cut_height(cut, x, y))])
    # Everything dyadic and the rotation a signed permutation: the bbox centre is exact.
    translation = centre - rotations[k] @ np.array([a / 2, h, b / 2])
    info = {"shape": "stepped_block", "dimensions": {"a": a, "a2": a2, "h": h, "b": b}, "scale": 1.0,
            "axis_rotation_index": k, "bbox_centre": centre.tolist(),
            "local_face": "y = h, a2 <= x <= a (the step), bbox centre (a/2, h, b/2)"}
    return points, tris, parts, rotations[k], translation, info


def _face_on_cut_plane(rng, bone, cut):
    points, tris, parts = _loft(STEM_LOOPS)
    scale = (0.875, 1.0, 1.125)[int(rng.integers(3))]
    x, y, _ = _near_axis_on_cut(rng, bone, cut, 0.25)
    x, y = _dyadic(x), _dyadic(y)
    tx, ty = cut["normal"][0], cut["normal"][1]
    # Shear z by the plane's slope: world z = z0 + w + tx x + ty y, so the collar's underside (w = 0)
    # is on the plane exactly; the stem stays vertical, faces stay flat.
    matrix = np.array([[scale, 0.0, 0.0], [0.0, scale, 0.0], [tx * scale, ty * scale, scale]])
    translation = np.array([x, y, cut["origin"][2] + tx * x + ty * y])
    info = {"shape": "stem_with_collar", "scale": scale, "shear": [tx, ty],
            "coplanar_face": "collar underside (local w = 0) on the cut plane"}
    return points, tris, parts, matrix, translation, info


def _face_on_voxel_boundary(rng, bone, cut):
    points, tris, parts = _loft(VOXEL_STEM_LOOPS)
    quarter = int(rng.integers(4))
    c, s = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][quarter]
    matrix = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    x, y, z = _near_axis_on_cut(rng, bone, cut, 0.25)
    (x, ix), (y, iy), (z, iz) = _voxel_boundary(0, x), _voxel_boundary(1, y), _voxel_boundary(2, z)
    # Centre and collar underside on voxel boundaries; the collar's half-sizes, thickness and the stem
    # length are multiples of the spacing, so the collar's six faces and the tip's bottom are too.
    info = {"shape": "stem_with_collar_voxel_sized", "scale": 1.0, "quarter_turns": quarter,
            "voxel_boundaries": {"x": [x, ix], "y": [y, iy], "z": [z, iz]},
            "note": "[coordinate, i]: coordinate = origin + spacing * (i + 0.5), between voxel centres i and i+1"}
    return points, tris, parts, matrix, np.array([x, y, z]), info


# ----------------------------------------------------------------------------------------------
# Files


def _write_label_map(path, labels):
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    image = vtkImageData()
    image.SetDimensions(DIMS)
    image.SetSpacing(SPACING, SPACING, SPACING)
    image.SetOrigin(ORIGIN)
    array = numpy_support.numpy_to_vtk(labels.ravel(), deep=True, array_type=3)  # VTK_UNSIGNED_CHAR
    array.SetName("labels")
    image.GetPointData().SetScalars(array)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.SetCompressorTypeToZLib()
    writer.SetDataModeToBinary()
    if not writer.Write():
        raise OSError(f"cannot write {path}")


def _polydata(points, tris):
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    pts = vtkPoints()
    pts.SetDataTypeToDouble()  # float32 would move the exact faces off their planes
    pts.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    cells = vtkCellArray()
    offsets = numpy_support.numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(tris) + 1, 3, dtype=np.int64), deep=True)
    conn = numpy_support.numpy_to_vtkIdTypeArray(np.ascontiguousarray(tris, dtype=np.int64).ravel(), deep=True)
    cells.SetData(offsets, conn)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(cells)
    return pd


def write_surface(path, points, tris):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(_polydata(points, tris))
    writer.SetDataModeToAscii()  # small, diffable; doubles are written round-trip exact
    if not writer.Write():
        raise OSError(f"cannot write {path}")


def _scene(variant, seed, cut, radius_edge, strategy):
    implant = {"name": "implant", "type": "surface", "file": "implant.vtp", "material": IMPLANT_MATERIAL}
    domains = [implant]
    bone_criteria = {"cell_size": 3.0, "facet_size": 3.0, "facet_distance": 2.0}
    # the implant's edge_size bounds the lines that touch the implant (its sharp edges, where it
    # enters the bone); a global one would bound the found rims of the coarse bone too
    materials = {str(IMPLANT_MATERIAL): {"cell_size": 1.0, "facet_size": 1.0, "facet_distance": 0.1, "edge_size": 0.5}}
    if variant != "implant_only":
        domains += [
            {"name": "resection", "type": "plane", "origin": cut["origin"], "normal": cut["normal"], "cut": True},
            {"name": "bone", "type": "labelmap", "file": "bone_labels.vti", "array": "labels", "background": 0,
             "label_names": dict(LABEL_NAMES)},
        ]
        materials = {"1": dict(bone_criteria), "2": dict(bone_criteria), **materials}
    return {
        "description": f"OracleMesh synthetic case: variant {variant}, seed {seed}",
        "domains": domains,
        "mesh": {
            "strategy": strategy,
            "criteria": {"facet_angle": 25.0, "cell_radius_edge_ratio": float(radius_edge), **bone_criteria},
            "materials": materials,
            "features": {"from_surface": "implant", "feature_angle": 60.0},
            "seed": int(seed),
            "maximum_number_of_vertices": 300000,
        },
    }


def _bone_volumes(labels, cut, parts_world):
    """Approximate surviving bone volumes: voxel centres of each label below the cut and outside the
    implant, times the voxel volume."""
    x, y, z = _grid_axes()
    Z, Y, X = np.meshgrid(z, y, x, indexing="ij")
    pts = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    flat = labels.ravel()
    keep = (flat > 0) & (_below_cut(cut, pts) > 0)
    lo, hi = parts_world.reshape(-1, 3).min(axis=0), parts_world.reshape(-1, 3).max(axis=0)
    near = keep & np.all((pts >= lo) & (pts <= hi), axis=1)
    keep[near] &= ~_inside_parts(parts_world, pts[near])
    return {str(m): float(np.count_nonzero(keep & (flat == m))) * SPACING ** 3 for m in (1, 2)}


def make_case(folder, seed, *, variant="random", radius_edge=1.3, strategy="Conforming"):
    """Writes one case into `folder` (created if needed); returns the path of its scene.json."""
    if variant not in VARIANTS:
        raise ValueError(f"unknown variant {variant!r} (use one of {', '.join(VARIANTS)})")
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown strategy {strategy!r} (use one of {', '.join(STRATEGIES)})")
    seed = int(seed)
    rng = np.random.default_rng(seed)
    bone = _bone_params(rng)  # drawn first for every variant: one seed, one bone and cut
    cut = _cut_params(rng)
    if variant in ("random", "implant_only"):
        local, tris, parts, matrix, translation, info = _random_pose(rng, bone, cut)
    elif variant in ("inside", "outside"):
        local, tris, parts, matrix, translation, info = _placed(rng, bone, cut, variant == "inside")
    else:
        local, tris, parts, matrix, translation, info = {
            "bbox_centre_on_face": _bbox_centre_on_face, "face_on_cut_plane": _face_on_cut_plane,
            "face_on_voxel_boundary": _face_on_voxel_boundary}[variant](rng, bone, cut)
    points = _transform(local, matrix, translation)
    parts_world = _transform(parts.reshape(-1, 3), matrix, translation).reshape(parts.shape)
    volume = volume_exact(points, tris)
    if volume <= 0:
        raise RuntimeError("implant surface is not oriented outwards")  # a bug in the builders
    labels = _bone_labels(bone)

    os.makedirs(folder, exist_ok=True)
    _write_label_map(os.path.join(folder, "bone_labels.vti"), labels)
    write_surface(os.path.join(folder, "implant.vtp"), points, tris)
    scene = _scene(variant, seed, cut, radius_edge, strategy)
    scene_path = os.path.join(folder, "scene.json")
    with open(scene_path, "w") as f:
        json.dump(scene, f, indent=2)
        f.write("\n")

    expected = {str(IMPLANT_MATERIAL): float(volume)}  # highest priority: nothing removes any of it
    exact = {str(IMPLANT_MATERIAL): True}
    if variant != "implant_only":
        bone_volumes = _bone_volumes(labels, cut, parts_world)
        expected.update(bone_volumes)
        exact.update({k: False for k in bone_volumes})
    case = {
        "generator": "oraclemesh_cases.cases", "version": VERSION, "seed": seed, "variant": variant,
        "radius_edge": float(radius_edge), "strategy": strategy,
        "files": {"label_map": "bone_labels.vti", "implant": "implant.vtp", "scene": "scene.json",
                  "label_map_in_scene": variant != "implant_only"},
        "label_map": {"origin": list(ORIGIN), "spacing": [SPACING] * 3, "dimensions": list(DIMS),
                      "array": "labels", "association": "point",
                      "labels": {"0": "background", **LABEL_NAMES}, "bone": bone},
        "cut": None if variant == "implant_only" else {
            **cut, "removes": "points with normal . (p - origin) <= 0 (above the plane)"},
        "implant": {
            **info,
            "transform": "world = matrix @ local + translation",
            "matrix": np.asarray(matrix).tolist(), "translation": np.asarray(translation).tolist(),
            "local_loops": [list(v) for v in (VOXEL_STEM_LOOPS if variant == "face_on_voxel_boundary" else STEM_LOOPS)]
            if info["shape"].startswith("stem") else None,
            "points": len(points), "triangles": len(tris),
            "bounds": [float(v) for pair in zip(points.min(axis=0), points.max(axis=0)) for v in pair],
            "volume": float(volume),
        },
        "expected_volumes": expected,
        "expected_volume_exact": exact,
        "expected_volume_notes": "implant: exact volume of implant.vtp (rational divergence theorem, rounded); "
                                 "bone: voxel centres below the cut and outside the implant times the voxel volume",
    }
    with open(os.path.join(folder, "case.json"), "w") as f:
        json.dump(case, f, indent=2)
        f.write("\n")
    return scene_path


# ----------------------------------------------------------------------------------------------
# Self-test (python3 cases.py --selftest): checks the generated files, not the mesher.


def _read_surface(path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput()
    polys = pd.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    if not np.all(np.diff(offsets) == 3):
        raise AssertionError("non-triangle cells")
    tris = vtk_to_numpy(polys.GetConnectivityArray()).reshape(-1, 3)
    return pd, vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64), tris


def _read_labels(path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader

    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    array = image.GetPointData().GetArray("labels")
    assert array is not None and array.GetDataType() == 3, "labels must be a uint8 point array"
    assert tuple(image.GetDimensions()) == DIMS and tuple(image.GetOrigin()) == ORIGIN
    assert tuple(image.GetSpacing()) == (SPACING,) * 3
    labels = vtk_to_numpy(array).reshape(DIMS[::-1])
    assert set(np.unique(labels).tolist()) == {0, 1, 2}
    return labels


def _open_edges(pd):
    from vtkmodules.vtkFiltersCore import vtkFeatureEdges

    fe = vtkFeatureEdges()
    fe.SetInputData(pd)
    fe.BoundaryEdgesOn()
    fe.NonManifoldEdgesOn()
    fe.FeatureEdgesOff()
    fe.ManifoldEdgesOff()
    fe.Update()
    return fe.GetOutput().GetNumberOfCells()


def _sub(u, v):
    return [u[i] - v[i] for i in range(3)]


def _cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def _dot(u, v):
    return sum(u[i] * v[i] for i in range(3))


def _exact_on_triangle(p, a, b, c):
    """p lies on the closed triangle abc, in exact arithmetic."""
    p, a, b, c = ([Fraction(float(v)) for v in q] for q in (p, a, b, c))
    n = _cross(_sub(b, a), _sub(c, a))
    if _dot(n, _sub(p, a)) != 0:
        return False
    return all(_dot(n, _cross(_sub(v, u), _sub(p, u))) >= 0 for u, v in ((a, b), (b, c), (c, a)))


def _enclosed_samples(pd, step=0.6):
    """Grid points inside the surface (vtkSelectEnclosedPoints: independent of the builders)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints

    b = pd.GetBounds()
    axes = [np.arange(b[2 * k] + step / 2, b[2 * k + 1], step) for k in range(3)]
    grid = np.stack([g.ravel() for g in np.meshgrid(*axes, indexing="ij")], axis=1)
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(grid, deep=True))
    query = vtkPolyData()
    query.SetPoints(pts)
    select = vtkSelectEnclosedPoints()
    select.SetInputData(query)
    select.SetSurfaceData(pd)
    select.Update()
    inside = vtk_to_numpy(select.GetOutput().GetPointData().GetArray("SelectedPoints")).astype(bool)
    return grid[inside]


def _label_at(labels, pts):
    """Nearest voxel's label and whether all 8 voxels around each point agree on bone/background."""
    f = (pts - np.asarray(ORIGIN)) / SPACING
    dims = np.asarray(DIMS)
    inside_map = np.all((f >= 0) & (f <= dims - 1), axis=1)
    n = np.clip(np.rint(f).astype(int), 0, dims - 1)
    nearest = np.where(inside_map, labels[n[:, 2], n[:, 1], n[:, 0]], 0)
    lo = np.clip(np.floor(f).astype(int), 0, dims - 2)
    corners = [labels[lo[:, 2] + k, lo[:, 1] + j, lo[:, 0] + i] > 0 for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    corners = np.where(inside_map, np.stack(corners), False)
    return nearest, np.all(corners, axis=0), ~np.any(corners, axis=0)


def _scene_validator():
    """The project's load_scene (every check of the JSON and the input files)."""
    from oraclemesh.scene import load_scene
    return load_scene, "oraclemesh.scene"


def _check_case(folder, seed, variant, load_scene, stats):
    with open(os.path.join(folder, "case.json")) as f:
        case = json.load(f)
    with open(os.path.join(folder, "scene.json")) as f:
        scene_json = json.load(f)
    scene = load_scene(os.path.join(folder, "scene.json"))
    mesh = scene.mesh
    assert mesh["strategy"] == "Conforming" and mesh["seed"] == seed
    assert mesh["criteria"] == {"facet_angle": 25, "cell_radius_edge_ratio": 1.3, "cell_size": 3, "facet_size": 3,
                                "facet_distance": 2}, mesh["criteria"]
    assert mesh["materials"][3] == {"cell_size": 1, "facet_size": 1, "facet_distance": 0.1, "edge_size": 0.5}
    assert mesh["features"]["from_surface"] == [0] and mesh["maximum_number_of_vertices"] == 300000
    names = [d["name"] for d in scene_json["domains"]]
    assert names == (["implant"] if variant == "implant_only" else ["implant", "resection", "bone"]), names
    if variant != "implant_only":
        assert mesh["materials"][1] == mesh["materials"][2] == {"cell_size": 3, "facet_size": 3, "facet_distance": 2}

    pd, points, tris = _read_surface(os.path.join(folder, "implant.vtp"))
    assert _open_edges(pd) == 0, "boundary or non-manifold edges"
    # Consistent orientation: every directed edge exactly once (its twin runs the other way).
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    assert len({tuple(e) for e in edges.tolist()}) == len(edges), "inconsistent orientation"
    assert len(np.unique(points, axis=0)) == len(points), "duplicate points"
    area2 = np.linalg.norm(np.cross(points[tris[:, 1]] - points[tris[:, 0]], points[tris[:, 2]] - points[tris[:, 0]]),
                           axis=1)
    assert np.all(area2 > 1e-9), "degenerate triangle"
    volume = volume_exact(points, tris)
    assert volume > 0, "not oriented outwards"
    assert float(volume) == case["implant"]["volume"] == case["expected_volumes"]["3"]
    loops = case["implant"]["local_loops"]
    if loops:
        local = _loft_volume([((hx, hy), w) for (hx, hy), w in loops])
    else:
        d = case["implant"]["dimensions"]
        local = (d["a"] + d["a2"]) * d["h"] * d["b"]
    analytic = local * np.linalg.det(case["implant"]["matrix"])
    assert abs(float(volume) - analytic) <= 1e-12 * analytic, (float(volume), analytic)
    labels = _read_labels(os.path.join(folder, "bone_labels.vti"))
    cut = case["cut"]

    if variant in ("random", "inside", "outside"):
        inner = _enclosed_samples(pd)
        nearest, all_bone, all_background = _label_at(labels, inner)
        below = _below_cut(cut, inner) > 0
        in_bone = (nearest > 0) & below
        if variant == "random":
            assert in_bone.any() and (~in_bone).any(), "random implant not partly in the bone"
            stats.setdefault("random_in_bone_fraction", []).append(in_bone.mean())
            stats.setdefault("random_reaches_label_0", []).append(bool((nearest == 0).any()))
        elif variant == "inside":
            assert np.all(all_bone & (_below_cut(cut, inner) > MARGIN / 2)), "implant not inside the bone"
        else:
            assert np.all(all_background & (_below_cut(cut, inner) > MARGIN / 2)), "implant not outside the bone"
    elif variant == "bbox_centre_on_face":
        lo, hi = points.min(axis=0), points.max(axis=0)
        centre = (lo + hi) / 2  # exact: dyadic coordinates
        assert all(Fraction(float(c)) == (Fraction(float(l)) + Fraction(float(h))) / 2
                   for c, l, h in zip(centre, lo, hi))
        assert centre.tolist() == case["implant"]["bbox_centre"]
        hits = [t for t in tris if _exact_on_triangle(centre, *points[t])]
        assert hits, "bbox centre is not on the surface"
    elif variant == "face_on_cut_plane":
        o = [Fraction(v) for v in cut["origin"]]
        n = [Fraction(v) for v in cut["normal"]]
        on = [all(sum(n[i] * (Fraction(float(p[i])) - o[i]) for i in range(3)) == 0 for p in points[t]) for t in tris]
        assert sum(on) >= 8, f"{sum(on)} triangles on the cut plane"  # the collar underside annulus
    elif variant == "face_on_voxel_boundary":
        count = 0
        for t in tris:
            for k in range(3):
                c = points[t, k]
                if c[0] == c[1] == c[2]:
                    i = (Fraction(float(c[0])) - Fraction(ORIGIN[k])) / Fraction(SPACING) - Fraction(1, 2)
                    assert i.denominator == 1 and 0 <= i < DIMS[k] - 1, f"face at {c[0]} is not on a voxel boundary"
                    count += 1
        assert count >= 14, f"only {count} axis-aligned triangles"  # collar 6 faces + tip bottom
    if variant != "implant_only":
        stats.setdefault("bone_volumes", []).append((case["expected_volumes"]["1"], case["expected_volumes"]["2"]))


def _selftest(seeds=range(25)):
    import filecmp
    import tempfile
    import time

    load_scene, how = _scene_validator()
    print(f"scene validator: {how}")
    stats, times = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for variant in VARIANTS:
            for seed in seeds:
                folders = [os.path.join(tmp, f"{variant}-{seed}-{run}") for run in "ab"]
                for folder in folders:
                    start = time.perf_counter()
                    make_case(folder, seed, variant=variant)
                    times.setdefault(variant, []).append(time.perf_counter() - start)
                for name in ("bone_labels.vti", "implant.vtp", "scene.json", "case.json"):
                    a, b = (os.path.join(f, name) for f in folders)
                    assert filecmp.cmp(a, b, shallow=False), f"{variant} seed {seed}: {name} differs between runs"
                try:
                    _check_case(folders[0], seed, variant, load_scene, stats)
                except Exception as e:
                    raise AssertionError(f"{variant} seed {seed}: {e}") from e
            print(f"{variant:24s} seeds {seeds[0]}..{seeds[-1]} ok, deterministic; "
                  f"generation {np.mean(times[variant]):.3f} s mean, {np.max(times[variant]):.3f} s max")
    f = np.array(stats["random_in_bone_fraction"])
    print(f"random: implant volume in the kept bone {f.min():.2f}..{f.max():.2f} (mean {f.mean():.2f}); "
          f"reaches background (label 0) in {sum(stats['random_reaches_label_0'])}/{len(f)} seeds")
    v = np.array(stats["bone_volumes"])
    print(f"approximate bone volumes (mm^3): cortical {v[:, 0].min():.0f}..{v[:, 0].max():.0f}, "
          f"cancellous {v[:, 1].min():.0f}..{v[:, 1].max():.0f}")
    print("selftest passed")


def main(argv=None):
    parser = argparse.ArgumentParser(description="Writes a synthetic bone/implant case (OracleMesh scene).")
    parser.add_argument("folder", nargs="?", help="output folder (for --variant all: one sub-folder per variant)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--variant", default="random", choices=VARIANTS + ("all",))
    parser.add_argument("--radius-edge", type=float, default=1.3)
    parser.add_argument("--strategy", default="Conforming", choices=STRATEGIES)
    parser.add_argument("--selftest", action="store_true", help="check seeds 0..24 of every variant and exit")
    args = parser.parse_args(argv)
    if args.selftest:
        _selftest()
        return 0
    if not args.folder:
        parser.error("give an output folder (or --selftest)")
    variants = VARIANTS if args.variant == "all" else (args.variant,)
    for variant in variants:
        folder = os.path.join(args.folder, variant) if args.variant == "all" else args.folder
        print(make_case(folder, args.seed, variant=variant, radius_edge=args.radius_edge, strategy=args.strategy))
    return 0


if __name__ == "__main__":
    sys.exit(main())
