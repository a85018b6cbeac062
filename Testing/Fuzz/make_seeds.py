#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the hand-made seed inputs of the fuzz harnesses into corpus/<harness>/seed-*.

The byte layout is the harnesses' (FuzzInput.h): a coordinate byte t < 240 means (t % 65 - 32) / 4.
Run it again after changing a harness's layout; crashers found by libFuzzer are kept beside them
as crash-<sha1> files.
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def c(v):
    t = int(round(v * 4)) + 32
    assert 0 <= t < 65
    return bytes([t])


def point(p):
    return b"".join(c(v) for v in p)


def write(harness, name, data):
    folder = os.path.join(HERE, "corpus", harness)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "seed-" + name), "wb") as f:
        f.write(data)


def cube_soup(lo, hi, offset=0):
    pts = [((hi if i & 1 else lo), (hi if i & 2 else lo), (hi if i & 4 else lo)) for i in range(8)]
    tris = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
            (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    return pts, [tuple(v + offset for v in t) for t in tris]


def surface(options, pts, tris, queries=()):
    data = bytes([options, len(pts)]) + b"".join(point(p) for p in pts)
    data += bytes([len(tris)]) + b"".join(bytes(t) for t in tris)
    return data + b"".join(point(q) for q in queries)


pts, tris = cube_soup(0, 2)
write("SurfaceDomain", "cube", surface(0, pts, tris, [(1, 1, 1), (3, 0, 0)]))
write("SurfaceDomain", "cube-open-winding", surface(2, pts, tris[:-1], [(1, 1, 1), (2, 1.5, 1.5)]))
p2, t2 = cube_soup(1, 3, offset=8)
write("SurfaceDomain", "two-cubes-overlap", surface(0, pts + p2, tris + t2, [(1.5, 1.5, 1.5)]))
write("SurfaceDomain", "two-cubes-overlap-allowed", surface(1, pts + p2, tris + t2, [(1.5, 1.5, 1.5)]))
p3, t3 = cube_soup(2, 4, offset=7)  # shares corner (2, 2, 2): point 7 of the first cube
write("SurfaceDomain", "two-cubes-corner", surface(0, pts + p3[1:], tris + [tuple(7 if v == 7 else v for v in t) for t in t3], [(2, 2, 2)]))

# label maps: options, dims (3 bytes), origin, [spacing], [direction], [background], labels
lm = bytes([0, 2, 2, 2]) + point((0, 0, 0)) + bytes([1, 2, 0, 1, 1, 1, 2, 0]) + point((0.5, 0.5, 0.5)) + point((3, 3, 3))
write("LabelMapDomain", "2x2x2", lm)
lm = bytes([1 | 4 | 8, 3, 2, 1]) + point((1, -1, 0)) + point((0.5, 2, 1)) + b"".join(c(v) for v in (0, 1, 0, -1, 0, 0, 0, 0, 1)) + bytes([1, 1, 2, 0, 2, 1]) + point((0, 0, 0)) + point((2, 2, 1))
write("LabelMapDomain", "rotated-trilinear", lm)

# feature lines: options, points, segments (index pairs)
fpts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 0, 0), (2, 0, 0), (0.5, 0, 0)]
fseg = [(0, 1), (1, 2), (3, 4), (1, 0), (5, 4)]
write("FeatureSegments", "overlaps", bytes([0, len(fpts)]) + b"".join(point(p) for p in fpts) + bytes([len(fseg)]) + b"".join(bytes(s) for s in fseg))
fpts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0.5, -1, 0), (0.5, 1, 0)]
fseg = [(0, 1), (1, 2), (3, 4)]
write("FeatureSegments", "crossing", bytes([1, len(fpts)]) + b"".join(point(p) for p in fpts) + bytes([len(fseg)]) + b"".join(bytes(s) for s in fseg))
fpts = [(0, 0, 0), (2, 0, 0), (2, 0.25, 0), (0, 2, 0)]
fseg = [(0, 1), (1, 2), (0, 3)]
write("FeatureSegments", "sharp-angle", bytes([4, len(fpts)]) + b"".join(point(p) for p in fpts) + bytes([len(fseg)]) + b"".join(bytes(s) for s in fseg) + c(0.5))

# oracles: number of domains, then per domain a kind byte and its numbers, then query points
sphere = bytes([0]) + point((0, 0, 0)) + c(3)
box = bytes([1]) + point((-1, -1, -1)) + point((2, 2, 2))
cyl = bytes([2]) + point((0, 0, 0)) + point((0, 0, 1)) + c(1) + c(4)
plane_cut = bytes([3 | 64]) + point((0, 0, 1)) + point((0, 0, -1))
surf = bytes([4]) + point((1, 1, 1)) + c(2) + bytes(6)
labels = bytes([5]) + bytes([2, 2, 2]) + bytes([1, 2, 0, 1, 1, 1, 2, 0]) + point((-1, -1, -1)) + point((1, 1, 1))
queries = b"".join(point(q) for q in [(-4, 0, 0), (4, 0.5, 0.25), (0, -4, 0.5), (0.25, 4, 2), (0, 0, -4), (1, 1, 4)])
write("Oracle", "all-kinds", bytes([5]) + plane_cut + surf + cyl + box + sphere + queries)
write("Oracle", "labels-and-sphere", bytes([1]) + labels + sphere + queries)
