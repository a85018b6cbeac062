# SPDX-License-Identifier: GPL-3.0-or-later
"""Boundary and interface surfaces of a multi-material tetrahedral mesh, for the finite-element writers.

Every triangle shared by tetrahedra of two different materials, or belonging to one tetrahedron only
(the mesh's outer boundary), goes into the set of its material pair: ``A__B`` for materials A < B
(by id), ``A__EXTERIOR`` for the boundary of A. A and B are the Abaqus-safe material names
(``cortical bone`` -> ``CORTICAL_BONE``, ``MATERIAL_<id>`` without a name), so the sets are named
alike in every format and the same scene always gives the same names.

Each face is kept on the side of its first-named material (its "owner"): Abaqus surfaces are faces
of the owner's elements, and triangles are ordered so that their normals point out of the owner,
into B or to the exterior.
"""
import re

import numpy as np

EXTERIOR = -1  # the "material" on the other side of a boundary face
EXTERIOR_NAME = "EXTERIOR"

# Abaqus C3D4 faces (S1..S4), 0-based: S1 = nodes 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1. With VTK's
# positive orientation each is ordered with its normal pointing into the tetrahedron.
TET_FACES = np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]])
_OPPOSITE = np.array([3, 2, 0, 1])  # the vertex not on each face


def abaqus_set_name(material, name=None):
    """An Abaqus-safe set name: letters, digits and '_', starting with a letter, <= 80 chars."""
    if name:
        clean = re.sub(r"[^A-Za-z0-9_]+", "_", name).strip("_").upper()
        if clean and not clean[0].isalpha():
            clean = "M_" + clean
        if clean:
            return clean[:80]
    return f"MATERIAL_{material}"


def material_set_names(ids, names=None):
    """{material id: distinct Abaqus-safe name} for the sorted ids; a clash (two materials called
    alike, or one called "exterior") keeps them apart with the id as suffix."""
    names = names or {}
    result, used = {}, {EXTERIOR_NAME}
    for m in sorted(ids):
        name = abaqus_set_name(m, names.get(m))
        if name in used:
            name = f"{name[:70]}_{m}"
        used.add(name)
        result[m] = name
    return result


class SurfaceSets:
    """The boundary and interface faces of a mesh, grouped by material pair.

    ``faces`` [k x 3] point ids, oriented out of the owner tetrahedron; ``owner`` [k] its index;
    ``side`` [k] the face's Abaqus number (1..4 for S1..S4); ``pairs`` [k x 2] (owner material, other
    material or EXTERIOR); ``surface`` [k] index into ``names`` and ``materials`` (one per pair,
    sorted: by the first material, then the second, EXTERIOR last)."""

    def __init__(self, faces, owner, side, pairs, surface, names, materials):
        self.faces, self.owner, self.side, self.pairs, self.surface = faces, owner, side, pairs, surface
        self.names, self.materials = names, materials

    def __len__(self):
        return len(self.names)

    def select(self, index):
        """Row mask of the faces of surface `index`."""
        return self.surface == index


def _face_keys(cells, n_points, block_rows=1 << 18):
    """An integer key per face of the tetrahedra `cells` (face f of tetrahedron t at 4 t + f, any
    vertex order), equal for equal faces."""
    if n_points >= 2 ** 21:
        faces = np.sort(cells[:, TET_FACES].reshape(-1, 3), axis=1)
        return np.unique(faces, axis=0, return_inverse=True)[1].ravel()
    # three 21-bit ids fit one int64: a single fast sort. Made from the cells' columns a block at a
    # time: the keys (8 bytes a face) are all that is held for the whole mesh, not its [4m x 3] faces.
    keys = np.empty((len(cells), 4), dtype=np.int64)
    for start in range(0, len(cells), block_rows):
        block = np.asarray(cells[start:start + block_rows], dtype=np.int64)
        for f, (i, j, k) in enumerate(TET_FACES):
            a, b, c = block[:, i], block[:, j], block[:, k]
            low, high = np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)
            keys[start:start + len(block), f] = (low << 42) | ((a + b + c - low - high) << 21) | high
    return keys.ravel()


def material_ids(material, block_rows=1 << 20):
    """The sorted distinct ids of an integer array: each id marked present, a block of the array at a
    time (no sort, no converted copy of the array)."""
    material = np.asarray(material)
    if not len(material):
        return []
    low = int(material.min())
    present = np.zeros(int(material.max()) - low + 1, dtype=bool)
    for start in range(0, len(material), block_rows):
        present[material[start:start + block_rows].astype(np.int64) - low] = True
    return (np.flatnonzero(present) + low).tolist()


def separating_faces(points, cells, material):
    """The faces on the boundary or between two materials, as (rows [k]: 4 x owner tetrahedron + its
    face's TET_FACES index, other [k]: the material on the other side or EXTERIOR), in any order:
    each face of one tetrahedron, or of two of different materials on the side of the lower id.
    Faces shared by more than two tetrahedra (a broken mesh; the validity check reports them) are
    left out."""
    keys = _face_keys(cells, len(points))  # face f of tet t is row 4 t + f
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    del keys
    starts = np.flatnonzero(np.r_[True, sorted_keys[1:] != sorted_keys[:-1]])
    counts = np.diff(np.r_[starts, len(sorted_keys)])

    single = order[starts[counts == 1]]
    first, second = order[starts[counts == 2]], order[starts[counts == 2] + 1]
    mat_first, mat_second = material[first // 4], material[second // 4]
    differ = mat_first != mat_second
    first, second, mat_first, mat_second = first[differ], second[differ], mat_first[differ], mat_second[differ]
    swap = mat_first > mat_second  # the owner is the lower material id
    owner_rows = np.where(swap, second, first)
    other_mat = np.where(swap, mat_first, mat_second)
    return (np.concatenate([owner_rows, single]),
            np.concatenate([other_mat, np.full(len(single), EXTERIOR, dtype=np.int64)]))


def surface_sets(points, cells, material, names=None, separating=None, ids=None, oriented=False):
    """SurfaceSets of tetrahedra `cells` [m x 4] (ids into `points` [n x 3]) with `material` [m] and
    {material id: name}. `separating`: the faces as separating_faces() gives them, when they are
    known (the mesher's validity check finds them in its pass over the faces: the field array
    SeparatingFaces of a mesh just made); else they are found here. `ids`: material_ids(material)
    when the caller has them. `oriented`: every tetrahedron is known to have a positive volume (the
    mesher's validity check counted none inverted or flat), so each face's outward order is known
    without measuring it.

    Faces shared by more than two tetrahedra (a broken mesh; the validity check reports them) are
    left out."""
    points = np.asarray(points, dtype=np.float64)
    cells = np.asarray(cells, dtype=np.int64)
    material = np.asarray(material)  # any integer type: read where needed, not copied to int64
    rows, other = separating if separating is not None else separating_faces(points, cells, material)
    rows, other = np.asarray(rows, dtype=np.int64), np.asarray(other, dtype=np.int64)
    first = material[rows // 4]
    # sort faces by pair (EXTERIOR last), then by owner and side (rows = 4 x owner + side): a
    # deterministic order for any input order
    order = np.lexsort((rows, np.where(other == EXTERIOR, np.iinfo(np.int64).max, other), first))
    rows = rows[order]
    owner, side = rows // 4, rows % 4
    pairs = np.stack([first[order], other[order]], axis=1)
    # each face's normal away from its owner's fourth vertex: TET_FACES turns it towards that
    # vertex in a positive tetrahedron, so reversed
    faces = cells[owner[:, None], TET_FACES[side][:, ::-1]]
    change = np.r_[True, (pairs[1:] != pairs[:-1]).any(axis=1)] if len(pairs) else np.zeros(0, bool)
    surface = np.cumsum(change) - 1  # faces are sorted by pair: a new surface where the pair changes
    unique_pairs = pairs[change]

    set_names = material_set_names(material_ids(material) if ids is None else ids, names)
    labels = []
    for i, (a, b) in enumerate(unique_pairs.tolist()):
        label = f"{set_names[a]}__{set_names[b] if b != EXTERIOR else EXTERIOR_NAME}"
        labels.append(label if len(label) <= 80 else f"{label[:70]}_{i}")  # Abaqus' limit, kept distinct
    if not oriented:  # measured (an inverted tetrahedron must not flip its face)
        fourth = cells[owner, _OPPOSITE[side]]
        a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
        inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), points[fourth] - a) > 0
        faces[inward] = faces[inward][:, ::-1]
    return SurfaceSets(faces, owner, side + 1, pairs, surface, labels,
                       [tuple(p) for p in unique_pairs.tolist()])
