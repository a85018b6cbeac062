# SPDX-License-Identifier: GPL-3.0-or-later
"""Quality report of a tetrahedral mesh written by ``oraclemesh mesh`` (cell data Material,
MinDihedralAngle; field data StatisticNames/StatisticValues, Warnings and MaterialIds/MaterialNames
when present): per material tetrahedra, volume and minimal dihedral angle, a dihedral-angle
histogram as text and as a PNG (matplotlib, Agg: no display needed)."""
from .errors import OracleMeshError
from .fielddata import labelled, strings
from .meshfiles import read_mesh  # noqa: F401  (the report's reader; kept here for its users)
from .shape import shape_measures
from .writers import element_nodes, tetrahedra
from . import fieldkeys

# Text histogram bins [degrees]: a tetrahedron's minimal dihedral angle is at most 70.53 degrees,
# its maximal one at least that; finite-element checks look at 15 and 155 (and 160, 170).
TEXT_BINS = (0, 5, 10, 20, 30, 40, 50, 60, 90)
MAX_TEXT_BINS = (60, 90, 120, 150, 155, 160, 170, 180)
# shape.shape_measures keys in the report's table: the worst is the largest for max_dihedral, else the smallest
SHAPE_KEYS = ("max_dihedral", "radius_ratio", "mean_ratio", "edge_ratio")
WORST_SHOWN = 5


def _strings(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())] if array is not None else []


def material_names(grid):
    """{material id: name} stored in the mesh's field data by ``oraclemesh mesh`` (may be empty)."""
    return {int(m): name for name, m in labelled(grid.GetFieldData(), fieldkeys.MATERIAL_IDS)}


def statistics(grid):
    """The mesher's statistics {name: value} from the field data (empty for other meshes)."""
    return dict(labelled(grid.GetFieldData(), fieldkeys.STATISTIC_VALUES))


# Defect counts of the validity check, in report order: (statistic name, words).
VALIDITY_ITEMS = (
    (fieldkeys.VALIDITY_DUPLICATE_VERTICES, "duplicate vertices"),
    (fieldkeys.VALIDITY_MICRO_TETRAHEDRA, "micro tetrahedra"),
    (fieldkeys.VALIDITY_FLAT_TETRAHEDRA, "flat tetrahedra"),
    (fieldkeys.VALIDITY_INVERTED_TETRAHEDRA, "inverted tetrahedra"),
    (fieldkeys.VALIDITY_NON_MANIFOLD_FACES, "faces shared by more than two tetrahedra"),
    (fieldkeys.VALIDITY_BAD_VERTEX_INDICES, "tetrahedra with bad vertex indices"),
    (fieldkeys.VALIDITY_MATERIAL_MISMATCHES, "tetrahedra whose material differs from the oracle's inside them"),
    (fieldkeys.VALIDITY_MISSING_SEGMENT_PIECES, "feature-line pieces missing from the mesh edges"),
    (fieldkeys.VALIDITY_UNUSED_VERTICES, "vertices no tetrahedron uses"),
)


def validity(grid, recheck=True):
    """Defect counts {statistic name: count} of a tetrahedral mesh, checked now on the geometry
    (vtkMeshValidityCheck: duplicates, micro, flat, inverted, non-manifold faces) plus, for meshes
    made by the tetrahedralizer, the checks that need the oracle or the feature lines (material
    mismatches, missing feature-line pieces) from its statistics. "validity.defects" is the sum.
    With recheck=False the mesher's own counts are taken where the grid carries them (a mesh just
    made, not read from a file: the same check has run on it)."""
    from . import vtkMeshValidityCheck

    made = statistics(grid)
    if not recheck and fieldkeys.VALIDITY_DEFECTS in made:
        return {k: v for k, v in made.items() if k.startswith("validity.")}
    check = vtkMeshValidityCheck()
    check.SetInputData(grid)
    check.Update()
    fd = check.GetOutput().GetFieldData()
    names, values = fd.GetAbstractArray(fieldkeys.VALIDITY_NAMES), fd.GetArray(fieldkeys.VALIDITY_VALUES)
    counts = {n: values.GetValue(i) for i, n in enumerate(_strings(names))} if names is not None else {}
    for key in (fieldkeys.VALIDITY_MATERIAL_MISMATCHES, fieldkeys.VALIDITY_MISSING_SEGMENT_PIECES):
        if key in made:
            counts[key] = made[key]
    counts[fieldkeys.VALIDITY_DEFECTS] = sum(counts.get(key, 0) for key, _ in VALIDITY_ITEMS)
    return counts


def validity_line(counts):
    """One line: "validity: no defects (...)" or "validity: N DEFECTS: ..."."""
    shortest = counts.get(fieldkeys.VALIDITY_SHORTEST_EDGE, 0) / max(counts.get(fieldkeys.VALIDITY_MEDIAN_EDGE, 1), 1e-300)
    if not counts.get(fieldkeys.VALIDITY_DEFECTS):
        return (f"validity: no defects (no duplicate or unused vertices, micro, flat or inverted tetrahedra, non-manifold "
                f"faces{', material mismatches' if fieldkeys.VALIDITY_MATERIAL_MISMATCHES in counts else ''}"
                f"{', missing feature-line pieces' if fieldkeys.VALIDITY_MISSING_SEGMENT_PIECES in counts else ''}); "
                f"shortest/median edge {shortest:.2g}")
    found = ", ".join(f"{int(counts[key])} {words}" for key, words in VALIDITY_ITEMS if counts.get(key))
    return f"validity: {int(counts[fieldkeys.VALIDITY_DEFECTS])} DEFECTS: {found}; shortest/median edge {shortest:.2g}"


def volume_text(volume):
    """A volume for the tables: one decimal, or four significant digits below 100 (so that a part in
    metres does not read as 0.0 mm^3)."""
    return f"{volume:.1f}" if volume == 0 or abs(volume) >= 100 else f"{volume:.4g}"


def _worst(shape, selected):
    """{"worst_<key>": value} over the tetrahedra `selected` for SHAPE_KEYS (the largest
    max_dihedral, else the smallest)."""
    return {f"worst_{key}": float(shape[key][selected].max() if key == "max_dihedral" else shape[key][selected].min())
            for key in SHAPE_KEYS}


def quality(grid, source="mesh", measured=False):
    """Per-material quality of a tetrahedral mesh: {"materials": {id: {"tets", "volume",
    "min_dihedral", "mean_min_dihedral", "worst_max_dihedral", "worst_radius_ratio", "worst_mean_ratio",
    "worst_edge_ratio"}}, "tets", "vertices" (corners), "nodes" (with the mid-edge ones), "volume",
    "min_dihedral", "max_dihedral", "worst" (the worst_* values of the whole mesh), "angles" (per-tet
    minimal dihedral angles, of the corners), "shape" (per-tet measures: shape.shape_measures of every
    tetrahedron, or with `measured` its "min_dihedral" and "max_dihedral" only), "points" and "cells"
    (the corners; centroid() gives a tetrahedron's centre),
    "material" (per-tet material), "order" (1 or 2) and for 10-node tetrahedra "min_jacobian_ratio"
    (quadratic.jacobian_ratios)}.
    Volumes come from the geometry (curved for 10-node tetrahedra), so any tetrahedral .vtu with
    Material and MinDihedralAngle works. With `measured` (a mesh just made, not read from a file) the
    mesher's own figures are taken where the grid carries them: its one measuring pass wrote the
    cell arrays and the shape.* statistics (the same measures, ShapeSummary.h); a file is measured
    here, independently of the mesher."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from .quadratic import jacobian_ratios, volumes as curved_volumes

    points, nodes, material = element_nodes(grid, source)
    cells = nodes[:, :4]
    array = grid.GetCellData().GetArray(fieldkeys.MIN_DIHEDRAL_ANGLE)
    if array is None:
        raise OracleMeshError(f"{source}: no cell array '{fieldkeys.MIN_DIHEDRAL_ANGLE}' (write meshes with 'oraclemesh mesh')")
    angles = np.asarray(vtk_to_numpy(array), dtype=np.float64)  # the grid's own memory when it is float64
    angles.flags.writeable = False
    quadratic = nodes.shape[1] == 10
    if measured and not quadratic:
        q = _measured_quality(grid, points, cells, material, angles)
        if q is not None:
            return q
    p = points[cells]
    volumes = curved_volumes(points, nodes) if quadratic else \
        np.abs(np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))) / 6
    shape = shape_measures(points, cells)  # from the corners: independent of the mesher's arrays
    materials = {}
    for m in sorted(set(material.tolist())):
        sel = material == m
        materials[m] = {"tets": int(sel.sum()), "volume": float(volumes[sel].sum()),
                        "min_dihedral": float(angles[sel].min()), "mean_min_dihedral": float(angles[sel].mean()),
                        **_worst(shape, sel)}
    worst = _worst(shape, slice(None))
    q = {"materials": materials, "tets": int(len(cells)), "vertices": int(len(np.unique(cells))) if quadratic else int(grid.GetNumberOfPoints()),
         "nodes": int(grid.GetNumberOfPoints()), "volume": float(volumes.sum()), "min_dihedral": float(angles.min()),
         "max_dihedral": worst["worst_max_dihedral"], "worst": worst, "angles": angles, "shape": shape,
         "points": points, "cells": cells, "material": material, "order": 2 if quadratic else 1}
    if quadratic:
        q["min_jacobian_ratio"] = float(jacobian_ratios(points, nodes).min())
    return q


# quality()'s figures and the shape.* statistics (ShapeSummary.h) they come from with `measured`
_MEASURED = (("tets", fieldkeys.SHAPE_TETRAHEDRA), ("volume", fieldkeys.SHAPE_VOLUME),
             ("min_dihedral", fieldkeys.SHAPE_MIN_DIHEDRAL), ("mean_min_dihedral", fieldkeys.SHAPE_MEAN_MIN_DIHEDRAL),
             ("worst_max_dihedral", fieldkeys.SHAPE_MAX_DIHEDRAL),
             ("worst_radius_ratio", fieldkeys.SHAPE_WORST_RADIUS_RATIO),
             ("worst_mean_ratio", fieldkeys.SHAPE_WORST_MEAN_RATIO),
             ("worst_edge_ratio", fieldkeys.SHAPE_WORST_EDGE_RATIO))


def _measured_quality(grid, points, cells, material, angles):
    """quality() of a linear mesh from the mesher's figures (cell arrays and shape.* statistics);
    None when the grid does not carry them for these cells."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    stats = statistics(grid)
    largest = grid.GetCellData().GetArray(fieldkeys.MAX_DIHEDRAL_ANGLE)
    if largest is None or stats.get(fieldkeys.SHAPE_TETRAHEDRA) != len(cells):
        return None
    prefix = fieldkeys.SHAPE_TETRAHEDRA + ".material_"
    ids = sorted(int(key[len(prefix):]) for key in stats if key.startswith(prefix))

    def row(suffix):
        figures = {name: stats[key + suffix] for name, key in _MEASURED}
        figures["tets"] = int(figures["tets"])
        return figures

    materials = {m: row(f".material_{m}") for m in ids}
    whole = row("")
    worst = {f"worst_{key}": whole[f"worst_{key}"] for key in SHAPE_KEYS}
    shape = {"min_dihedral": angles, "max_dihedral": vtk_to_numpy(largest)}
    # the report's histograms and the tetrahedra it names, from the same pass (report_lines and
    # worst_tetrahedra take them)
    histograms, named = {}, {}
    for key, bins_key, bins, tets_key in (
            ("min_dihedral", fieldkeys.SHAPE_MIN_DIHEDRAL_BIN, TEXT_BINS, fieldkeys.SHAPE_SMALLEST_MIN_DIHEDRAL_TET),
            ("max_dihedral", fieldkeys.SHAPE_MAX_DIHEDRAL_BIN, MAX_TEXT_BINS, fieldkeys.SHAPE_LARGEST_MAX_DIHEDRAL_TET)):
        histograms[key] = counted_bins(stats, bins_key, bins, len(cells))
        named[key] = _mesher_list(stats, [f"{tets_key}.{rank}" for rank in range(WORST_SHOWN)])
    if all(counts is not None for counts in histograms.values()):
        shape["histogram"] = histograms
    if all(ids is not None for ids in named.values()):
        shape["worst_first"] = {key: np.array(ids, dtype=np.int64) for key, ids in named.items()}
    return {"materials": materials, "tets": int(len(cells)), "vertices": int(grid.GetNumberOfPoints()),
            "nodes": int(grid.GetNumberOfPoints()), "volume": whole["volume"], "min_dihedral": whole["min_dihedral"],
            "max_dihedral": whole["worst_max_dihedral"], "worst": worst, "angles": angles, "shape": shape,
            "points": points, "cells": cells, "material": material, "order": 1}


def _mesher_list(stats, names):
    """The mesher's counts or indices under `names` (statistics of its measuring pass), or None when
    one is missing."""
    return [int(stats[name]) for name in names] if all(name in stats for name in names) else None


def centroid(q, t):
    """The centre of tetrahedron `t` of a quality() dict (its corners' mean)."""
    return q["points"][q["cells"][t]].mean(axis=0)


def report_lines(grid, title, names=None, source="mesh", recheck=True):
    """The quality report as lines of text (and the quality dict it was made from)."""
    import numpy as np

    q = quality(grid, source, measured=not recheck)
    names = {**material_names(grid), **(names or {})}
    stats = statistics(grid)
    lines = [f"{title}: {q['tets']} {'10-node ' if q['order'] == 2 else ''}tetrahedra, {q['vertices']} vertices"
             + (f", {q['nodes']} nodes" if q["order"] == 2 else ""),
             f"{'material':>8}  {'name':<18} {'tets':>9} {'volume [mm^3]':>14} {'min dihedral':>13} {'mean min':>9} "
             f"{'max dihedral':>13} {'radius ratio':>13} {'mean ratio':>11} {'edge ratio':>11}"]
    for m, row in q["materials"].items():
        lines.append(f"{m:>8}  {names.get(m, '?'):<18} {row['tets']:>9} {volume_text(row['volume']):>14} "
                     f"{row['min_dihedral']:>12.2f}° {row['mean_min_dihedral']:>8.1f}° " + _shape_columns(row))
    lines.append(f"{'all':>8}  {'':<18} {q['tets']:>9} {volume_text(q['volume']):>14} {q['min_dihedral']:>12.2f}° "
                 f"{q['angles'].mean():>8.1f}° " + _shape_columns(q["worst"]))
    lines.append("(max dihedral and the ratios are the worst tetrahedron's; the ratios are 1 for the regular "
                 "tetrahedron: radius ratio 3 r / R, mean ratio, shortest / longest edge)")
    for words, key, values, bins in (("minimal", "min_dihedral", q["angles"], TEXT_BINS),
                                     ("maximal", "max_dihedral", q["shape"]["max_dihedral"], MAX_TEXT_BINS)):
        counted = q["shape"].get("histogram", {}).get(key)  # a fresh mesh's: the mesher's pass counted them
        hist = counted if counted is not None else histogram(values, bins)
        lines.append(f"{words} dihedral angle per tetrahedron: "
                     + ", ".join(f"{int(a)}-{int(b)}°: {n}" for a, b, n in zip(bins, bins[1:], hist)))
    lines += shape_lines(q)
    segments = grid.GetFieldData().GetArray("FeatureSegments")
    if segments is not None and segments.GetValue(0) == 0:
        lines.append("feature lines: none given")
    elif fieldkeys.FEATURE_COVERAGE in stats:
        lines.append(f"feature lines present as mesh edges: {100 * stats[fieldkeys.FEATURE_COVERAGE]:.1f}%"
                     + (f" ({segments.GetValue(0)} segments)" if segments is not None else ""))
    q["validity"] = validity(grid, recheck)
    lines.append(validity_line(q["validity"]))
    if q["order"] == 2:
        line = (f"quadratic tetrahedra: smallest Jacobian ratio {q['min_jacobian_ratio']:.3g} (det J at the 10 nodes "
                f"and 4 Gauss points over the straight tetrahedron's; <= 0 is inverted)")
        if fieldkeys.QUADRATIC_SNAPPED_NODES in stats:
            line += (f"; {int(stats[fieldkeys.QUADRATIC_SNAPPED_NODES])} of {int(stats[fieldkeys.QUADRATIC_INTERFACE_EDGES])} interface "
                     f"mid-edge nodes on the true surfaces, {int(stats[fieldkeys.QUADRATIC_RELAXED_NODES])} pulled back for "
                     f"validity, {int(stats[fieldkeys.QUADRATIC_UNSNAPPED_INTERFACE_EDGES])} straight (junctions, creases)")
        lines.append(line)
    phases = [(phase, stats[f"optimisation.{phase}_steps"], stats.get(f"optimisation.{phase}_cut_short"),
               stats.get(f"time.{phase}", 0.0)) for phase in ("perturbation", "exudation")
              if f"optimisation.{phase}_steps" in stats]
    if phases:
        def phase_text(phase, steps, cut, seconds):
            if phase == "perturbation" and stats.get("optimisation.perturbation_skipped"):
                return f"perturbation not needed (every tetrahedron above {stats['optimisation.perturbation_last_bound']:g}°)"
            return f"{phase} {int(steps)} steps in {seconds:.1f} s, " + ("ended at its budget" if cut else "done")
        lines.append("optimisation: " + "; ".join(phase_text(*phase) for phase in phases))
    if fieldkeys.IMPROVEMENT_OUTSIDE_BEFORE in stats:
        window = f"[{stats[fieldkeys.IMPROVEMENT_MIN_ANGLE]:g}, {stats[fieldkeys.IMPROVEMENT_MAX_ANGLE]:g}]"
        lines.append(f"quality step: {int(stats[fieldkeys.IMPROVEMENT_OUTSIDE_BEFORE])} tetrahedra with a dihedral angle "
                     f"outside {window} degrees before it, {int(stats[fieldkeys.IMPROVEMENT_OUTSIDE_AFTER])} after"
                     + (f" ({int(stats[fieldkeys.IMPROVEMENT_OUTSIDE_HELD])} with every vertex held: on feature lines, "
                        "corners or where interfaces meet, their shape is the input's; see the worst tetrahedra above)"
                        if stats.get(fieldkeys.IMPROVEMENT_OUTSIDE_HELD) else "")
                     + f" ({stats.get(fieldkeys.TIME_IMPROVEMENT, 0.0):.1f} s, "
                     + ("ended at its budget of rounds)" if stats.get(fieldkeys.IMPROVEMENT_CUT_SHORT) else "done)"))
    for warning in strings(grid.GetFieldData(), fieldkeys.WARNINGS):
        if not warning.startswith("mesh validity:"):  # the line above says it
            lines.append("warning: " + warning)
    return lines, q


def counted_bins(stats, key, bins, tets):
    """The mesher's counts of its tetrahedra per bin (statistics "<key>.<low>_<high>", counted by its
    measuring pass, ShapeSummary.h) when it counted these bins for all `tets` tetrahedra; else None."""
    counts = _mesher_list(stats, [f"{key}.{low:g}_{high:g}" for low, high in zip(bins, bins[1:])])
    return counts if counts is not None and sum(counts) == tets else None


def histogram(values, bins):
    """np.histogram(values, bins)'s counts (bins [b0, b1), ..., [b(n-1), bn], values outside left out)
    without its sort of the values: one search among the few bin edges per value."""
    import numpy as np

    edges = np.asarray(bins, dtype=np.float64)
    index = np.searchsorted(edges, values, side="right") - 1
    index[values == edges[-1]] = len(edges) - 2  # the last bin holds its right edge
    inside = (index >= 0) & (index < len(edges) - 1)
    return np.bincount(index[inside], minlength=len(edges) - 1)


def worst_tetrahedra(q, key, count=WORST_SHOWN):
    """Indices of the `count` worst tetrahedra by shape measure `key` (largest max_dihedral, else
    smallest), worst first."""
    import numpy as np

    counted = q["shape"].get("worst_first", {}).get(key)  # a fresh mesh's: the mesher's pass found them
    if counted is not None and count == len(counted):
        return counted
    values = q["shape"][key]
    keyed = -values if key == "max_dihedral" else values
    if len(keyed) > count:  # a partition finds the count-th value; only those up to it are sorted
        cut = np.partition(keyed, count - 1)[count - 1]
        few = np.flatnonzero(keyed <= cut)  # with its ties, in index order: as a stable sort of all
        order = few[np.argsort(keyed[few], kind="stable")]
    else:
        order = np.argsort(keyed, kind="stable")
    return order[:count]


def _shape_columns(row):
    return (f"{row['worst_max_dihedral']:>12.2f}° {row['worst_radius_ratio']:>13.3f} {row['worst_mean_ratio']:>11.3f} "
            f"{row['worst_edge_ratio']:>11.3f}")


def shape_lines(q):
    """The worst tetrahedra by smallest and by largest dihedral angle, with where they are."""
    shape, lines = q["shape"], []
    for key, words in (("min_dihedral", "smallest"), ("max_dihedral", "largest")):
        items = [f"{shape[key][t]:.2f}° in #{t} (material {int(q['material'][t])}) at "
                 f"({', '.join(f'{x:.4g}' for x in centroid(q, t))})" for t in worst_tetrahedra(q, key)]
        lines.append(f"worst tetrahedra by {words} dihedral angle: " + "; ".join(items))
    return lines


def save_histogram(q, png_path, names=None, title=None):
    """Saves the histograms of the per-tetrahedron minimal and maximal dihedral angles, stacked by
    material, side by side as PNG."""
    import numpy as np
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    names = names or {}
    figure = Figure(figsize=(11, 4.5), dpi=100)
    FigureCanvasAgg(figure)
    smallest, largest = figure.subplots(1, 2)
    ids = list(q["materials"])
    # the colours of the rendered mesh (render.py: ParaView's "Brewer Qualitative Set1", in id order)
    set1 = colormaps["Set1"].colors
    colours = [set1[i % len(set1)] for i in range(len(ids))]
    labels = [f"{m}: {names[m]}" if m in names else str(m) for m in ids]
    for axes, values, bins, words in ((smallest, q["angles"], np.arange(0, 72, 1.0), "minimal"),
                                      (largest, q["shape"]["max_dihedral"], np.arange(60, 181, 2.0), "maximal")):
        axes.hist([values[q["material"] == m] for m in ids], bins=bins, stacked=True, color=colours, label=labels)
        axes.set_xlabel(f"{words} dihedral angle of the tetrahedron [°]")
        axes.set_ylabel("tetrahedra")
        axes.set_xlim(bins[0], bins[-1])
    smallest.legend(title=fieldkeys.MATERIAL)
    figure.suptitle(title or "Dihedral angles")
    figure.tight_layout()
    from .atomic import atomic_output

    with atomic_output(png_path) as temporary:
        figure.savefig(temporary, format="png")


def section(grid, axis=None, source="mesh"):
    """The mesh cut by the plane through its bounding box's centre normal to `axis` (0, 1, 2; default
    its thinnest axis, so the plane holds the longest ones): (polygons [n, 4, 2] in the plane's two
    other coordinates (triangles repeat a corner), their materials, axis, the plane's position,
    the names of the two in-plane axes)."""
    import numpy as np

    points, cells, material = tetrahedra(grid, source)
    lo, hi = points.min(axis=0), points.max(axis=0)
    if axis is None:
        axis = int(np.argmin(hi - lo))
    position = float((lo[axis] + hi[axis]) / 2)
    distance = points[:, axis] - position
    distance[distance == 0] = 1e-9 * float((hi - lo).max() or 1)  # points on the plane: on one side
    d = distance[cells]
    above = d > 0
    crossing = above.any(axis=1) & ~above.all(axis=1)
    cells, d, material = cells[crossing], d[crossing], material[crossing]
    p = points[cells]
    corners, valid = [], []
    for i, j in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
        crosses = (d[:, i] > 0) != (d[:, j] > 0)  # only these edges have a corner (others: no division)
        t = np.divide(d[:, i], d[:, i] - d[:, j], out=np.zeros(len(d)), where=crosses)[:, None]
        corners.append(p[:, i] + t * (p[:, j] - p[:, i]))
        valid.append(crosses)
    corners, valid = np.stack(corners, axis=1), np.stack(valid, axis=1)  # [n, 6, 3], [n, 6]
    plane = [a for a in range(3) if a != axis]
    corners = corners[:, :, plane]
    # 3 or 4 corners per tetrahedron, ordered by angle around their centre
    centre = (np.where(valid[:, :, None], corners, 0.0)).sum(axis=1) / valid.sum(axis=1)[:, None]
    angle = np.arctan2(corners[:, :, 1] - centre[:, None, 1], corners[:, :, 0] - centre[:, None, 0])
    angle = np.where(valid, angle, np.inf)
    order = np.argsort(angle, axis=1, kind="stable")[:, :4]
    polygons = np.take_along_axis(corners, order[:, :, None], axis=1)
    triangle = valid.sum(axis=1) == 3
    polygons[triangle, 3] = polygons[triangle, 2]  # a repeated last corner keeps the triangle's area
    names = "xyz"
    return polygons, material, axis, position, (names[plane[0]], names[plane[1]])


def save_section(grid, png_path, names=None, title=None, source="mesh"):
    """Saves the mesh's cross-section (see section()) as a PNG: the cut tetrahedra coloured by
    material (the histogram's colours), their edges drawn."""
    import numpy as np
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    from .writers import tetrahedra as _tetrahedra

    names = names or {}
    ids = sorted(set(_tetrahedra(grid, source)[2].tolist()))
    polygons, material, axis, position, (u, v) = section(grid, source=source)
    set1 = colormaps["Set1"].colors
    colour = {m: set1[i % len(set1)] for i, m in enumerate(ids)}
    figure = Figure(figsize=(7, 7), dpi=100)
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    axes.add_collection(PolyCollection(polygons, facecolors=[colour[m] for m in material.tolist()],
                                       edgecolors=(0.15, 0.15, 0.15), linewidths=0.2))
    if len(polygons):
        lo, hi = polygons.reshape(-1, 2).min(axis=0), polygons.reshape(-1, 2).max(axis=0)
        pad = 0.03 * float(np.max(hi - lo) or 1)
        axes.set_xlim(lo[0] - pad, hi[0] + pad)
        axes.set_ylim(lo[1] - pad, hi[1] + pad)
    axes.set_aspect("equal")
    axes.set_xlabel(f"{u} [mm]")
    axes.set_ylabel(f"{v} [mm]")
    axes.set_title(title or f"Section at {'xyz'[axis]} = {position:.4g}")
    axes.legend(handles=[Patch(color=colour[m], label=f"{m}: {names[m]}" if m in names else str(m)) for m in ids],
                title=fieldkeys.MATERIAL, loc="upper right", fontsize="small")
    figure.tight_layout()
    from .atomic import atomic_output

    with atomic_output(png_path) as temporary:
        figure.savefig(temporary, format="png")
