# SPDX-License-Identifier: GPL-3.0-or-later
"""Command line: ``python3 -m oraclemesh <command> ...`` (see ``--help``)."""
import argparse
import os
import sys
import time

from .errors import OracleMeshError, update
from .scene import load_scene


def _write(data, path, writer_class):
    """Writes `data` with a VTK XML writer (zlib-compressed), creating the folder."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    writer = writer_class()
    writer.SetFileName(path)
    writer.SetInputData(data)
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        raise OracleMeshError(f"{path}: could not be written")


def _publish(lines, report_path):
    """Prints a report and, when asked, saves it."""
    report = "\n".join(lines)
    print(report)
    if report_path:
        with open(report_path, "w") as f:
            f.write(report + "\n")


def _sample(args):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    from . import vtkOracleSampler

    started = time.perf_counter()
    scene = load_scene(args.scene)
    sampler = vtkOracleSampler()
    sampler.SetInputConnection(scene.oracle.GetOutputPort())
    sampler.SetDimensions(*args.dims)
    image = update(sampler)
    if args.output:
        _write(image, args.output, vtkXMLImageDataWriter)
    names = scene.material_names()
    fd = image.GetFieldData()
    ids, volumes = fd.GetArray("MaterialIds"), fd.GetArray("MaterialVolume")
    total = sum(volumes.GetValue(i) for i in range(volumes.GetNumberOfTuples()))
    lines = [f"Oracle of {args.scene} sampled on {' x '.join(map(str, args.dims))} points "
             f"({time.perf_counter() - started:.2f} s)",
             f"{'material':>8}  {'name':<18} {'volume [mm^3]':>14} {'share':>7}"]
    for i in range(ids.GetNumberOfTuples()):
        m, v = ids.GetValue(i), volumes.GetValue(i)
        lines.append(f"{m:>8}  {names.get(m, '?'):<18} {v:>14.1f} {100 * v / total:>6.1f}%")
    lines.append(f"{'all':>8}  {'':<18} {total:>14.1f}")
    if args.output:
        lines.append(f"wrote {args.output} (point array 'Material', -1 outside): open it in ParaView")
    _publish(lines, args.report)
    return 0


CRITERIA_KEYS = {
    "facet_angle": "FacetAngle", "facet_size": "FacetSize", "facet_distance": "FacetDistance",
    "cell_size": "CellSize", "cell_radius_edge_ratio": "CellRadiusEdgeRatio", "edge_size": "EdgeSize",
}
STRATEGIES = ("Conforming", "None", "ProtectingBalls")


def _mesher_for(scene, args):
    """The tetrahedralizer set up from the scene's "mesh" block (criteria, per-material criteria,
    feature lines, strategy, seed), command-line options winning."""
    from vtkmodules.vtkFiltersCore import vtkFeatureEdges

    from . import vtkFeaturePreservingTetrahedralizer

    spec = scene.description.get("mesh", {})
    mesher = vtkFeaturePreservingTetrahedralizer()
    mesher.SetInputConnection(0, scene.oracle.GetOutputPort())
    strategy = args.strategy or spec.get("strategy", "Conforming")
    if strategy not in STRATEGIES:
        raise OracleMeshError(f"$.mesh.strategy: must be one of {', '.join(STRATEGIES)}, got {strategy!r}")
    getattr(mesher, "SetFeatureStrategyTo" + strategy)()
    for key, value in spec.get("criteria", {}).items():
        if key not in CRITERIA_KEYS:
            raise OracleMeshError(f"$.mesh.criteria.{key}: unknown (use {', '.join(CRITERIA_KEYS)})")
        getattr(mesher, "Set" + CRITERIA_KEYS[key])(float(value))
    for material, overrides in spec.get("materials", {}).items():
        values = [-1.0] * 6
        for key, value in overrides.items():
            if key not in CRITERIA_KEYS:
                raise OracleMeshError(f"$.mesh.materials.{material}.{key}: unknown criterion")
            values[list(CRITERIA_KEYS).index(key)] = float(value)
        mesher.SetMaterialCriteria(int(material), *values)
    features = spec.get("features")
    if features:
        names = [d.get("name") for d in scene.description["domains"]]
        source = features.get("from_surface")
        if source not in names or scene.description["domains"][names.index(source)]["type"] != "surface":
            raise OracleMeshError(f"$.mesh.features.from_surface: no surface domain named {source!r}")
        reader = scene.domains[names.index(source)].GetInputAlgorithm()
        edges = vtkFeatureEdges()
        edges.SetInputConnection(reader.GetOutputPort())
        edges.BoundaryEdgesOff()
        edges.NonManifoldEdgesOff()
        edges.ManifoldEdgesOff()
        edges.SetFeatureAngle(float(features.get("feature_angle", 60)))
        mesher.SetInputConnection(1, edges.GetOutputPort())
        scene.feature_edges = edges
    mesher.SetSeed(int(spec.get("seed", 0)))
    if "maximum_number_of_vertices" in spec:
        mesher.SetMaximumNumberOfVertices(int(spec["maximum_number_of_vertices"]))
    return mesher


def _mesh(args):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    started = time.perf_counter()
    scene = load_scene(args.scene)
    mesher = _mesher_for(scene, args)
    grid = update(mesher)
    _write(grid, args.output, vtkXMLUnstructuredGridWriter)
    fd = grid.GetFieldData()
    names_array, values_array = fd.GetAbstractArray("StatisticNames"), fd.GetArray("StatisticValues")
    stats = {names_array.GetValue(i): values_array.GetValue(i) for i in range(names_array.GetNumberOfValues())}
    material = vtk_to_numpy(grid.GetCellData().GetArray("Material"))
    angles = vtk_to_numpy(grid.GetCellData().GetArray("MinDihedralAngle"))
    names = scene.material_names()
    lines = [f"Mesh of {args.scene}: {grid.GetNumberOfCells()} tetrahedra, {grid.GetNumberOfPoints()} vertices "
             f"({time.perf_counter() - started:.1f} s, strategy {args.strategy or scene.description.get('mesh', {}).get('strategy', 'Conforming')})",
             f"{'material':>8}  {'name':<18} {'tets':>9} {'volume [mm^3]':>14} {'min dihedral':>13}"]
    for m in sorted(set(material.tolist())):
        sel = material == m
        lines.append(f"{m:>8}  {names.get(m, '?'):<18} {int(sel.sum()):>9} "
                     f"{stats.get(f'volume.material_{m}', 0):>14.1f} {angles[sel].min():>12.2f}°")
    hist, edges = np.histogram(angles, bins=[0, 5, 10, 20, 30, 40, 50, 60, 90])
    lines.append("dihedral angles: " + ", ".join(f"{int(a)}-{int(b)}°: {n}" for a, b, n in zip(edges, edges[1:], hist)))
    lines.append(f"min dihedral {stats['min_dihedral_angle']:.2f}°, mean of per-tet minima "
                 f"{stats['mean_min_dihedral_angle']:.1f}°, feature lines present as mesh edges: "
                 f"{100 * stats['feature_coverage']:.1f}%")
    warnings = fd.GetAbstractArray("Warnings")
    for i in range(warnings.GetNumberOfValues()):
        lines.append("warning: " + warnings.GetValue(i))
    lines.append(f"wrote {args.output} (cell data Material, MinDihedralAngle, RadiusEdgeRatio): open it in ParaView")
    _publish(lines, args.report)
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="oraclemesh", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("sample", help="sample a scene's oracle to a label image and report material volumes")
    p.add_argument("scene", help="scene file (JSON)")
    p.add_argument("-o", "--output", help="output image (.vti)")
    p.add_argument("--dims", type=int, nargs=3, default=(128, 128, 128), metavar=("NX", "NY", "NZ"),
                   help="grid points per axis (default 128 128 128)")
    p.add_argument("--report", help="also write the report to this text file")
    p.set_defaults(run=_sample)
    p = sub.add_parser("mesh", help="tetrahedralize a scene (its \"mesh\" block sets the criteria) to a .vtu")
    p.add_argument("scene", help="scene file (JSON)")
    p.add_argument("-o", "--output", required=True, help="output mesh (.vtu)")
    p.add_argument("--strategy", choices=STRATEGIES, help="feature strategy (default: the scene's, else Conforming)")
    p.add_argument("--report", help="also write the quality report to this text file")
    p.set_defaults(run=_mesh)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except OracleMeshError as e:
        print(f"oraclemesh: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
