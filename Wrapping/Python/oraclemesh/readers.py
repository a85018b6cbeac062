# SPDX-License-Identifier: GPL-3.0-or-later
"""VTK readers chosen by file extension, for surfaces and label maps."""
import os

from .errors import OracleMeshError

SURFACE_EXTENSIONS = (".vtp", ".vtk", ".stl", ".obj", ".ply")
LABEL_MAP_EXTENSIONS = (".vti", ".mha", ".mhd", ".nii", ".nii.gz", ".nrrd", ".nhdr")


def _extension(path):
    lower = path.lower()
    return ".nii.gz" if lower.endswith(".nii.gz") else os.path.splitext(lower)[1]


def surface_reader(path):
    """A VTK reader algorithm for a surface file (.vtp .vtk .stl .obj .ply)."""
    ext = _extension(path)
    if ext == ".vtp":
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader as Reader
    elif ext == ".vtk":
        from vtkmodules.vtkIOLegacy import vtkPolyDataReader as Reader
    elif ext == ".stl":
        from vtkmodules.vtkIOGeometry import vtkSTLReader as Reader
    elif ext == ".obj":
        from vtkmodules.vtkIOGeometry import vtkOBJReader as Reader
    elif ext == ".ply":
        from vtkmodules.vtkIOPLY import vtkPLYReader as Reader
    else:
        raise OracleMeshError(f"{path}: unknown surface format '{ext}' (use one of {', '.join(SURFACE_EXTENSIONS)})")
    _check_exists(path)
    reader = Reader()
    reader.SetFileName(path)
    if ext == ".stl":
        reader.MergingOn()  # STL repeats every corner: merge them or the surface is all open edges
    return reader


def label_map_reader(path):
    """A VTK reader algorithm for a label image (.vti .mha .mhd .nii .nii.gz .nrrd .nhdr)."""
    ext = _extension(path)
    if ext == ".vti":
        from vtkmodules.vtkIOXML import vtkXMLImageDataReader as Reader
    elif ext in (".mha", ".mhd"):
        from vtkmodules.vtkIOImage import vtkMetaImageReader as Reader
    elif ext in (".nii", ".nii.gz"):
        from vtkmodules.vtkIOImage import vtkNIFTIImageReader as Reader
    elif ext in (".nrrd", ".nhdr"):
        from vtkmodules.vtkIOImage import vtkNrrdReader as Reader
    else:
        raise OracleMeshError(f"{path}: unknown label-map format '{ext}' (use one of {', '.join(LABEL_MAP_EXTENSIONS)})")
    _check_exists(path)
    reader = Reader()
    reader.SetFileName(path)
    return reader


def _check_exists(path):
    if not os.path.isfile(path):
        raise OracleMeshError(f"{path}: file not found")
