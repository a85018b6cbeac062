# SPDX-License-Identifier: GPL-3.0-or-later
"""Reading back the meshes ``oraclemesh mesh`` writes, in every format of ``writers.MESH_FORMATS``,
as the vtkUnstructuredGrid the report works on: the tetrahedra, cell data Material and
MinDihedralAngle, field data MaterialIds/MaterialNames.

Meshes of 10-node tetrahedra come back as VTK_QUADRATIC_TETRA (the .mesh ``TetrahedraP2`` that
meshio 5.0 does not read by a small reader here).

The material of a tetrahedron comes from the .vtu's Material array, the Gmsh physical tag, the Medit
reference, or the Abaqus element set it is in (its id from the writer's ``** OracleMesh material``
comments, else the sets numbered 1, 2, ... in file order); the names from the field data, the Gmsh
physical names of dimension 3, or the writers' comments. The surfaces (triangles, *SURFACE) are
not part of the volume mesh and are skipped.
"""
import os
import re

from .fielddata import add_material_names
from .errors import OracleMeshError, update
from .writers import MESH_FORMATS
from . import fieldkeys


def min_dihedral_angles(points, cells):
    """The smallest of the six dihedral angles of each tetrahedron [degrees]."""
    import numpy as np

    p = points[cells]
    smallest = np.full(len(cells), 180.0)
    for i, j, k, l in ((0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1)):
        edge = p[:, j] - p[:, i]
        a = np.cross(edge, p[:, k] - p[:, i])  # normals of the two faces at edge ij
        b = np.cross(edge, p[:, l] - p[:, i])
        cosine = np.einsum("ij,ij->i", a, b) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1),
                                                          1e-300)
        smallest = np.minimum(smallest, np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))
    return smallest


def _grid(points, cells, material, names):
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.util.vtkConstants import VTK_QUADRATIC_TETRA, VTK_TETRA
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid

    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    grid.SetPoints(vtk_points)
    tets = vtkCellArray()
    width = cells.shape[1]  # 4, or 10 for quadratic tetrahedra
    tets.SetData(numpy_to_vtk(np.arange(0, width * len(cells) + 1, width, dtype=np.int64), deep=True),
                 numpy_to_vtk(np.ascontiguousarray(cells, dtype=np.int64).ravel(), deep=True))
    grid.SetCells(VTK_QUADRATIC_TETRA if width == 10 else VTK_TETRA, tets)
    array = numpy_to_vtk(np.asarray(material, dtype=np.int32), deep=True)
    array.SetName(fieldkeys.MATERIAL)
    grid.GetCellData().AddArray(array)
    add_material_names(grid.GetFieldData(), names)
    return grid


def _comments(path, prefix):
    """{id: rest of the line} from the comment lines ``<prefix> <id> <rest>`` of a text file."""
    found = {}
    pattern = re.compile(re.escape(prefix) + r" (-?\d+)(?: (.*))?$")
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            match = pattern.match(line.rstrip("\n"))
            if match:
                found[int(match.group(1))] = match.group(2) or ""
    return found


def _medit_p2(path):
    """(points, 10-node tetrahedra, their references) of an ASCII Medit file with TetrahedraP2, which
    meshio 5.0 does not read; None for other files."""
    import numpy as np

    with open(path, encoding="utf-8", errors="replace") as f:
        lines = [line for line in f if not line.lstrip().startswith("#")]
    tokens = " ".join(lines).split()
    if "TetrahedraP2" not in tokens:
        return None
    found, i = {}, 0
    widths = {"Vertices": 4, "TrianglesP2": 7, "TetrahedraP2": 11, "Triangles": 4, "Tetrahedra": 5, "Edges": 3}
    try:
        while i < len(tokens):
            word = tokens[i]
            if word in widths:
                count = int(tokens[i + 1])
                values = np.array(tokens[i + 2:i + 2 + count * widths[word]], dtype=np.float64)
                found[word] = values.reshape(count, widths[word])
                i += 2 + count * widths[word]
            else:  # MeshVersionFormatted 2, Dimension 3, End, ...
                i += 1
    except (ValueError, IndexError) as e:
        raise OracleMeshError(f"{path}: not a readable .mesh file ({type(e).__name__}: {e})") from None
    if "Vertices" not in found:
        raise OracleMeshError(f"{path}: no Vertices in the file")
    tets = found["TetrahedraP2"]
    return found["Vertices"][:, :3], tets[:, :10].astype(np.int64) - 1, tets[:, 10].astype(np.int64)


def _from_meshio(path, ext):
    import meshio
    import numpy as np

    if ext == ".mesh":
        p2 = _medit_p2(path)
        if p2 is not None:
            names = {m: name for m, name in _comments(path, "# material").items() if name}
            return _grid(p2[0], p2[1], p2[2], names)
    try:
        mesh = meshio.read(path, file_format={".msh": "gmsh", ".mesh": "medit", ".inp": "abaqus"}[ext])
    except (Exception, SystemExit) as e:  # meshio raises (and on some files exits) with its own types
        raise OracleMeshError(f"{path}: not a readable {ext} file ({type(e).__name__}: {e})") from None
    blocks = [i for i, block in enumerate(mesh.cells) if block.type == "tetra"]
    if not blocks:
        blocks = [i for i, block in enumerate(mesh.cells) if block.type == "tetra10"]
    if not blocks:
        raise OracleMeshError(f"{path}: no tetrahedra in the file")
    cells = np.concatenate([mesh.cells[i].data for i in blocks]).astype(np.int64)
    names = {}
    if ext == ".msh":
        material = np.concatenate([mesh.cell_data["gmsh:physical"][i] for i in blocks])
        names = {int(v[0]): name for name, v in mesh.field_data.items() if len(v) == 2 and int(v[1]) == 3}
    elif ext == ".mesh":
        material = np.concatenate([mesh.cell_data["medit:ref"][i] for i in blocks])
        names = {m: name for m, name in _comments(path, "# material").items() if name}
    else:  # .inp: the element sets
        declared = _comments(path, "** OracleMesh material")  # {id: "SETNAME name"}
        set_ids = {text.split(" ", 1)[0]: m for m, text in declared.items()}
        material = np.zeros(len(cells), dtype=np.int64)
        offsets = np.cumsum([0] + [len(mesh.cells[i].data) for i in blocks])
        for number, (set_name, parts) in enumerate(mesh.cell_sets.items(), start=1):
            m = set_ids.get(set_name, number)
            for k, i in enumerate(blocks):
                if i < len(parts) and parts[i] is not None and len(parts[i]):
                    material[offsets[k] + np.asarray(parts[i], dtype=np.int64)] = m
            text = declared.get(m, "").split(" ", 1)
            names[m] = text[1] if len(text) == 2 and text[1] else set_name
    return _grid(mesh.points[:, :3], cells, material, names)


def _refuse_surfaces(grid, path):
    """OracleMeshError saying what a .vtu of triangles is (the boundary and interface sets that
    'oraclemesh mesh' writes beside a mesh as <name>_surfaces.vtu) and which file to report on."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TRIANGLE, VTK_TRIANGLE

    if grid.GetNumberOfCells() == 0:
        return
    types = set(vtk_to_numpy(grid.GetCellTypesArray()).tolist())
    if types <= {VTK_TRIANGLE, VTK_QUADRATIC_TRIANGLE}:
        base = os.path.basename(path)
        mesh = base[:-len("_surfaces.vtu")] + ".vtu" if base.endswith("_surfaces.vtu") else None
        raise OracleMeshError(
            f"{path}: holds {grid.GetNumberOfCells()} triangles, no tetrahedra: "
            + ("the boundary and interface sets that 'oraclemesh mesh' writes beside a mesh; "
               f"report on the mesh itself, {mesh}" if mesh else "a surface, not a tetrahedral mesh"))


def read_mesh(path):
    """Reads a mesh written by ``oraclemesh mesh`` (.vtu, .inp, .msh or .mesh) into a tetrahedral
    vtkUnstructuredGrid with cell data Material and MinDihedralAngle; OracleMeshError naming the file
    when it is missing, of another format or unreadable."""
    from vtkmodules.util.numpy_support import numpy_to_vtk

    from .writers import tetrahedra

    ext = os.path.splitext(path)[1].lower()
    if ext not in MESH_FORMATS:
        raise OracleMeshError(f"{path}: the report reads meshes written by 'oraclemesh mesh' "
                              f"({', '.join(MESH_FORMATS)}), not '{ext}'")
    if not os.path.isfile(path):
        raise OracleMeshError(f"{path}: file not found")
    if ext == ".vtu":
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        try:
            grid = update(reader)
        except OracleMeshError as e:
            raise OracleMeshError(f"{path}: not a readable .vtu file ({e})") from None
        _refuse_surfaces(grid, path)
    else:
        try:
            import meshio  # noqa: F401
        except ImportError:
            raise OracleMeshError(f"{path}: reading '{ext}' needs meshio (Debian: apt-get install python3-meshio)") \
                from None
        grid = _from_meshio(path, ext)
    if grid.GetCellData().GetArray(fieldkeys.MIN_DIHEDRAL_ANGLE) is None:
        points, cells, _ = tetrahedra(grid, path)
        angles = numpy_to_vtk(min_dihedral_angles(points, cells), deep=True)
        angles.SetName(fieldkeys.MIN_DIHEDRAL_ANGLE)
        grid.GetCellData().AddArray(angles)
    return grid
