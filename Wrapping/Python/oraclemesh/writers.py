# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh and image writers chosen by file extension, each with the mesh's boundary and interface
surfaces (``surfaces.py``: one set per material pair, ``CORTICAL_BONE__IMPLANT``,
``CORTICAL_BONE__EXTERIOR``; the faces sit on the first-named material's side).

- ``.vtu``  VTK XML (zlib): the tetrahedra with cell data Material, ...; the text of the field data
  as component names (``fielddata.py``), so meshio reads it too. Next to it ``<name>_surfaces.vtu``:
  the surface triangles with cell data ``Surface`` (the surface tag, below) and ``Materials`` (the
  owner material and the other one, -1 = exterior), field data ``SurfaceTags`` whose components are
  named after the surfaces.
- ``.inp``  Abaqus: nodes, C3D4 elements, one ``*ELSET`` per material named after it (``cortical
  bone`` -> ``CORTICAL_BONE``, ``MATERIAL_<id>`` without a name); per surface an element-face
  ``*SURFACE`` (faces S1..S4 of the owner's elements) and an ``*NSET`` of its nodes, both under the
  surface's name; ``** OracleMesh material`` comments give each element set's material id.
- ``.msh``  Gmsh 2.2 (ASCII): tetrahedra tagged with their material id (physical and elementary
  tag), triangles with their surface tag; ``$PhysicalNames`` name both (dimension 3 and 2).
- ``.mesh`` Medit: tetrahedron references are the material ids, triangle references the surface
  tags; ``#`` comments name both.

10-node tetrahedra (``element_order`` 2, VTK_QUADRATIC_TETRA) are written as such: .vtu quadratic
tetrahedra with ``_surfaces.vtu`` 6-node triangles (VTK_QUADRATIC_TRIANGLE); .inp C3D10 (the
element-face ``*SURFACE`` works unchanged, each ``*NSET`` gets the faces' mid-edge nodes too); .msh
Gmsh tetrahedra of 10 nodes and triangles of 6; .mesh ``TetrahedraP2`` and ``TrianglesP2`` (libMeshb's
keywords; node order corners, then edges 12 23 31 (14 24 34), said in a comment; gmsh and
``oraclemesh report`` read them, meshio 5.0 cannot).

Surface tags are the largest material id + 1, + 2, ... in the surfaces' order (sorted by material
pair, the exterior last), the same in every format. Every file is written atomically (``atomic.py``).

A large mesh is written beside itself, not copied: MeshArrays reads the grid's own points,
connectivity and Material (read-only views where the types match, as in the mesher's meshes), the
.vtu goes to VTK's writer as a shallow copy, and .inp, .msh and .mesh are formatted a block of rows
at a time (``meshtext.py``); what they add is one block's text and the surfaces' arrays.
"""
import os

from . import fieldkeys
from .atomic import atomic_output
from .errors import OracleMeshError


def __getattr__(name):
    # abaqus_set_name, surface_sets: API here, defined in surfaces.py, which imports numpy: loaded
    # when first used, so `oraclemesh mesh` loads numpy after the meshing (the process floor and the
    # mesher's peak memory without numpy's 20 MB).
    if name in ("abaqus_set_name", "surface_sets"):
        from . import surfaces

        return getattr(surfaces, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def material_set_names(ids, names=None):
    """surfaces.material_set_names (loaded on first use, see __getattr__)."""
    from .surfaces import material_set_names as set_names

    return set_names(ids, names)


MESH_FORMATS = (".vtu", ".inp", ".msh", ".mesh")
SURFACES_SUFFIX = "_surfaces.vtu"


def _extension(path):
    return os.path.splitext(path)[1].lower()


def surfaces_path(vtu_path):
    """The companion file holding the surfaces of a .vtu mesh: ``x.vtu`` -> ``x_surfaces.vtu``."""
    return os.path.splitext(vtu_path)[0] + SURFACES_SUFFIX


def write_vtk_xml(data, path, writer_class):
    """Writes `data` with a VTK XML writer (zlib-compressed) atomically; raises OracleMeshError
    naming `path` and VTK's reason when the writer fails."""
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING

    from .errors import _clean

    messages = []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, calldata):
        messages.append(_clean(calldata))

    with atomic_output(path) as temporary:
        writer = writer_class()
        writer.SetFileName(temporary)
        writer.SetInputData(data)
        writer.SetCompressorTypeToZLib()
        tag = writer.AddObserver("ErrorEvent", on_error)
        try:
            ok = writer.Write()
        finally:
            writer.RemoveObserver(tag)
        if not ok or messages or writer.GetErrorCode():
            code = writer.GetErrorCode()
            reason = messages[0] if messages else (f"{writer.GetClassName()} failed (VTK error code {code})" if code
                                                   else f"{writer.GetClassName()} failed")
            raise OracleMeshError(f"{path}: could not be written: {reason.replace(temporary, path)}")


def element_nodes(grid, source="mesh"):
    """(points [n x 3], element nodes [m x 4] or, for 10-node tetrahedra, [m x 10] point ids (VTK
    order), Material [m]) of a tetrahedral vtkUnstructuredGrid: all linear or all quadratic. Read-only
    arrays, views of the grid's where the types allow (float64, int64, Material's integer type)."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.util.vtkConstants import VTK_QUADRATIC_TETRA, VTK_TETRA

    if grid.GetNumberOfCells() == 0:
        raise OracleMeshError(f"{source}: the mesh has no cells")
    types = vtk_to_numpy(grid.GetCellTypesArray())
    kind = VTK_QUADRATIC_TETRA if types[0] == VTK_QUADRATIC_TETRA else VTK_TETRA
    if (types != kind).any():
        wrong = int(np.argmax(types != kind))
        raise OracleMeshError(f"{source}: cell {wrong} is not a {'quadratic ' if kind != VTK_TETRA else ''}"
                              f"tetrahedron like cell 0 (VTK cell type {int(types[wrong])})")
    material = grid.GetCellData().GetArray(fieldkeys.MATERIAL)
    if material is None:
        raise OracleMeshError(f"{source}: no cell array '{fieldkeys.MATERIAL}' (write meshes with 'oraclemesh mesh')")
    width = 10 if kind == VTK_QUADRATIC_TETRA else 4
    material = vtk_to_numpy(material)
    return (_read_only(vtk_to_numpy(grid.GetPoints().GetData()), np.float64),
            _read_only(vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, width), np.int64),
            _read_only(material, material.dtype if np.issubdtype(material.dtype, np.integer) else np.int64))


def _read_only(array, dtype):
    """`array` as `dtype`: the mesh's own memory when it has that type already (a mesh from the mesher:
    float64 points, int64 connectivity), so a large mesh is not held twice; read-only, as what reads
    it must leave the mesh as it is."""
    import numpy as np

    array = np.asarray(array, dtype=dtype)
    array.flags.writeable = False
    return array


def tetrahedra(grid, source="mesh"):
    """(points [n x 3], tetrahedra [m x 4] point ids, Material [m]) of a tetrahedral vtkUnstructuredGrid;
    of 10-node tetrahedra, their corners."""
    points, nodes, material = element_nodes(grid, source)
    return points, nodes[:, :4], material


class MeshArrays:
    """What every format needs, computed once per mesh: points, cells (corners), nodes (all nodes:
    the cells, or 10 per 10-node tetrahedron), quadratic, material, {id: name}, the SurfaceSets and
    each surface's tag, face_nodes (the surface triangles' nodes: 3, or 6 for quadratic meshes)."""

    def __init__(self, grid, names=None, source="mesh", separating=None, oriented=False, ids=None):
        """`separating`: the boundary and interface faces when known, `oriented`: every tetrahedron
        known to have a positive volume (surfaces.surface_sets); `ids`: the sorted material ids of
        the cells when known (else read from them)."""
        from .quadratic import face_nodes
        from .surfaces import material_ids, surface_sets

        self.points, self.nodes, self.material = element_nodes(grid, source)
        self.cells = self.nodes[:, :4]
        self.quadratic = self.nodes.shape[1] == 10
        self.names = dict(names or {})
        self.ids = list(ids) if ids is not None else material_ids(self.material)
        self.sets = surface_sets(self.points, self.cells, self.material, self.names, separating, self.ids, oriented)
        self.face_nodes = face_nodes(self.sets.faces, self.nodes, self.sets.owner) if self.quadratic \
            else self.sets.faces
        first = max(self.ids) + 1
        self.tags = [first + i for i in range(len(self.sets))]

    def surface_tag(self):
        """The surface tag of each face of ``sets``."""
        import numpy as np

        return np.asarray(self.tags, dtype=np.int64)[self.sets.surface] if len(self.tags) else \
            np.zeros(0, np.int64)


def _write_vtu(grid, path, arrays):
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.util.vtkConstants import VTK_QUADRATIC_TRIANGLE, VTK_TRIANGLE
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    from .fielddata import _escape, without_strings

    write_vtk_xml(without_strings(grid), path, vtkXMLUnstructuredGridWriter)
    sets = arrays.sets
    used, local = np.unique(arrays.face_nodes, return_inverse=True)  # only the surfaces' points
    surfaces = vtkUnstructuredGrid()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(arrays.points[used], deep=True))
    surfaces.SetPoints(points)
    triangles = vtkCellArray()
    width = arrays.face_nodes.shape[1]
    offsets = np.arange(0, width * len(sets.faces) + 1, width, dtype=np.int64)
    triangles.SetData(numpy_to_vtk(offsets, deep=True), numpy_to_vtk(local.ravel().astype(np.int64), deep=True))
    surfaces.SetCells(VTK_QUADRATIC_TRIANGLE if arrays.quadratic else VTK_TRIANGLE, triangles)
    tag = numpy_to_vtk(arrays.surface_tag().astype(np.int32), deep=True)
    tag.SetName("Surface")
    surfaces.GetCellData().AddArray(tag)
    pair = numpy_to_vtk(sets.pairs.astype(np.int32), deep=True)
    pair.SetName(fieldkeys.MATERIALS)
    pair.SetComponentName(0, "owner")
    pair.SetComponentName(1, "other")
    surfaces.GetCellData().AddArray(pair)
    names = vtkIntArray()
    names.SetName("SurfaceTags")
    names.SetNumberOfComponents(max(len(sets), 1))
    names.SetNumberOfTuples(1 if len(sets) else 0)
    for i, (t, name) in enumerate(zip(arrays.tags, sets.names)):
        names.SetComponent(0, i, t)
        names.SetComponentName(i, _escape(name))
    surfaces.GetFieldData().AddArray(names)
    companion = surfaces_path(path)
    write_vtk_xml(surfaces, companion, vtkXMLUnstructuredGridWriter)
    return [path, companion]


def _write_text(path, arrays, block_rows):
    """Writes .inp, .msh or .mesh with meshtext's writer of the format, atomically."""
    from . import meshtext

    ext = _extension(path)
    if ext == ".msh" and arrays.ids[0] <= 0:
        raise OracleMeshError(f"{path}: material {arrays.ids[0]} cannot be a Gmsh physical tag (they are "
                              f"positive); renumber it in the scene to write .msh")
    write = {".inp": meshtext.write_inp, ".msh": meshtext.write_msh, ".mesh": meshtext.write_medit}[ext]
    with atomic_output(path) as temporary, open(temporary, "w", encoding="utf-8") as f:
        write(f, arrays, block_rows)
    return [path]


def write_mesh(grid, path, material_names=None, arrays=None, block_rows=None):
    """Writes a tetrahedral mesh (vtkUnstructuredGrid with cell array Material) with its boundary and
    interface surfaces to `path`, the format chosen by the extension (one of MESH_FORMATS), and
    returns the files written (a .vtu has its ``_surfaces.vtu``). `material_names`: {material id:
    name}; `arrays`: a MeshArrays of the grid, to share the work between several formats;
    `block_rows`: rows of a text format formatted at a time (default: about meshtext.BLOCK_VALUES
    numbers' worth; the file is the same for any)."""
    ext = _extension(path)
    if ext not in MESH_FORMATS:
        raise OracleMeshError(f"{path}: unknown mesh format '{ext}' (use one of {', '.join(MESH_FORMATS)})")
    arrays = arrays or MeshArrays(grid, material_names, path)
    if ext == ".vtu":
        return _write_vtu(grid, path, arrays)
    return _write_text(path, arrays, block_rows)
