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
    order), Material [m]) of a tetrahedral vtkUnstructuredGrid: all linear or all quadratic."""
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
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    width = 10 if kind == VTK_QUADRATIC_TETRA else 4
    nodes = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, width).astype(np.int64)
    return points, nodes, vtk_to_numpy(material).astype(np.int64)


def tetrahedra(grid, source="mesh"):
    """(points [n x 3], tetrahedra [m x 4] point ids, Material [m]) of a tetrahedral vtkUnstructuredGrid;
    of 10-node tetrahedra, their corners."""
    points, nodes, material = element_nodes(grid, source)
    return points, nodes[:, :4], material


class MeshArrays:
    """What every format needs, computed once per mesh: points, cells (corners), nodes (all nodes:
    the cells, or 10 per 10-node tetrahedron), quadratic, material, {id: name}, the SurfaceSets and
    each surface's tag, face_nodes (the surface triangles' nodes: 3, or 6 for quadratic meshes)."""

    def __init__(self, grid, names=None, source="mesh", separating=None):
        """`separating`: the boundary and interface faces when known (surfaces.surface_sets)."""
        from .quadratic import face_nodes
        from .surfaces import material_ids, surface_sets

        self.points, self.nodes, self.material = element_nodes(grid, source)
        self.cells = self.nodes[:, :4]
        self.quadratic = self.nodes.shape[1] == 10
        self.names = dict(names or {})
        self.ids = material_ids(self.material)
        self.sets = surface_sets(self.points, self.cells, self.material, self.names, separating)
        self.face_nodes = face_nodes(self.sets.faces, self.nodes) if self.quadratic else self.sets.faces
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


def _abaqus_surfaces(arrays):
    """The *SURFACE sections and the material-id comments appended to meshio's Abaqus file."""
    sets, set_names = arrays.sets, material_set_names(arrays.ids, arrays.names)
    lines = ["** OracleMesh: element sets per material (id, set, name); per surface *SURFACE (faces of "
             "the first-named material's elements) and *NSET of the same name"]
    lines += [f"** OracleMesh material {m} {set_names[m]} {arrays.names.get(m, '')}".rstrip().replace("\n", " ")
              for m in arrays.ids]
    for i, name in enumerate(sets.names):
        rows = sets.select(i)
        lines.append(f"*SURFACE, NAME={name}, TYPE=ELEMENT")
        lines += [f"{e + 1}, S{s}" for e, s in zip(sets.owner[rows].tolist(), sets.side[rows].tolist())]
    return "\n".join(lines) + "\n"


def _plain_c3d10(path):
    """meshio names 10-node tetrahedra C3D10MH (hybrid, modified: the last of its aliases); the plain
    C3D10 is what a user asking for quadratic tetrahedra expects."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    with open(path, "w", encoding="utf-8") as f:
        f.write(text.replace("*ELEMENT, TYPE=C3D10MH\n", "*ELEMENT, TYPE=C3D10\n", 1))


ABAQUS_FLOAT_FORMAT = ".12e"


def _write_inp(path, arrays):
    import meshio
    import numpy as np

    set_names = material_set_names(arrays.ids, arrays.names)
    cell_sets = {set_names[m]: [np.flatnonzero(arrays.material == m)] for m in arrays.ids}
    point_sets = {name: np.unique(arrays.face_nodes[arrays.sets.select(i)])
                  for i, name in enumerate(arrays.sets.names)}
    kind = "tetra10" if arrays.quadratic else "tetra"
    mesh = meshio.Mesh(arrays.points, [(kind, arrays.nodes)], cell_sets=cell_sets, point_sets=point_sets)
    with atomic_output(path) as temporary:
        # 13 significant digits: 19 characters at most; CalculiX's reader takes 20 per number and
        # stops at longer ones ("*ERROR reading *NODE")
        meshio.abaqus.write(temporary, mesh, float_fmt=ABAQUS_FLOAT_FORMAT)
        if arrays.quadratic:
            _plain_c3d10(temporary)
        with open(temporary, "a", encoding="utf-8") as f:
            f.write(_abaqus_surfaces(arrays))
    return [path]


def _write_msh(path, arrays):
    import meshio
    import numpy as np

    if arrays.ids[0] <= 0:
        raise OracleMeshError(f"{path}: material {arrays.ids[0]} cannot be a Gmsh physical tag (they are "
                              f"positive); renumber it in the scene to write .msh")
    field_data = {}
    for m in arrays.ids:
        # $PhysicalNames are quoted, one per line
        name = (arrays.names.get(m) or f"material_{m}").replace('"', "'").replace("\n", " ")
        field_data[name if name not in field_data else f"{name}_{m}"] = np.array([m, 3])
    for tag, name in zip(arrays.tags, arrays.sets.names):
        field_data[name if name not in field_data else f"{name}_{tag}"] = np.array([tag, 2])
    tets, tris = arrays.material.astype(np.int32), arrays.surface_tag().astype(np.int32)
    volume, face = ("tetra10", "triangle6") if arrays.quadratic else ("tetra", "triangle")
    mesh = meshio.Mesh(arrays.points, [(volume, arrays.nodes), (face, arrays.face_nodes)],
                       cell_data={"gmsh:physical": [tets, tris], "gmsh:geometrical": [tets, tris]},
                       field_data=field_data)
    with atomic_output(path) as temporary:
        meshio.write(temporary, mesh, file_format="gmsh22", binary=False)
    return [path]


def _write_medit(path, arrays):
    import numpy as np

    def block(f, keyword, rows, fmt):
        f.write(f"{keyword}\n{len(rows)}\n")
        np.savetxt(f, rows, fmt=fmt)

    with atomic_output(path) as temporary, open(temporary, "w", encoding="utf-8") as f:
        f.write("# OracleMesh: tetrahedron references are material ids, triangle references surface tags\n")
        if arrays.quadratic:
            f.write("# OracleMesh: P2 nodes: corners, then the mid-edge nodes of edges 12 23 31 (triangles), "
                    "12 23 31 14 24 34 (tetrahedra)\n")
        for m in arrays.ids:
            f.write(f"# material {m} {arrays.names.get(m, '')}".rstrip().replace("\n", " ") + "\n")
        for tag, name in zip(arrays.tags, arrays.sets.names):
            f.write(f"# surface {tag} {name}\n")
        f.write("MeshVersionFormatted 2\nDimension 3\n")
        block(f, "Vertices", np.column_stack([arrays.points, np.zeros(len(arrays.points))]),
              ["%.17g"] * 3 + ["%d"])
        p2 = "P2" if arrays.quadratic else ""  # libMeshb's keywords of 6-node triangles, 10-node tetrahedra
        block(f, "Triangles" + p2, np.column_stack([arrays.face_nodes + 1, arrays.surface_tag()]), "%d")
        block(f, "Tetrahedra" + p2, np.column_stack([arrays.nodes + 1, arrays.material]), "%d")
        f.write("End\n")
    return [path]


def write_mesh(grid, path, material_names=None, arrays=None):
    """Writes a tetrahedral mesh (vtkUnstructuredGrid with cell array Material) with its boundary and
    interface surfaces to `path`, the format chosen by the extension (one of MESH_FORMATS), and
    returns the files written (a .vtu has its ``_surfaces.vtu``). `material_names`: {material id:
    name}; `arrays`: a MeshArrays of the grid, to share the work between several formats."""
    ext = _extension(path)
    if ext not in MESH_FORMATS:
        raise OracleMeshError(f"{path}: unknown mesh format '{ext}' (use one of {', '.join(MESH_FORMATS)})")
    arrays = arrays or MeshArrays(grid, material_names, path)
    if ext == ".vtu":
        return _write_vtu(grid, path, arrays)
    if ext == ".mesh":
        return _write_medit(path, arrays)
    try:
        import meshio  # noqa: F401
    except ImportError:
        raise OracleMeshError(f"{path}: writing '{ext}' needs meshio (Debian: apt-get install python3-meshio)") \
            from None
    return _write_inp(path, arrays) if ext == ".inp" else _write_msh(path, arrays)
