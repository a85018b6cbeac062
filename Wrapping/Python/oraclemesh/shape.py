# SPDX-License-Identifier: GPL-3.0-or-later
"""Shape measures of tetrahedra, as finite-element preprocessors report them, computed from the
corners alone (numpy, vectorised; independent of the mesher's own arrays):

- the smallest and largest of the six dihedral angles [degrees] (70.53 for the regular tetrahedron;
  small angles spoil the stiffness matrix's conditioning, angles near 180 the gradients);
- the radius ratio 3 r / R (inradius over circumradius; Gmsh's "gamma"), 1 for the regular one;
- the mean ratio 12 (3 |V|)^(2/3) / sum of the squared edge lengths, 1 for the regular one;
- the edge ratio, shortest over longest edge.

Flat tetrahedra get 0 (180 degrees for the largest angle)."""
import numpy as np

_FACES = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))  # face k is opposite corner k
_EDGES = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))


def shape_measures(points, cells):
    """{"min_dihedral", "max_dihedral", "radius_ratio", "mean_ratio", "edge_ratio"}: arrays over the
    tetrahedra `cells` [m x 4] (indices into `points` [n x 3])."""
    p = np.asarray(points, dtype=np.float64)[np.asarray(cells)[:, :4]]  # [m, 4, 3]
    normals = np.empty((len(p), 4, 3))
    for k, (a, b, c) in enumerate(_FACES):
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        outward = np.einsum("ij,ij->i", n, p[:, a] - p[:, k]) >= 0  # away from the opposite corner
        normals[:, k] = np.where(outward[:, None], n, -n)
    twice_area = np.linalg.norm(normals, axis=2)  # [m, 4]
    flat_face = (twice_area <= 0).any(axis=1)
    unit = normals / np.where(twice_area > 0, twice_area, 1.0)[:, :, None]
    # the dihedral angle along the edge shared by faces i and j: pi minus the angle of their normals
    cosines = np.stack([-np.einsum("ij,ij->i", unit[:, i], unit[:, j])
                        for i in range(4) for j in range(i + 1, 4)], axis=1)
    angles = np.degrees(np.arccos(np.clip(cosines, -1.0, 1.0)))
    min_dihedral = np.where(flat_face, 0.0, angles.min(axis=1))
    max_dihedral = np.where(flat_face, 180.0, angles.max(axis=1))

    volume = np.abs(np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))) / 6
    lengths = np.stack([np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j in _EDGES], axis=1)  # [m, 6]
    # circumradius from the products of opposite edges' lengths (a tetrahedron's "Heron")
    a, b, c = lengths[:, 0] * lengths[:, 5], lengths[:, 1] * lengths[:, 4], lengths[:, 2] * lengths[:, 3]
    product = np.clip((a + b + c) * (a + b - c) * (a - b + c) * (-a + b + c), 0.0, None)
    with np.errstate(divide="ignore", invalid="ignore"):
        circumradius = np.sqrt(product) / (24 * volume)
        inradius = 3 * volume / (twice_area.sum(axis=1) / 2)
        radius_ratio = np.where(volume > 0, 3 * inradius / circumradius, 0.0)
        mean_ratio = np.where(volume > 0, 12 * (3 * volume) ** (2 / 3) / (lengths ** 2).sum(axis=1), 0.0)
        edge_ratio = np.where(lengths.max(axis=1) > 0, lengths.min(axis=1) / lengths.max(axis=1), 0.0)
    return {"min_dihedral": min_dihedral, "max_dihedral": max_dihedral,
            "radius_ratio": np.nan_to_num(radius_ratio), "mean_ratio": np.nan_to_num(mean_ratio),
            "edge_ratio": edge_ratio}
