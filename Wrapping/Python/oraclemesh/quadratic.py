# SPDX-License-Identifier: GPL-3.0-or-later
"""Measures of 10-node (quadratic) tetrahedra in numpy, for the report and the writers: node order of
VTK_QUADRATIC_TETRA and Abaqus C3D10 (corners 0-3, then the mid-edge nodes of EDGES).

The mesher checks its curved tetrahedra in C++ (QuadraticTets.h); this reads them back from any file.
"""
import numpy as np

EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # mid-edge nodes 4..9
TRIANGLE_EDGES = ((0, 1), (1, 2), (2, 0))  # mid-edge nodes 3..5 of a 6-node triangle

# The validity sample of the mesher: the 10 nodes and the 4 Gauss points of the degree-2 rule.
_A, _B = 0.5854101966249685, 0.1381966011250105
SAMPLE = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
                  + [[0.5 if k in e else 0.0 for k in range(4)] for e in EDGES]
                  + [[_A if k == i else _B for k in range(4)] for i in range(4)], dtype=np.float64)


def jacobians(x, bary):
    """Jacobian determinants of the tetrahedra x [m, 10, 3] at barycentric coordinates `bary` (4):
    6 x the signed volume for straight sides."""
    l = np.asarray(bary, dtype=np.float64)
    gradient = [(4 * l[k] - 1) * x[:, k] for k in range(4)]  # d position / d l_k
    for e, (i, j) in enumerate(EDGES):
        gradient[i] = gradient[i] + 4 * l[j] * x[:, 4 + e]
        gradient[j] = gradient[j] + 4 * l[i] * x[:, 4 + e]
    a, b, c = (gradient[k] - gradient[0] for k in (1, 2, 3))
    return np.einsum("ij,ij->i", a, np.cross(b, c))


def jacobian_ratios(points, nodes):
    """Per tetrahedron (nodes [m, 10] into points), the smallest Jacobian determinant on SAMPLE over
    that of the straight tetrahedron on its corners (1 = straight; <= 0: inverted somewhere)."""
    x = points[nodes]
    straight = np.einsum("ij,ij->i", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]))
    smallest = np.min([jacobians(x, l) for l in SAMPLE], axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(straight != 0, smallest / straight, -np.inf)


def volumes(points, nodes):
    """Volume of each 10-node tetrahedron, exact (Keast's 5-point rule on the cubic det J)."""
    x = points[nodes]
    total = -0.8 * jacobians(x, (0.25, 0.25, 0.25, 0.25))
    for i in range(4):
        total = total + 0.45 * jacobians(x, [0.5 if k == i else 1 / 6 for k in range(4)])
    return np.abs(total) / 6


def _edge_table():
    """[4, 4]: the index in EDGES of the edge between corners i and j of a tetrahedron."""
    table = np.full((4, 4), -1)
    for e, (i, j) in enumerate(EDGES):
        table[i, j] = table[j, i] = e
    return table


_EDGE = _edge_table()


def face_nodes(faces, nodes, owner):
    """The 6 nodes of each triangle of `faces` [k, 3] (corner ids, in their order): the corners, then
    the mid-edge nodes of its edges 01, 12, 20, taken from the tetrahedron `owner` [k] (of `nodes`
    [m, 10]) the face belongs to: work and memory in proportion to the faces, not the mesh."""
    faces = np.asarray(faces, dtype=np.int64)
    tets = np.asarray(nodes[np.asarray(owner, dtype=np.int64)], dtype=np.int64)
    # which of its owner's corners each face vertex is
    corner = np.argmax(tets[:, None, :4] == faces[:, :, None], axis=2)
    out = np.empty((len(faces), 6), dtype=np.int64)
    out[:, :3] = faces
    rows = np.arange(len(faces))
    for k, (i, j) in enumerate(TRIANGLE_EDGES):
        out[:, 3 + k] = tets[rows, 4 + _EDGE[corner[:, i], corner[:, j]]]
    return out
