# SPDX-License-Identifier: GPL-3.0-or-later
"""Meshing a scene in one call, shared by the command line and Python::

    import oraclemesh as om
    result = om.mesh("scene.json")       # or a dict in the scene format, or a loaded Scene
    print(result.report)                 # the quality report `oraclemesh mesh` prints
    result.save("out.inp", "out.vtu")    # any of MESH_FORMATS, with the boundary and interface sets
    om.mesh("scene.json", element_order=2)  # 10-node tetrahedra, curved on the interfaces
    grid = result.grid                   # the vtkUnstructuredGrid
"""
import os
import sys
import time

from .defaults import CRITERIA_KEYS, FEATURE_SOURCES, MESH_PROPERTIES, domain_criteria_unset, mesh_defaults
from .fielddata import add_material_names
from .errors import OracleMeshError, scene_spelling, update
from .scene import Scene, build_scene, load_scene
from . import fieldkeys


def mesher_for(scene, strategy=None, element_order=None, features=None, threads=None, feature_angle=None):
    """The tetrahedralizer set up from the scene's validated "mesh" block (criteria, the
    "mesh.materials" table, feature lines, strategy, seed, ...); a key the scene leaves out keeps the
    filter's default (defaults.py). The domains carry their own criteria; the core merges them
    (MeshCriteria.h). `strategy`, `element_order` (1 or 2) and `threads` override the scene's, `features`
    (None, Given, Automatic, Both: which feature lines are kept) the scene's "mesh.features.use",
    `feature_angle` its "mesh.features.feature_angle": one angle for a surface's sharp edges, those of
    "from_surface" (vtkFeatureEdges) and the creases Automatic/Both find (the filter's CreaseAngle,
    whose default applies to both when neither gives one)."""
    from vtkmodules.vtkFiltersCore import vtkAppendPolyData, vtkFeatureEdges

    from . import vtkFeaturePreservingTetrahedralizer

    spec = scene.mesh
    mesher = vtkFeaturePreservingTetrahedralizer()
    mesher.SetInputConnection(0, scene.oracle.GetOutputPort())
    if strategy or "strategy" in spec:
        getattr(mesher, "SetFeatureStrategyTo" + (strategy or spec["strategy"]))()
    for key, value in spec.get("criteria", {}).items():
        getattr(mesher, "Set" + CRITERIA_KEYS[key])(value)
    unset = domain_criteria_unset()
    for material, overrides in sorted(spec.get("materials", {}).items()):
        values = [overrides.get(key, unset) for key in CRITERIA_KEYS]
        mesher.SetMaterialCriteria(material, *values)
    use = features or (spec.get("features") or {}).get("use")
    if use:
        sources = {v.lower(): v for v in FEATURE_SOURCES}
        if str(use).lower() not in sources:
            raise OracleMeshError(f"features: must be one of {', '.join(FEATURE_SOURCES)}, got {use!r}")
        getattr(mesher, "SetFeaturesTo" + sources[str(use).lower()])()
    features = spec.get("features")
    if feature_angle is None and features:
        feature_angle = features.get("feature_angle")
    if feature_angle is not None:
        if isinstance(feature_angle, bool) or not isinstance(feature_angle, (int, float)) or not 0 < feature_angle <= 180:
            raise OracleMeshError(f"feature_angle: must be a number above 0 and at most 180 degrees (180 = no sharp "
                                  f"edges), got {feature_angle!r}")
        mesher.SetCreaseAngle(feature_angle)
    if features and (features["from_surface"] or features["files"]):
        parts = []
        for index in features["from_surface"]:
            edges = vtkFeatureEdges()
            # the domain's output: triangulated and welded (an unwelded box has no sharp edges)
            edges.SetInputConnection(scene.domains[index].GetOutputPort())
            edges.BoundaryEdgesOff()
            edges.NonManifoldEdgesOff()
            edges.ManifoldEdgesOff()
            edges.SetFeatureAngle(mesher.GetCreaseAngle())
            parts.append(edges)
        parts.extend(scene.feature_readers)
        sizes = [None] * len(features["from_surface"]) + list(scene.feature_edge_sizes)
        names = [f"the sharp edges of {scene.domains[i].GetMaterialName()}" for i in features["from_surface"]] + features["files"]
        # whose sharp edges each part's lines are (the domain's index = its priority in the oracle),
        # -1 for the files: the filter clips a part's edges to where that part survives
        owners = list(features["from_surface"]) + [-1] * len(scene.feature_readers)
        sized = any(size is not None for size in sizes) or (len(parts) > 1 and any(
            _edge_size_array(part) is not None for part in scene.feature_readers))
        if sized or features["from_surface"]:
            # per-feature edge sizes: each part's lines get an "EdgeSize" cell array (-1 = none), so
            # that appending keeps it (vtkAppendPolyData drops arrays some inputs lack); with
            # from_surface each part's lines say whose edges they are (fieldkeys.EDGES_OF_DOMAIN)
            if sized:
                parts = [_with_edge_sizes(part, size, name) for part, size, name in zip(parts, sizes, names)]
            if features["from_surface"]:
                parts = [_with_owner(part, owner) for part, owner in zip(parts, owners)]
            lines = vtkAppendPolyData()
            for part in parts:
                lines.AddInputData(part)
        elif len(parts) == 1:
            lines = parts[0]
        else:
            lines = vtkAppendPolyData()
            for part in parts:
                lines.AddInputConnection(part.GetOutputPort())
        mesher.SetInputConnection(1, lines.GetOutputPort())
        scene.feature_lines = (lines, parts)  # keeps the Python objects alive with the scene
    for key, prop in MESH_PROPERTIES.items():
        if key in spec:
            getattr(mesher, "Set" + prop)(spec[key])
    if element_order is not None:
        if element_order not in (1, 2) or isinstance(element_order, bool):
            raise OracleMeshError(f"element_order: must be 1 (linear) or 2 (quadratic tetrahedra), got {element_order!r}")
        mesher.SetElementOrder(element_order)
    if threads is not None:
        mesher.SetThreads(threads)
    return mesher


def _edge_size_array(part):
    """The "EdgeSize" cell array of a feature-line source's output (None without one)."""
    part.Update()
    return part.GetOutput().GetCellData().GetArray("EdgeSize")


def _with_edge_sizes(part, size, name):
    """The lines of `part` with an "EdgeSize" cell array: the file's own values, `size` (the scene's
    "edge_size" of that entry) where the file has none (-1), -1 where neither gives one. A line that
    the file and the scene give different values is a contradiction."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    own = _edge_size_array(part)
    lines = vtkPolyData()
    lines.ShallowCopy(part.GetOutput())
    values = vtkDoubleArray()
    values.SetName("EdgeSize")
    values.SetNumberOfTuples(lines.GetNumberOfCells())
    for cell in range(lines.GetNumberOfCells()):
        value = own.GetComponent(cell, 0) if own is not None else -1.0
        if size is not None:
            if value != -1.0 and value != size:
                raise OracleMeshError(f"feature lines: line {cell} of {name} gets EdgeSize {value:g} from the file and "
                                      f"{size:g} from the scene's edge_size (give it once: drop one of them)")
            value = size
        values.SetValue(cell, value)
    lines.GetCellData().RemoveArray("EdgeSize")
    lines.GetCellData().AddArray(values)
    return lines


def _with_owner(lines, owner):
    """The lines of `lines` (a vtkPolyData, or an algorithm whose output they are) with the integer
    cell array fieldkeys.EDGES_OF_DOMAIN: `owner` on every line (the index of the domain whose sharp
    edges they are, -1 for a user's own lines)."""
    from vtkmodules.vtkCommonCore import vtkIntArray
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    if not isinstance(lines, vtkPolyData):
        lines.Update()
        copy = vtkPolyData()
        copy.ShallowCopy(lines.GetOutput())
        lines = copy
    values = vtkIntArray()
    values.SetName(fieldkeys.EDGES_OF_DOMAIN)
    values.SetNumberOfTuples(lines.GetNumberOfCells())
    values.Fill(owner)
    lines.GetCellData().RemoveArray(fieldkeys.EDGES_OF_DOMAIN)
    lines.GetCellData().AddArray(values)
    return lines


def describe(grid, names, feature_segments):
    """Stores {material id: name} (MaterialIds, MaterialNames) and the number of feature-line
    segments given (FeatureSegments) in the mesh's field data, for the report and the writers."""
    from vtkmodules.vtkCommonCore import vtkIntArray

    count = vtkIntArray()
    count.SetName("FeatureSegments")
    count.InsertNextValue(feature_segments)
    grid.GetFieldData().AddArray(count)
    add_material_names(grid.GetFieldData(), names)


def add_input_warnings(grid, warnings):
    """Appends warnings about the inputs that only the scene knows (the frames its files declare) to
    the mesh's field data, Warnings and InputWarnings, as the mesher's own: the report prints them and
    --strict fails on them."""
    from vtkmodules.vtkCommonCore import vtkStringArray

    for name in (fieldkeys.WARNINGS, fieldkeys.INPUT_WARNINGS):
        if not warnings:
            break
        array = grid.GetFieldData().GetAbstractArray(name)
        if not isinstance(array, vtkStringArray):
            array = vtkStringArray()
            array.SetName(name)
            grid.GetFieldData().AddArray(array)
        for warning in warnings:
            array.InsertNextValue(warning)


def as_scene(scene, base_dir=None):
    """A Scene from a JSON scene path, a scene dict (relative paths against `base_dir`, default the
    working folder) or a Scene."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return load_scene(os.fspath(scene))
    if isinstance(scene, dict):
        return build_scene(scene, base_dir or os.getcwd(), source="scene")
    raise OracleMeshError(f"scene: expected a scene file path, a dict in the scene format or a Scene, "
                          f"got {type(scene).__name__}")


class MeshResult:
    """A meshed scene.

    ``grid``: the vtkUnstructuredGrid (cell data Material, MinDihedralAngle, MaxDihedralAngle, RadiusEdgeRatio,
    Defects; field data: statistics, warnings, material names); ``scene``; ``material_names``
    {id: name}; ``strategy``; ``seconds`` (meshing time); ``statistics`` {name: value} (the mesher's:
    volumes, validity counts, timings, ...); ``quality`` (per-material table, see report.quality);
    ``report`` (the quality report as text); ``warnings`` (all the mesher's, also in the report);
    ``input_warnings`` (those about the inputs: frames or units that do not match, materials or labels
    without a tetrahedron; the command line's ``--strict`` fails on them); ``surface_sets``;
    ``save(path, ...)``."""

    def __init__(self, grid, scene, strategy, seconds, title):
        from .fielddata import strings
        from .report import report_lines, statistics

        self.grid, self.scene, self.strategy, self.seconds = grid, scene, strategy, seconds
        self.material_names = scene.material_names()
        self.statistics = statistics(grid)
        self.warnings = strings(grid.GetFieldData(), fieldkeys.WARNINGS)
        self.input_warnings = strings(grid.GetFieldData(), fieldkeys.INPUT_WARNINGS)
        lines, self.quality = report_lines(grid, title, self.material_names, recheck=False)
        self.report = "\n".join(lines)
        self._arrays = None
        self._separating = separating_faces_of(grid)

    def save(self, *paths):
        """Writes the mesh to each path, the format by extension (.vtu, .inp, .msh, .mesh; see
        writers.py), with its boundary and interface sets; returns the files written (a .vtu also
        writes ``<name>_surfaces.vtu``). Raises OracleMeshError naming a path that fails, after removing
        the files this call wrote before it."""
        from .writers import MESH_FORMATS, write_mesh

        for path in paths:  # refuse a bad name before writing anything
            ext = os.path.splitext(os.fspath(path))[1].lower()
            if ext not in MESH_FORMATS:
                raise OracleMeshError(f"{path}: unknown mesh format '{ext}' (use one of {', '.join(MESH_FORMATS)})")
        written = []
        try:
            for path in paths:
                written += write_mesh(self.grid, os.fspath(path), self.material_names, self._mesh_arrays())
        except BaseException:
            for done in written:  # all the files or none: no set half written
                try:
                    os.remove(done)
                except OSError:
                    pass
            raise
        return written

    def _mesh_arrays(self):
        from .writers import MeshArrays

        if self._arrays is None:  # computed once for every save and surface_sets
            # the validity check measured every tetrahedron of a fresh mesh: none inverted or flat
            # means every volume is positive
            st = self.statistics
            oriented = self._separating is not None and st.get(fieldkeys.VALIDITY_INVERTED_TETRAHEDRA) == 0 \
                and st.get(fieldkeys.VALIDITY_FLAT_TETRAHEDRA) == 0
            self._arrays = MeshArrays(self.grid, self.material_names, separating=self._separating, oriented=oriented,
                                      ids=self._material_ids())
        return self._arrays

    def _material_ids(self):
        """The materials of a fresh mesh's cells from its statistics (tetrahedra.material_<id>, counted
        by the validity check's pass over every tetrahedron), or None when they do not cover every
        cell."""
        prefix = "tetrahedra.material_"
        counts = {int(k[len(prefix):]): v for k, v in self.statistics.items() if k.startswith(prefix)}
        if self._separating is None or sum(counts.values()) != self.grid.GetNumberOfCells():
            return None
        return sorted(m for m, n in counts.items() if n > 0)

    @property
    def surface_sets(self):
        """The boundary and interface sets (surfaces.SurfaceSets: ``names``, ``faces``, ...) the files get."""
        return self._mesh_arrays().sets

    def __repr__(self):
        return (f"<MeshResult: {self.quality['tets']} tetrahedra, {len(self.quality['materials'])} materials, "
                f"min dihedral {self.quality['min_dihedral']:.1f} deg>")


def separating_faces_of(grid):
    """The mesher's boundary and interface faces (field array SeparatingFaces: found by its validity
    check) as surfaces.surface_sets takes them, or None when the grid does not carry them for its
    cells (then the writers find them)."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    array = grid.GetFieldData().GetArray(fieldkeys.SEPARATING_FACES)
    if array is None or array.GetNumberOfComponents() != 2:
        return None
    faces = vtk_to_numpy(array).astype(np.int64).reshape(-1, 2)
    if len(faces) and not (0 <= faces[:, 0].min() and faces[:, 0].max() < 4 * grid.GetNumberOfCells()):
        return None
    return faces[:, 0], faces[:, 1]


def mesh(scene, strategy=None, progress=None, base_dir=None, updater=update, element_order=None, features=None,
         threads=None, feature_angle=None):
    """Meshes a scene and returns a MeshResult (``.grid``, ``.report``, ``.statistics``, ``.save()``).

    `scene`: a JSON scene file path, a dict in the same format (see the README's "Scene files";
    relative file paths resolve against `base_dir`, default the working folder) or a loaded Scene.
    `strategy` overrides the scene's feature strategy ("Conforming", "None", "ProtectingBalls");
    `element_order` its "element_order" (1: 4-node tetrahedra, 2: 10-node ones with the mid-edge nodes
    of interface edges on the true surfaces);
    `features` which feature lines are kept ("None", "Given", "Automatic", "Both"; default the
    scene's "mesh.features.use", else Given); `feature_angle` the scene's "mesh.features.feature_angle"
    (degrees, default 60: a surface's sharp edges and the creases Automatic finds; 180 = none);
    `progress`, if given, is called with the mesher's progress (0..1); `updater` runs the mesher
    (default errors.update, called with a `warnings` list; the command line passes one that signals can
    abort). `threads` overrides
    the scene's "threads": 1 = sequential (the same seed gives the same mesh), N > 1 = the refinement
    on N threads (0 = every core; the mesh then differs from run to run, see docs/REFERENCE.md). Bad scenes
    and failed meshing raise OracleMeshError naming the problem; failed meshing raises MeshingError, whose
    ``statistics`` hold the figures so far (after the scene's "time_limit": vertices, tetrahedra,
    time.elapsed, time_limit)."""
    started = time.perf_counter()
    if threads is not None and (not isinstance(threads, int) or isinstance(threads, bool) or threads < 0):
        raise OracleMeshError(f"threads: must be an integer >= 0 (1 = sequential, 0 = every core), got {threads!r}")
    scene = as_scene(scene, base_dir)
    mesher = mesher_for(scene, strategy, element_order, features, threads, feature_angle)
    if progress is not None:
        mesher.AddObserver("ProgressEvent", lambda algorithm, event: progress(algorithm.GetProgress()))
    collected = []  # the mesher's warnings are the result's (its report): printed only when others
    grid = updater(mesher, warnings=collected)
    add_input_warnings(grid, scene.input_warnings())
    segments = mesher.GetOutputDataObject(2)
    describe(grid, scene.material_names(), segments.GetNumberOfCells() if segments is not None else 0)
    strategy = strategy or scene.mesh.get("strategy", mesh_defaults()["strategy"])
    seconds = time.perf_counter() - started
    result = MeshResult(grid, scene, strategy, seconds, f"Mesh of {scene.source} ({seconds:.1f} s, strategy {strategy})")
    for text in collected:  # those of the filters before the mesher, which the report lacks
        if text not in result.warnings:
            print(f"oraclemesh: warning: {scene_spelling(text)}", file=sys.stderr)
    return result
