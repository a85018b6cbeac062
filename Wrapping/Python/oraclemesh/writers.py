# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh and image writers chosen by file extension.

``.vtu`` (and ``.vti`` for sampled images) go through VTK's XML writers; the finite-element formats
through meshio (Debian package ``python3-meshio``):

- ``.inp``  Abaqus: nodes, C3D4 elements, one ``*ELSET`` per material, named after the material
  (``cortical bone`` -> ``CORTICAL_BONE``) or ``MATERIAL_<id>`` when the scene gives no name;
- ``.msh``  Gmsh 2.2 (ASCII): the material id is each tetrahedron's physical tag, the names are
  ``$PhysicalNames``;
- ``.mesh`` Medit: the material id is each tetrahedron's reference.
"""
import os
import re

from .errors import OracleMeshError

MESH_FORMATS = (".vtu", ".inp", ".msh", ".mesh")


def _extension(path):
    return os.path.splitext(path)[1].lower()


def _make_folder(path):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)


def write_vtk_xml(data, path, writer_class):
    """Writes `data` with a VTK XML writer (zlib-compressed), creating the folder."""
    _make_folder(path)
    writer = writer_class()
    writer.SetFileName(path)
    writer.SetInputData(data)
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        raise OracleMeshError(f"{path}: could not be written")


def tetrahedra(grid, source="mesh"):
    """(points [n x 3], tetrahedra [m x 4] point ids, Material [m]) of a tetrahedral vtkUnstructuredGrid."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.util.vtkConstants import VTK_TETRA

    if grid.GetNumberOfCells() == 0:
        raise OracleMeshError(f"{source}: the mesh has no cells")
    types = vtk_to_numpy(grid.GetCellTypesArray())
    if (types != VTK_TETRA).any():
        raise OracleMeshError(f"{source}: cell {int(np.argmax(types != VTK_TETRA))} is not a tetrahedron "
                              f"(VTK cell type {int(types[types != VTK_TETRA][0])})")
    material = grid.GetCellData().GetArray("Material")
    if material is None:
        raise OracleMeshError(f"{source}: no cell array 'Material' (write meshes with 'oraclemesh mesh')")
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    cells = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4).astype(np.int64)
    return points, cells, vtk_to_numpy(material).astype(np.int64)


def abaqus_set_name(material, name=None):
    """An Abaqus-safe element set name: letters, digits and '_', starting with a letter, <= 80 chars."""
    if name:
        clean = re.sub(r"[^A-Za-z0-9_]+", "_", name).strip("_").upper()
        if clean and not clean[0].isalpha():
            clean = "M_" + clean
        if clean:
            return clean[:80]
    return f"MATERIAL_{material}"


def _meshio_mesh(grid, ext, names, source):
    import meshio
    import numpy as np

    points, cells, material = tetrahedra(grid, source)
    ids = sorted(set(material.tolist()))
    if ext == ".inp":
        sets, used = {}, set()
        for m in ids:
            name = abaqus_set_name(m, names.get(m))
            if name in used:  # two materials with the same name: keep them apart
                name = f"{name}_{m}"
            used.add(name)
            sets[name] = [np.flatnonzero(material == m)]
        return meshio.Mesh(points, [("tetra", cells)], cell_sets=sets), {}
    if ext == ".msh":
        if ids[0] <= 0:
            raise OracleMeshError(f"{source}: material {ids[0]} cannot be a Gmsh physical tag (they are "
                                  f"positive); renumber it in the scene to write .msh")
        tags = material.astype(np.int32)
        field_data = {names.get(m) or f"material_{m}": np.array([m, 3]) for m in ids}
        mesh = meshio.Mesh(points, [("tetra", cells)],
                           cell_data={"gmsh:physical": [tags], "gmsh:geometrical": [tags]},
                           field_data=field_data)
        return mesh, {"file_format": "gmsh22", "binary": False}
    return meshio.Mesh(points, [("tetra", cells)], cell_data={"medit:ref": [material.astype(np.int32)]}), \
        {"file_format": "medit"}


def write_mesh(grid, path, material_names=None):
    """Writes a tetrahedral mesh (vtkUnstructuredGrid with cell array Material) to `path`, the format
    chosen by the extension (one of MESH_FORMATS). `material_names`: {material id: name}."""
    ext = _extension(path)
    if ext not in MESH_FORMATS:
        raise OracleMeshError(f"{path}: unknown mesh format '{ext}' (use one of {', '.join(MESH_FORMATS)})")
    if ext == ".vtu":
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

        write_vtk_xml(grid, path, vtkXMLUnstructuredGridWriter)
        return
    try:
        import meshio
    except ImportError:
        raise OracleMeshError(f"{path}: writing '{ext}' needs meshio (Debian: apt-get install python3-meshio)") \
            from None
    mesh, options = _meshio_mesh(grid, ext, material_names or {}, path)
    _make_folder(path)
    try:
        if ext == ".inp":
            meshio.abaqus.write(path, mesh)
        else:
            meshio.write(path, mesh, **options)
    except OSError as e:
        raise OracleMeshError(f"{path}: could not be written: {e.strerror}") from None
