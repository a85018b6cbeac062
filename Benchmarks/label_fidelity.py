#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""How close a label map's meshed interfaces come to the true surfaces the voxels were sampled from.

Binary and nested label maps of analytic shapes (a label per voxel centre: inside or not), with
fixed seeds for their placement: spheres of radius 4.5 to 10 voxels, a tilted cube, a shell 1.5
voxels thick around a core, and nested spheres on a CT-like grid of 0.5 x 0.5 x 1.25. Each is
meshed by OracleMesh with each label interpolation (PeerOracleMesh --interpolation) and by stock
CGAL 5.5's labelled image domain (PeerCgal, a small program of ours), same image, same criteria,
same seed. Per run:

  dist mean / max   distance of the interface vertices (on a face between two materials or on the
                    boundary) to the nearest true surface, in voxels (the geometric mean spacing)
  vol err           largest relative error of a material's volume against the exact one
  oracle vol err    the same for the volumes the oracle itself gives (sampled 7^3 times per voxel,
                    no mesh: the interpolation's own error, without the facets' chords), when the
                    oraclemesh package imports
  voxel err         the same for the voxel count (what the voxels alone give)
  lost / pieces     labels with no tetrahedra / connected pieces of each material (face-adjacent)
  tets, min/max dihedral, seconds (the whole call)

    cmake --build build --target PeerCgal PeerOracleMesh
    python3 Benchmarks/label_fidelity.py --cgal build/bin/PeerCgal --oraclemesh build/bin/PeerOracleMesh \\
        --work build/label_fidelity [--cases sphere_r4.5 shell_1.5 ...] [--generated]

--generated: thirty more cases with fixed seeds (balls of radius 3.5-14, shells, a hollow shell and
two balls of one label across a gap, tilted and notched boxes, crossing balls, a CT grid at other
placements: generated_cases), e.g. with --interpolations smooth.
    python3 Benchmarks/label_fidelity.py --oraclemesh build/bin/PeerOracleMesh --work DIR --check

--cost N: instead, the cost of building the oracle of an N^3 image of 10 overlapping balls (labels
1-10), per interpolation, each in a fresh process: seconds and the peak resident memory it added
(VmHWM), per voxel (the image itself and its label array are read before the measure starts):

    PYTHONPATH=build/lib/python3.11/site-packages python3 Benchmarks/label_fidelity.py --oraclemesh - --work DIR --cost 256

--chords: instead, what the facets' chords alone cost a material's volume at these criteria: exact
balls of the generated radii meshed as analytic spheres (no label map), with linear and with
10-node tetrahedra (mid-edge nodes on the sphere), against the voxel count's RMS error over 200
random placements of each ball on the grid:

    PYTHONPATH=build/lib/python3.11/site-packages python3 Benchmarks/label_fidelity.py --oraclemesh - --work DIR --chords

--check (ctest Python.label_fidelity): four cases, OracleMesh only (Trilinear and Smooth). Smooth
must keep the distances of CHECK_BOUNDS (the aims, 0.08 voxel on average and 0.35 at most), be at least 20 % closer than Trilinear on average, keep
every label with each material one piece, the shell's volume within 3 %, and give a valid mesh
with no more tetrahedra than Trilinear's at equal criteria (+2 %) and a min dihedral angle within
1 degree of Trilinear's.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

INTERPOLATIONS = ("nearest", "trilinear", "smooth")
# mean and max distance bounds for --check: the aims. On the CT grid the inner ball (2.4 voxels
# along z) needs its voxel volume kept (small pieces) for the mean, and the caps over the flat
# patches of its last slices for the max.
CHECK_BOUNDS = {"sphere_r4.5": (0.08, 0.35), "shell_1.5": (0.08, 0.35), "tilted_box": (0.08, 0.35),
                "ct_aniso": (0.08, 0.35)}
CHECK_CASES = tuple(CHECK_BOUNDS)


def rotation(rng):
    """A random rotation (QR of a Gaussian matrix, signs fixed)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


class Sphere:
    def __init__(self, centre, radius):
        self.c, self.r = np.asarray(centre, float), float(radius)

    def sdf(self, p):
        return np.linalg.norm(p - self.c, axis=1) - self.r

    def volume(self):
        return 4.0 / 3.0 * math.pi * self.r ** 3


class Box:
    def __init__(self, centre, half, rot):
        self.c, self.h, self.rot = np.asarray(centre, float), float(half), rot

    def sdf(self, p):
        q = np.abs((p - self.c) @ self.rot) - self.h
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
        return outside + np.minimum(q.max(axis=1), 0.0)

    def volume(self):
        return (2.0 * self.h) ** 3


class Hollow:
    """A ball's shell of one label, the background inside and out."""

    def __init__(self, centre, radius, thickness):
        self.c, self.r, self.t = np.asarray(centre, float), float(radius), float(thickness)

    def sdf(self, p):
        d = np.linalg.norm(p - self.c, axis=1)
        return np.maximum(d - self.r, self.r - self.t - d)

    def volume(self):
        return 4.0 / 3.0 * math.pi * (self.r ** 3 - (self.r - self.t) ** 3)


class Pair:
    """Two balls of one label a gap apart (one label on both sides of a thin layer of another)."""

    def __init__(self, centre, radius, gap, axis):
        offset = (radius + 0.5 * gap) * np.asarray(axis, float) / np.linalg.norm(axis)
        self.balls = (Sphere(np.asarray(centre, float) - offset, radius), Sphere(np.asarray(centre, float) + offset, radius))

    def sdf(self, p):
        return np.minimum(self.balls[0].sdf(p), self.balls[1].sdf(p))

    def volume(self):
        return self.balls[0].volume() + self.balls[1].volume()


class NotchedBox(Box):
    """A box with one octant cut away (three concave edges meeting at a concave corner)."""

    def sdf(self, p):
        q = (p - self.c) @ self.rot
        # the octant q > 0 (its own distance: inside -min(q), outside the length past it)
        octant = np.where((q > 0).all(axis=1), -q.min(axis=1), np.linalg.norm(np.minimum(q, 0.0), axis=1))
        return np.maximum(super().sdf(p), -octant)

    def volume(self):
        return 7.0 * self.h ** 3


def make_case(name):
    """(dims, spacing, shapes: [(label, shape)] innermost first, exact volume per label)."""
    rng = np.random.default_rng(sum(map(ord, name)))  # a fixed seed per case
    jitter = lambda: rng.uniform(-0.5, 0.5, 3)
    if name == "sphere_r4.5":
        dims, h = (16, 16, 16), (1.0, 1.0, 1.0)
        shapes = [(1, Sphere(np.array([7.5, 7.5, 7.5]) + jitter(), 4.5))]
    elif name == "sphere_r10":
        dims, h = (28, 28, 28), (1.0, 1.0, 1.0)
        shapes = [(1, Sphere(np.array([13.5, 13.5, 13.5]) + jitter(), 10.0))]
    elif name == "nested":
        dims, h = (28, 28, 28), (1.0, 1.0, 1.0)
        c = np.array([13.5, 13.5, 13.5]) + jitter()
        shapes = [(2, Sphere(c + rng.uniform(-1.5, 1.5, 3), 5.0)), (1, Sphere(c, 10.0))]
    elif name == "tilted_box":
        dims, h = (26, 26, 26), (1.0, 1.0, 1.0)
        shapes = [(1, Box(np.array([12.5, 12.5, 12.5]) + jitter(), 6.0, rotation(rng)))]
    elif name == "shell_1.5":
        dims, h = (26, 26, 26), (1.0, 1.0, 1.0)
        c = np.array([12.5, 12.5, 12.5]) + jitter()
        shapes = [(2, Sphere(c, 7.0)), (1, Sphere(c, 8.5))]
    elif name == "ct_aniso":
        dims, h = (36, 36, 16), (0.5, 0.5, 1.25)
        c = np.array([8.75, 8.75, 9.375]) + 0.5 * jitter()
        shapes = [(2, Sphere(c + rng.uniform(-1, 1, 3), 3.0)), (1, Sphere(c, 6.5))]
    else:
        return generated_case(name)
    return dims, np.array(h), shapes


CASES = ("sphere_r4.5", "sphere_r10", "nested", "tilted_box", "shell_1.5", "ct_aniso")


def generated_case(name):
    """The cases --generated lists, by name: ball_<radius>_<seed>, shell_<radius>_<thickness>_<seed>
    (a core of the radius inside a shell of the thickness), hollow_<radius>_<thickness>_<seed> (a
    shell of one label, the background inside and out), gap_<radius>_<gap>_<seed> (two balls of one
    label the gap apart along a random axis), box_<half>_<seed> (a randomly rotated
    cube), notch_<half>_<seed> (the same with an octant cut away), lens_<radius>_<seed> (two balls
    that cross, centres a radius apart) and ct_<seed> (two nested balls of 3.5 and 7 mm on a 0.5 x
    0.5 x 1.25 grid); centres jittered by the seed."""
    kind, *numbers = name.split("_")
    try:
        *sizes, seed = [float(x) for x in numbers]
    except ValueError:
        raise SystemExit(f"unknown case {name!r}")
    rng = np.random.default_rng(int(seed))
    jitter = lambda: rng.uniform(-0.5, 0.5, 3)
    if kind == "ball" and len(sizes) == 1:
        n = int(2 * sizes[0] + 8)
        return (n, n, n), np.ones(3), [(1, Sphere(np.full(3, (n - 1) / 2) + jitter(), sizes[0]))]
    if kind == "shell" and len(sizes) == 2:
        r, t = sizes
        n = int(2 * (r + t) + 8)
        c = np.full(3, (n - 1) / 2) + jitter()
        return (n, n, n), np.ones(3), [(2, Sphere(c, r)), (1, Sphere(c, r + t))]
    if kind == "hollow" and len(sizes) == 2:
        r, t = sizes
        n = int(2 * r + 8)
        return (n, n, n), np.ones(3), [(1, Hollow(np.full(3, (n - 1) / 2) + jitter(), r, t))]
    if kind == "gap" and len(sizes) == 2:
        r, g = sizes
        n = int(4 * r + g + 8)
        return (n, n, n), np.ones(3), [(1, Pair(np.full(3, (n - 1) / 2) + jitter(), r, g, rng.normal(size=3)))]
    if kind == "box" and len(sizes) == 1:
        n = int(3.6 * sizes[0] + 6)
        c = np.full(3, (n - 1) / 2) + jitter()
        return (n, n, n), np.ones(3), [(1, Box(c, sizes[0], rotation(rng)))]
    if kind == "notch" and len(sizes) == 1:
        n = int(3.6 * sizes[0] + 6)
        c = np.full(3, (n - 1) / 2) + jitter()
        return (n, n, n), np.ones(3), [(1, NotchedBox(c, sizes[0], rotation(rng)))]
    if kind == "lens" and len(sizes) == 1:
        r = sizes[0]
        n = int(3 * r + 8)
        c = np.full(3, (n - 1) / 2) + jitter()
        u = rng.normal(size=3)
        u *= 0.5 * r / np.linalg.norm(u)
        return (n, n, n), np.ones(3), [(2, Sphere(c + u, r)), (1, Sphere(c - u, r))]
    if kind == "ct" and not sizes:
        c = np.array([9.75, 9.75, 10.6]) + 0.5 * jitter()
        return (40, 40, 18), np.array([0.5, 0.5, 1.25]), [(2, Sphere(c + rng.uniform(-1, 1, 3), 3.5)),
                                                          (1, Sphere(c, 7.0))]
    raise SystemExit(f"unknown case {name!r}")


def generated_cases(seeds=(11, 12)):
    """Fifteen generated cases per seed (--generated): balls of radius 3.5 to 14 voxels, shells 1.5
    and 2 voxels thick around a core, a hollow shell 1.5 thick, two balls of one label 1.5 apart,
    tilted boxes of half 5 and 9, a tilted box of half 7 with an octant cut
    away (concave edges and corners), two balls of radius 6 or 14 that cross (the crease where they
    meet is sharp, their faces are not), a CT-like grid."""
    names = []
    for seed in seeds:
        names += [f"ball_{r}_{seed}" for r in (3.5, 6, 8, 14)]
        names += [f"shell_{r}_{t}_{seed}" for r, t in ((6, 1.5), (10, 2), (12, 1.5))]
        names += [f"hollow_8.5_1.5_{seed}", f"gap_6_1.5_{seed}"]
        names += [f"box_{h}_{seed}" for h in (5, 9)] + [f"notch_7_{seed}"] + [f"lens_{r}_{seed}" for r in (6, 14)]
        names += [f"ct_{seed}"]
    return names


def label_image(dims, h, shapes):
    """Labels at the voxel centres (origin 0, point-centred: centre i at i * h), x fastest."""
    z, y, x = np.meshgrid(*(np.arange(n) for n in dims[::-1]), indexing="ij")
    p = np.stack([x.ravel() * h[0], y.ravel() * h[1], z.ravel() * h[2]], axis=1)
    labels = np.zeros(len(p), np.uint8)
    for label, shape in reversed(shapes):  # outermost first, the inner ones on top
        labels[shape.sdf(p) < 0.0] = label
    return labels


def overlap_volume(inner, outer):
    """The volume the earlier shape takes from the later one: all of it when nested, else (two balls
    that cross) their lens."""
    if not (isinstance(inner, Sphere) and isinstance(outer, Sphere)):
        return inner.volume()
    d, r, R = float(np.linalg.norm(inner.c - outer.c)), min(inner.r, outer.r), max(inner.r, outer.r)
    if d <= R - r:
        return inner.volume() if inner.r <= outer.r else outer.volume()
    if d >= R + r:
        return 0.0
    return math.pi * (R + r - d) ** 2 * (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d)


def exact_volumes(shapes):
    """Exact volume per label: each shape less what the one before it (on top) takes."""
    out, previous = {}, None
    for label, shape in shapes:
        out[label] = shape.volume() - (overlap_volume(previous, shape) if previous is not None else 0.0)
        previous = shape
    return out


def write_labels(path, dims, h, labels):
    with open(path, "wb") as f:
        f.write(("OMLABELS %d %d %d %r %r %r 0 0 0\n" % (*dims, *h)).encode())
        f.write(labels.tobytes())


def read_mesh(path):
    with open(path, "rb") as f:
        magic, n_points, n_tets = f.readline().split()
        n_points, n_tets = int(n_points), int(n_tets)
        points = np.frombuffer(f.read(24 * n_points), np.float64).reshape(-1, 3)
        tets = np.frombuffer(f.read(16 * n_tets), np.int32).reshape(-1, 4)
        materials = np.frombuffer(f.read(4 * n_tets), np.int32)
    return points, tets, materials


def tet_volumes(points, tets):
    a, b, c, d = (points[tets[:, i]] for i in range(4))
    return np.abs(np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)) / 6.0


def faces_of(tets):
    """The mesh's distinct faces: (vertex ids, the material on each side, -1 on the boundary)."""
    faces = np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 2, 3]], tets[:, [0, 1, 3]], tets[:, [0, 1, 2]]])
    faces.sort(axis=1)
    owner = np.tile(np.arange(len(tets)), 4)
    unique, inverse, counts = np.unique(faces, axis=0, return_inverse=True, return_counts=True)
    order = np.argsort(inverse.ravel(), kind="stable")  # the two copies of an inner face side by side
    starts = np.r_[0, np.cumsum(counts)[:-1]]
    first = owner[order[starts]]
    second = np.where(counts == 2, owner[order[np.minimum(starts + 1, len(order) - 1)]], -1)
    return unique, first, second


def measure(points, tets, materials, shapes, unit):
    faces, first, second = faces_of(tets)
    inner = second >= 0
    interface = ~inner | (materials[first] != np.where(inner, materials[second], -1))
    vertices = np.unique(faces[interface].ravel())
    p = points[vertices]
    dist = np.min(np.abs(np.stack([s.sdf(p) for _, s in shapes])), axis=0) / unit
    # connected pieces per material (tetrahedra sharing a face of the same material)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    same = inner & ~interface
    graph = coo_matrix((np.ones(same.sum()), (first[same], second[same])), shape=(len(tets), len(tets)))
    _, component = connected_components(graph, directed=False)
    pieces = {int(m): int(np.unique(component[materials == m]).size) for m in np.unique(materials)}
    volumes = {}
    vol = tet_volumes(points, tets)
    for m in np.unique(materials):
        volumes[int(m)] = float(vol[materials == m].sum())
    return {"dist_mean": float(dist.mean()) if dist.size else float("nan"),
            "dist_max": float(dist.max()) if dist.size else float("nan"),
            "interface_vertices": int(vertices.size), "pieces": pieces, "volumes": volumes}


def oracle_volumes(dims, h, labels, interpolation, per_voxel=7):
    """The volume of each label as the oracle itself gives it (no mesh: what the interpolation puts
    where), from per_voxel^3 samples per voxel at the centres of sub-cells; None without the
    oraclemesh package (PYTHONPATH=build/lib/python3.*/site-packages)."""
    try:
        import oraclemesh as om
        from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
        from vtkmodules.vtkCommonDataModel import vtkImageData
    except ImportError:
        return None
    image = vtkImageData()
    image.SetDimensions(*dims)
    image.SetSpacing(*h)
    array = numpy_to_vtk(labels, deep=True)
    array.SetName("labels")
    image.GetPointData().SetScalars(array)
    domain = om.vtkLabelMapDomain()
    domain.SetInputData(image)
    domain.SetInterpolation(INTERPOLATIONS.index(interpolation))
    sampler = om.vtkOracleSampler()
    sampler.SetInputConnection(domain.GetOutputPort())
    cells = [per_voxel * (n - 1) for n in dims]
    half = [0.5 * step / per_voxel for step in h]
    sampler.SetDimensions(*cells)
    sampler.SetBounds(half[0], (dims[0] - 1) * h[0] - half[0], half[1], (dims[1] - 1) * h[1] - half[1],
                      half[2], (dims[2] - 1) * h[2] - half[2])
    sampler.Update()
    out = sampler.GetOutput()
    material = vtk_to_numpy(out.GetPointData().GetArray("Material"))
    cell = float(np.prod(h)) / per_voxel ** 3
    ids, counts = np.unique(material, return_counts=True)
    return {int(m): float(c) * cell for m, c in zip(ids, counts)}


def oracle_error(dims, h, labels, interpolation, exact):
    """Largest relative error of a label's volume as the oracle gives it (oracle_volumes), or None."""
    volumes = oracle_volumes(dims, h, labels, interpolation)
    if volumes is None:
        return None
    return max(abs(volumes.get(lab, 0.0) - exact[lab]) / exact[lab] for lab in exact)


def run(tool, exe, image, mesh_path, interpolation, criteria, seed):
    cmd = [exe, "labels", image, "--write", mesh_path, "--seed", str(seed), "--opt", "default"]
    for key, value in criteria.items():
        cmd += ["--" + key.replace("_", "-"), repr(value)]
    if tool == "oraclemesh":
        cmd += ["--interpolation", interpolation]
    t0 = time.time()
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{out.stderr}")
    record = json.loads(out.stdout.strip().splitlines()[-1])
    record["wall"] = time.time() - t0
    return record


COST_CHILD = r'''
import sys, time
import oraclemesh as om
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
def peak():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM:"))
r = vtkXMLImageDataReader(); r.SetFileName(sys.argv[1]); r.Update()
image = r.GetOutput()
d = om.vtkLabelMapDomain(); d.SetInputData(image); d.SetInterpolation(int(sys.argv[2])); d.Update()
before = peak()
s = om.vtkOracleSampler(); s.SetInputConnection(d.GetOutputPort()); s.SetDimensions(2, 2, 2)
t = time.time(); s.Update(); seconds = time.time() - t
print(seconds, peak() - before)
'''


def cost(n, work):
    """Seconds and added peak bytes per voxel of building an n^3, 10-label oracle, per interpolation."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
    path = os.path.join(work, f"balls_{n}.vti")
    rng = np.random.default_rng(1)
    labels = np.zeros((n, n, n), np.uint8)
    axis = np.arange(n, dtype=np.float32)
    for label in range(1, 11):
        c, r = rng.uniform(0.2 * n, 0.8 * n, 3), rng.uniform(0.1 * n, 0.25 * n)
        inside = ((axis[None, None, :] - c[0]) ** 2 + (axis[None, :, None] - c[1]) ** 2 +
                  (axis[:, None, None] - c[2]) ** 2) < r * r
        labels[inside] = label
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    array = numpy_to_vtk(labels.ravel(), deep=True)
    array.SetName("labels")
    image.GetPointData().SetScalars(array)
    w = vtkXMLImageDataWriter()
    w.SetFileName(path)
    w.SetInputData(image)
    w.Write()
    print(f"| {n}^3, 10 labels | build s | added peak, bytes per voxel |")
    print("|---|---:|---:|")
    for name, mode in (("nearest", 0), ("trilinear", 1), ("smooth", 2)):
        out = subprocess.run([sys.executable, "-c", COST_CHILD, path, str(mode)], capture_output=True, text=True,
                             check=True)
        seconds, added = map(float, out.stdout.split()[-2:])
        print(f"| {name} | {seconds:.2f} | {added / n ** 3:.1f} |")
    return 0


def mesh_criteria(unit):
    """The criteria of every run, in world units for a voxel of `unit` (the geometric mean spacing)."""
    return {"facet_angle": 25, "facet_size": 1.0 * unit, "facet_distance": 0.03 * unit, "cell_size": 2.0 * unit,
            "radius_edge": 3}


def chords(placements=200):
    """--chords: volume errors of exact balls meshed at mesh_criteria, linear and 10-node, and the voxel
    count's RMS error over random placements of the same balls on a grid of spacing 1."""
    import oraclemesh as om
    rng = np.random.default_rng(1)
    keys = {"radius_edge": "cell_radius_edge_ratio"}
    criteria = {keys.get(k, k): v for k, v in mesh_criteria(1.0).items()}
    print("| ball radius (voxels) | linear tetrahedra | 10-node tetrahedra | voxel count (RMS) | tets |")
    print("|---:|---:|---:|---:|---:|")
    for radius in (3.5, 4.5, 6, 8, 10, 14):
        exact = 4.0 / 3.0 * math.pi * radius ** 3
        scene = {"domains": [{"type": "sphere", "center": [0.3, 0.1, -0.2], "radius": radius, "material": 1}],
                 "mesh": {"criteria": criteria, "seed": 1}}
        linear, quadratic = om.mesh(scene), om.mesh(scene, element_order=2)
        n = int(math.ceil(radius)) + 1
        grid = np.stack(np.meshgrid(*[np.arange(-n, n + 1)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
        counts = [np.count_nonzero(np.linalg.norm(grid - rng.uniform(-0.5, 0.5, 3), axis=1) < radius)
                  for _ in range(placements)]
        rms = math.sqrt(np.mean([((c - exact) / exact) ** 2 for c in counts]))
        errors = [(m.quality["materials"][1]["volume"] - exact) / exact for m in (linear, quadratic)]
        print(f"| {radius} | {errors[0]:+.3%} | {errors[1]:+.4%} | {rms:.3%} | {linear.quality['tets']} |")
    return 0


def volume_summary(rows):
    """Per tool: on how many cases the mesh and the oracle are closer to the exact volumes than the voxel
    count, and the RMS of each over the cases (each case's worst material)."""
    for tool in sorted({r["tool"] for r in rows}):
        mine = [r for r in rows if r["tool"] == tool]
        rms = lambda key: math.sqrt(np.mean([r[key] ** 2 for r in mine]))
        line = (f"{tool}: mesh closer to exact than the voxel count on {sum(r['vol_err'] < r['voxel_err'] for r in mine)}"
                f" of {len(mine)}; RMS over cases: mesh {rms('vol_err'):.2%}, voxel count {rms('voxel_err'):.2%}")
        if all(r["oracle_vol_err"] is not None for r in mine):
            line += (f", oracle {rms('oracle_vol_err'):.2%} (closer than the count on "
                     f"{sum(r['oracle_vol_err'] < r['voxel_err'] for r in mine)})")
        print(line)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--oraclemesh", required=True, help="PeerOracleMesh")
    ap.add_argument("--cgal", help="PeerCgal (stock CGAL 5.5); without it, OracleMesh only")
    ap.add_argument("--work", required=True)
    ap.add_argument("--cases", nargs="+", default=None)
    ap.add_argument("--generated", action="store_true",
                    help="twenty generated cases with fixed seeds instead (generated_cases): placements beyond the six")
    ap.add_argument("--interpolations", nargs="+", default=list(INTERPOLATIONS), choices=INTERPOLATIONS)
    ap.add_argument("--check", action="store_true", help="four cases, assert the Smooth aims")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cost", type=int, metavar="N", help="the cost of building an N^3 10-label oracle instead")
    ap.add_argument("--chords", action="store_true", help="the facets' chords' volume error on exact balls instead")
    args = ap.parse_args()
    if args.chords:
        return chords()
    if args.cost:
        os.makedirs(args.work, exist_ok=True)
        return cost(args.cost, args.work)
    cases = args.cases or (generated_cases() if args.generated else list(CHECK_CASES) if args.check else list(CASES))
    interpolations = ["trilinear", "smooth"] if args.check else args.interpolations
    os.makedirs(args.work, exist_ok=True)
    rows, failures = [], []
    for name in cases:
        dims, h, shapes = make_case(name)
        labels = label_image(dims, h, shapes)
        image = os.path.join(args.work, name + ".oml")
        write_labels(image, dims, h, labels)
        unit = float(np.prod(h)) ** (1.0 / 3.0)
        exact = exact_volumes(shapes)
        voxel = {lab: float(np.count_nonzero(labels == lab)) * float(np.prod(h)) for lab in exact}
        voxel_err = max(abs(voxel[m] - exact[m]) / exact[m] for m in exact)
        criteria = mesh_criteria(unit)
        runs = [("oraclemesh", i) for i in interpolations]
        if args.cgal and not args.check:
            runs.append(("cgal", "trilinear"))
        results = {}
        for tool, interpolation in runs:
            mesh_path = os.path.join(args.work, f"{name}_{tool}_{interpolation}.omtets")
            exe = args.cgal if tool == "cgal" else args.oraclemesh
            record = run(tool, exe, image, mesh_path, interpolation, criteria, args.seed)
            points, tets, materials = read_mesh(mesh_path)
            m = measure(points, tets, materials, shapes, unit)
            errors = {lab: (m["volumes"].get(lab, 0.0) - exact[lab]) / exact[lab] for lab in exact}
            row = {"case": name, "tool": "CGAL 5.5" if tool == "cgal" else "OracleMesh " + interpolation,
                   "interpolation": interpolation, **m, "volume_errors": errors,
                   "vol_err": max(abs(e) for e in errors.values()), "voxel_err": voxel_err,
                   "oracle_vol_err": oracle_error(dims, h, labels, interpolation, exact) if tool == "oraclemesh" else None,
                   "lost": sorted(set(exact) - set(m["volumes"])), "tets": record["tets"],
                   "min_dihedral": record["min_dihedral"], "defects": record["defects"], "seconds": record["call"]}
            rows.append(row)
            results[(tool, interpolation)] = row
        if args.check:
            s, t = results[("oraclemesh", "smooth")], results[("oraclemesh", "trilinear")]
            def need(ok, what):
                if not ok:
                    failures.append(f"{name}: {what}")
            mean_bound, max_bound = CHECK_BOUNDS[name]
            need(s["dist_mean"] <= mean_bound, f"mean distance {s['dist_mean']:.3f} voxel > {mean_bound}")
            need(s["dist_max"] <= max_bound, f"max distance {s['dist_max']:.3f} voxel > {max_bound}")
            need(s["dist_mean"] <= 0.8 * t["dist_mean"],
                 f"mean distance {s['dist_mean']:.3f} not 20 % below Trilinear's {t['dist_mean']:.3f}")
            need(not s["lost"], f"labels lost: {s['lost']}")
            need(all(v == 1 for v in s["pieces"].values()), f"pieces per material {s['pieces']}")
            if name.startswith("shell"):
                need(abs(s["volume_errors"][1]) <= 0.03, f"shell volume {s['volume_errors'][1]:+.2%} beyond 3 %")
            need(s["defects"] == 0, f"{s['defects']} defects")
            need(s["tets"] <= 1.02 * t["tets"], f"{s['tets']} tetrahedra > Trilinear's {t['tets']} + 2 %")
            need(s["min_dihedral"] >= t["min_dihedral"] - 1.0,
                 f"min dihedral {s['min_dihedral']:.2f} below Trilinear's {t['min_dihedral']:.2f} - 1")

    print("| case | tool | dist mean | dist max | vol err | oracle vol err | voxel err | lost | pieces | tets | min dih | s |")
    print("|---|---|---:|---:|---:|---:|---:|---|---|---:|---:|---:|")
    for r in rows:
        pieces = ",".join(f"{m}:{n}" for m, n in sorted(r["pieces"].items()))
        oracle = "-" if r["oracle_vol_err"] is None else f"{r['oracle_vol_err']:.2%}"
        print(f"| {r['case']} | {r['tool']} | {r['dist_mean']:.3f} | {r['dist_max']:.3f} | {r['vol_err']:.2%} | "
              f"{oracle} | {r['voxel_err']:.2%} | {r['lost'] or '-'} | {pieces} | {r['tets']} | {r['min_dihedral']:.1f} | "
              f"{r['seconds']:.2f} |")
    print()
    volume_summary(rows)
    with open(os.path.join(args.work, "results.jsonl"), "w") as f:
        for r in rows:
            f.write(json.dumps(r, default=str) + "\n")
    if failures:
        print("\nFAILED:\n  " + "\n  ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
