# SPDX-License-Identifier: GPL-3.0-or-later
"""The bad-input table (issue 14): each case is generated here and run through the command line
(scene files) or the Python API, asserting "exit code N and a message containing these words" or
"accepted (with this warning)". The messages must name the input (file, domain, port or property)
and the problem; no case may show a traceback. Run by ctest (Python.bad_inputs)."""
import concurrent.futures
import json
import math
import os
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest

import oraclemesh as om
from oraclemesh import fieldkeys
from oraclemesh.fielddata import strings
from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkImageData, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkCubeSource, vtkSphereSource
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
from vtkmodules.vtkIOGeometry import vtkSTLWriter
from vtkmodules.vtkIOPLY import vtkPLYWriter
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataWriter

COMMAND = os.environ.get("ORACLEMESH_COMMAND")
BALL = {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 3, "material": 2}
BLOCK = {"name": "block", "type": "box", "bounds": [-5, 5, -5, 5, -5, 5], "material": 1}
MESH = {"strategy": "None", "criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.5}, "seed": 1}


def run(*args, timeout=120):
    prefix = [COMMAND] if COMMAND else [sys.executable, "-m", "oraclemesh"]
    return subprocess.run(prefix + [str(a) for a in args], capture_output=True, encoding="utf-8",
                          errors="replace", check=False, timeout=timeout)


# ----------------------------------------------------------------------------------------------
# Generated inputs

def sphere_polydata(radius=3.0, resolution=12):
    source = vtkSphereSource()
    source.SetRadius(radius)
    source.SetThetaResolution(resolution)
    source.SetPhiResolution(resolution)
    source.Update()
    return source.GetOutput()


def write_vtp(path, polydata, binary=True):
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(polydata)
    if not binary:
        writer.SetDataModeToAscii()
    assert writer.Write() == 1
    return path


def write_vti(path, image):
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    assert writer.Write() == 1
    return path


def polyline_data(points, lines):
    pts = vtkPoints()
    for p in points:
        pts.InsertNextPoint(*p)
    cells = vtkCellArray()
    for line in lines:
        cells.InsertNextCell(len(line), line)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetLines(cells)
    return pd


def label_image(dims=(8, 8, 8), spacing=(1, 1, 1), origin=(-4, -4, -4), name="labels"):
    image = vtkImageData()
    image.SetDimensions(*dims)
    image.SetSpacing(*spacing)
    image.SetOrigin(*origin)
    labels = vtkIntArray()
    labels.SetName(name)
    labels.SetNumberOfTuples(dims[0] * dims[1] * dims[2])
    labels.Fill(1)
    image.GetPointData().SetScalars(labels)
    return image


def truncate(path, keep):
    """Cuts `path` to `keep` (a fraction) of its bytes."""
    size = os.path.getsize(path)
    with open(path, "r+b") as f:
        f.truncate(int(size * keep))
    return path


def nifti(path, dims, datatype=2, bitpix=8, data_bytes=None):
    """A minimal NIfTI-1 single file (.nii) of `dims`, uint8 voxels, with `data_bytes` of data."""
    header = bytearray(352)
    struct.pack_into("<i", header, 0, 348)
    struct.pack_into("<8h", header, 40, 3, *dims, 1, 1, 1, 1)
    struct.pack_into("<hh", header, 70, datatype, bitpix)
    struct.pack_into("<8f", header, 76, 1, 1, 1, 1, 1, 1, 1, 1)
    struct.pack_into("<f", header, 108, 352.0)
    header[344:348] = b"n+1\0"
    count = dims[0] * dims[1] * dims[2] if data_bytes is None else data_bytes
    with open(path, "wb") as f:
        f.write(bytes(header) + b"\x01" * count)
    return path


def metaimage(path, dims, data_bytes):
    text = (f"ObjectType = Image\nNDims = 3\nDimSize = {' '.join(map(str, dims))}\nElementSpacing = 1 1 1\n"
            "Offset = 0 0 0\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
    with open(path, "wb") as f:
        f.write(text.encode() + b"\x01" * data_bytes)
    return path


# ----------------------------------------------------------------------------------------------
# The command-line table: (name, make(tmp) -> (args, ...), exit code, words in stderr or stdout)

def scene(tmp, name, domains=None, mesh=None, **extra):
    description = {"domains": domains or [BALL, BLOCK], "mesh": mesh or MESH}
    description.update(extra)
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(description, f)
    return path


def surface_scene(tmp, name, file, **domain):
    spec = {"name": "part", "type": "surface", "file": file, "material": 3}
    spec.update(domain)
    return scene(tmp, name, [spec, BLOCK])


def case_binary_scene(tmp):
    path = os.path.join(tmp, "binary.json")
    with open(path, "wb") as f:
        f.write(bytes(range(256)) * 4)
    return ["mesh", path, "-o", os.path.join(tmp, "o.vtu")]


def case_folder_scene(tmp):
    path = os.path.join(tmp, "folder.json")
    os.makedirs(path, exist_ok=True)
    return ["mesh", path, "-o", os.path.join(tmp, "o.vtu")]


def case_big_material(tmp):
    return ["mesh", scene(tmp, "big_material", [dict(BALL, material=2**40), BLOCK]), "-o", os.path.join(tmp, "o.vtu")]


def case_big_seed(tmp):
    return ["mesh", scene(tmp, "big_seed", mesh=dict(MESH, seed=2**40)), "-o", os.path.join(tmp, "o.vtu")]


def case_big_budget(tmp):
    return ["mesh", scene(tmp, "big_budget", mesh=dict(MESH, maximum_number_of_vertices=2**70)),
            "-o", os.path.join(tmp, "o.vtu")]


def case_big_label_name(tmp):
    image = write_vti(os.path.join(tmp, "labels_ok.vti"), label_image())
    spec = {"name": "tissue", "type": "labelmap", "file": image, "label_names": {str(2**40): "x"}}
    return ["mesh", scene(tmp, "big_label", [spec]), "-o", os.path.join(tmp, "o.vtu")]


def case_output_under_file(tmp):
    blocker = os.path.join(tmp, "blocker")
    with open(blocker, "w") as f:
        f.write("a file, not a folder")
    return ["mesh", scene(tmp, "under_file"), "-o", os.path.join(blocker, "sub", "o.vtu")]


def case_output_is_folder(tmp):
    folder = os.path.join(tmp, "out.vtu")
    os.makedirs(folder, exist_ok=True)
    return ["mesh", scene(tmp, "is_folder"), "-o", folder]


def case_nan_surface(tmp):
    pd = sphere_polydata()
    pd.GetPoints().SetPoint(5, float("nan"), 0, 0)
    return ["mesh", surface_scene(tmp, "nan_surface", write_vtp(os.path.join(tmp, "nan.vtp"), pd)),
            "-o", os.path.join(tmp, "o.vtu")]


def case_absurd_surface(tmp):
    pd = sphere_polydata()
    pd.GetPoints().SetPoint(5, 1e20, 0, 0)
    return ["mesh", surface_scene(tmp, "absurd_surface", write_vtp(os.path.join(tmp, "absurd.vtp"), pd)),
            "-o", os.path.join(tmp, "o.vtu")]


def case_absurd_feature(tmp):
    lines = write_vtp(os.path.join(tmp, "absurd_lines.vtp"), polyline_data([(0, 0, 0), (1e20, 0, 0)], [(0, 1)]))
    return ["mesh", scene(tmp, "absurd_feature", mesh=dict(MESH, features={"files": lines})),
            "-o", os.path.join(tmp, "o.vtu")]


def case_triangles_as_features(tmp):
    lines = write_vtp(os.path.join(tmp, "triangles_as_lines.vtp"), sphere_polydata())
    return ["mesh", scene(tmp, "triangle_features", mesh=dict(MESH, features={"files": lines})),
            "-o", os.path.join(tmp, "o.vtu")]


def case_absurd_spacing(tmp):
    image = write_vti(os.path.join(tmp, "absurd_spacing.vti"), label_image(spacing=(1e300, 1, 1)))
    return ["mesh", scene(tmp, "absurd_spacing", [{"name": "tissue", "type": "labelmap", "file": image}]),
            "-o", os.path.join(tmp, "o.vtu")]


def case_missing_label_array(tmp):
    image = write_vti(os.path.join(tmp, "labels.vti"), label_image())
    spec = {"name": "tissue", "type": "labelmap", "file": image, "array": "segmentation"}
    return ["mesh", scene(tmp, "missing_array", [spec]), "-o", os.path.join(tmp, "o.vtu")]


def case_huge_metaimage(tmp):
    image = metaimage(os.path.join(tmp, "huge.mha"), (100000, 100000, 100000), 16)
    return ["mesh", scene(tmp, "huge_mha", [{"name": "tissue", "type": "labelmap", "file": image}]),
            "-o", os.path.join(tmp, "o.vtu")]


def case_truncated_metaimage(tmp):
    image = metaimage(os.path.join(tmp, "short.mha"), (20, 20, 20), 4000)
    return ["mesh", scene(tmp, "short_mha", [{"name": "tissue", "type": "labelmap", "file": image}]),
            "-o", os.path.join(tmp, "o.vtu")]


def case_truncated_nifti(tmp):
    image = nifti(os.path.join(tmp, "short.nii"), (20, 20, 20), data_bytes=1000)
    return ["mesh", scene(tmp, "short_nii", [{"name": "tissue", "type": "labelmap", "file": image}]),
            "-o", os.path.join(tmp, "o.vtu")]


def case_huge_nifti(tmp):
    image = nifti(os.path.join(tmp, "huge.nii"), (30000, 30000, 30000), data_bytes=64)
    return ["mesh", scene(tmp, "huge_nii", [{"name": "tissue", "type": "labelmap", "file": image}]),
            "-o", os.path.join(tmp, "o.vtu")]


def case_truncated_vti(tmp):
    image = truncate(write_vti(os.path.join(tmp, "short.vti"), label_image()), 0.6)
    return ["mesh", scene(tmp, "short_vti", [{"name": "tissue", "type": "labelmap", "file": image}]),
            "-o", os.path.join(tmp, "o.vtu")]


def case_empty_ply(tmp):
    path = os.path.join(tmp, "empty.ply")
    open(path, "wb").close()
    return ["mesh", surface_scene(tmp, "empty_ply", path), "-o", os.path.join(tmp, "o.vtu")]


def case_truncated_ply(tmp):
    writer = vtkPLYWriter()
    path = os.path.join(tmp, "short.ply")
    writer.SetFileName(path)
    writer.SetInputData(sphere_polydata())
    writer.SetFileTypeToBinary()
    assert writer.Write() == 1
    truncate(path, 0.5)
    return ["mesh", surface_scene(tmp, "short_ply", path), "-o", os.path.join(tmp, "o.vtu")]


def case_truncated_stl(tmp):
    writer = vtkSTLWriter()
    path = os.path.join(tmp, "short.stl")
    writer.SetFileName(path)
    writer.SetInputData(sphere_polydata())
    writer.SetFileTypeToBinary()
    assert writer.Write() == 1
    truncate(path, 0.7)
    return ["mesh", surface_scene(tmp, "short_stl", path), "-o", os.path.join(tmp, "o.vtu")]


def case_truncated_vtp(tmp):
    path = truncate(write_vtp(os.path.join(tmp, "short.vtp"), sphere_polydata()), 0.6)
    return ["mesh", surface_scene(tmp, "short_vtp", path), "-o", os.path.join(tmp, "o.vtu")]


def case_huge_sampler(tmp):
    return ["sample", scene(tmp, "huge_sample"), "--dims", 100000, 100000, 100000]


def case_cube_quads(tmp):
    cube = vtkCubeSource()
    cube.SetXLength(4)
    cube.SetYLength(4)
    cube.SetZLength(4)
    cube.Update()
    path = write_vtp(os.path.join(tmp, "cube.vtp"), cube.GetOutput())
    return ["mesh", surface_scene(tmp, "cube", path), "-o", os.path.join(tmp, "cube.vtu")]


def case_unwelded_surface(tmp):
    """Every triangle with its own three corners (as an STL writer's soup): merged, then closed."""
    pd = sphere_polydata()
    points, cells = vtkPoints(), vtkCellArray()
    for c in range(pd.GetNumberOfCells()):
        ids = pd.GetCell(c).GetPointIds()
        cells.InsertNextCell(3, [points.InsertNextPoint(pd.GetPoint(ids.GetId(k))) for k in range(3)])
    soup = vtkPolyData()
    soup.SetPoints(points)
    soup.SetPolys(cells)
    return ["mesh", surface_scene(tmp, "unwelded", write_vtp(os.path.join(tmp, "soup.vtp"), soup)),
            "-o", os.path.join(tmp, "soup.vtu")]


def case_overlapping_features(tmp):
    # one segment twice (once reversed), a collinear one overlapping it: merged with a warning
    lines = polyline_data([(-2, 0, 0), (2, 0, 0), (-1, 0, 0), (1, 0, 0)], [(0, 1), (1, 0), (2, 3)])
    path = write_vtp(os.path.join(tmp, "overlap.vtp"), lines)
    return ["mesh", scene(tmp, "overlap", mesh=dict(MESH, features={"files": path})), "-o", os.path.join(tmp, "f.vtu")]


def case_hidden_domain(tmp):
    inner = {"name": "hidden ball", "type": "sphere", "center": [0, 0, 0], "radius": 2, "material": 5}
    return ["mesh", scene(tmp, "hidden", [BLOCK, inner]), "-o", os.path.join(tmp, "h.vtu")]


def overlapping_cubes():
    from vtkmodules.vtkFiltersCore import vtkAppendPolyData
    append = vtkAppendPolyData()
    for center in ((0, 0, 0), (1, 1, 1)):
        cube = vtkCubeSource()
        cube.SetCenter(*center)
        cube.SetXLength(4)
        cube.SetYLength(4)
        cube.SetZLength(4)
        append.AddInputConnection(cube.GetOutputPort())
    append.Update()
    return append.GetOutput()


def case_self_intersecting(tmp, **domain):
    path = write_vtp(os.path.join(tmp, "cubes.vtp"), overlapping_cubes())
    return ["mesh", surface_scene(tmp, "cubes", path, **domain), "-o", os.path.join(tmp, "cubes.vtu")]


def sphere_with_hole():
    """A sphere without one triangle: one hole (a border loop of 3 edges)."""
    pd = sphere_polydata()
    cells = vtkCellArray()
    for c in range(1, pd.GetNumberOfCells()):
        ids = pd.GetCell(c).GetPointIds()
        cells.InsertNextCell(3, [ids.GetId(k) for k in range(3)])
    out = vtkPolyData()
    out.SetPoints(pd.GetPoints())
    out.SetPolys(cells)
    return out


def case_surface_with_hole(tmp, **domain):
    path = write_vtp(os.path.join(tmp, "holed.vtp"), sphere_with_hole())
    return ["mesh", surface_scene(tmp, "holed", path, **domain), "-o", os.path.join(tmp, "holed.vtu")]


def case_open_patch(tmp):
    """A lone square (two triangles): nothing inside whatever the inside test."""
    pts = vtkPoints()
    for p in ((0, 0, 0), (4, 0, 0), (4, 4, 0), (0, 4, 0)):
        pts.InsertNextPoint(*p)
    cells = vtkCellArray()
    cells.InsertNextCell(3, [0, 1, 2])
    cells.InsertNextCell(3, [0, 2, 3])
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(cells)
    path = write_vtp(os.path.join(tmp, "patch.vtp"), pd)
    return ["mesh", surface_scene(tmp, "patch", path), "-o", os.path.join(tmp, "patch.vtu")]


def case_tiny_facets(tmp):
    """Facet size 1e-9 ran for hours (3 GB with the default budget): refused before meshing, with the
    estimate and the factor to coarsen by."""
    tiny = dict(MESH, criteria=dict(MESH["criteria"], facet_size=1e-9))
    return ["mesh", scene(tmp, "tiny_facets", mesh=tiny), "-o", os.path.join(tmp, "t.vtu")]


def case_tiny_facet_distance(tmp):
    """Facet distance 1e-9 (which the size estimate does not see): ends at --time-limit."""
    tiny = dict(MESH, criteria=dict(MESH["criteria"], facet_distance=1e-9), maximum_number_of_vertices=500000)
    return ["mesh", scene(tmp, "tiny_distance", mesh=tiny), "-o", os.path.join(tmp, "t.vtu"), "--time-limit", 2]


def criteria_case(name, outputs=None, **criteria):
    """A scene with these global criteria (and mesh keys, e.g. time_limit), written to `outputs`."""
    def make(tmp):
        mesh = dict(MESH, criteria=dict(MESH["criteria"], **criteria.pop("criteria", {})), **criteria)
        path = scene(tmp, name, mesh=mesh)
        return ["mesh", path] + sum((["-o", os.path.join(tmp, o)] for o in outputs or [name + ".vtu"]), []) + ["--strict"]
    return make


def case_everything_cut(tmp):
    """A cut that removes every material: an error naming the scene and the cut, no files."""
    cut = {"name": "everything", "type": "plane", "origin": [0, 0, 100], "normal": [0, 0, 1], "cut": True}
    path = scene(tmp, "all_cut", domains=[cut, BALL, BLOCK])
    return ["mesh", path, "-o", os.path.join(tmp, "cut.vtu"), "-o", os.path.join(tmp, "cut.inp")]


def case_metres(tmp):
    """A part in metres (a ball of radius 0.02) with criteria in millimetres: warned, --strict fails."""
    ball = {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 0.02, "material": 1}
    mesh = dict(MESH, criteria={"cell_size": 2, "facet_size": 2, "facet_distance": 0.1})
    return ["mesh", scene(tmp, "metres", domains=[ball], mesh=mesh), "-o", os.path.join(tmp, "m.vtu"), "--strict"]


def case_unknown_label(tmp):
    """label_names and criteria for labels the image lacks: warned by name, --strict fails."""
    labels = write_vti(os.path.join(tmp, "labels.vti"), label_image())  # label 1 only
    tissue = {"name": "tissue", "type": "labelmap", "file": labels, "array": "labels",
              "label_names": {"1": "bone", "7": "no such tissue"}}
    mesh = dict(MESH, materials={"9": {"cell_size": 1}})
    return ["mesh", scene(tmp, "labels", domains=[tissue], mesh=mesh), "-o", os.path.join(tmp, "l.vtu"), "--strict"]


def case_dense_features(tmp):
    """10,000 feature segments on a circle with Conforming ran past 120 s: ends at the scene's time_limit."""
    n = 10000
    points = [(2 * math.cos(2 * math.pi * i / n), 2 * math.sin(2 * math.pi * i / n), 0) for i in range(n)]
    lines = write_vtp(os.path.join(tmp, "dense.vtp"), polyline_data(points, [(i, (i + 1) % n) for i in range(n)]))
    dense = dict(MESH, strategy="Conforming", features={"files": lines}, maximum_number_of_vertices=20000,
                 time_limit=2)
    return ["mesh", scene(tmp, "dense", mesh=dense), "-o", os.path.join(tmp, "d.vtu")]


# name -> (make, exit code, words that must all appear in stderr+stdout, case-insensitive)
CLI_CASES = {
    "binary scene file": (case_binary_scene, 2, ["binary.json", "binary", "not utf-8"]),
    "folder as scene": (case_folder_scene, 2, ["folder.json", "folder"]),
    "material id beyond int": (case_big_material, 2, ["$.domains[0].material", "out of range"]),
    "seed beyond int": (case_big_seed, 2, ["$.mesh.seed", "out of range"]),
    "vertex budget beyond int64": (case_big_budget, 2, ["maximum_number_of_vertices", "out of range"]),
    "label beyond int": (case_big_label_name, 2, ["label_names", "out of range"]),
    "output under a file": (case_output_under_file, 2, ["blocker", "is a file"]),
    "output is a folder": (case_output_is_folder, 2, ["out.vtu", "is a folder"]),
    "NaN surface coordinate": (case_nan_surface, 2, ["'part'", "point 5", "nan"]),
    "absurd surface coordinate": (case_absurd_surface, 2, ["'part'", "point 5", "1e15"]),
    "absurd feature coordinate": (case_absurd_feature, 2, ["feature lines", "1e15"]),
    "triangles as feature lines": (case_triangles_as_features, 2, ["feature lines", "polygon", "line cells"]),
    "absurd label-map spacing": (case_absurd_spacing, 2, ["'tissue'", "spacing"]),
    "missing label array": (case_missing_label_array, 2, ["'tissue'", "'segmentation'", "labels"]),
    "label map larger than memory": (case_huge_metaimage, 2, ["huge.mha", "would need", "available"]),
    "NIfTI larger than memory": (case_huge_nifti, 2, ["huge.nii", "would need", "available"]),
    "truncated MetaImage": (case_truncated_metaimage, 2, ["short.mha", "truncated"]),
    "truncated NIfTI": (case_truncated_nifti, 2, ["short.nii", "truncated"]),
    "truncated VTI": (case_truncated_vti, 2, ["short.vti", "truncated"]),
    "zero-byte PLY": (case_empty_ply, 2, ["empty.ply", "empty"]),
    "truncated PLY": (case_truncated_ply, 2, ["short.ply", "truncated"]),
    "truncated STL": (case_truncated_stl, 2, ["short.stl", "truncated"]),
    "truncated VTP": (case_truncated_vtp, 2, ["short.vtp", "truncated"]),
    "sampler grid larger than memory": (case_huge_sampler, 2, ["dimensions", "would need", "available"]),
    "quads (vtkCubeSource) accepted": (case_cube_quads, 0, ["wrote"]),
    "unwelded triangle soup accepted": (case_unwelded_surface, 0, ["wrote"]),
    "overlapping feature segments merged": (case_overlapping_features, 0, ["warning", "merged", "duplicate"]),
    "hidden domain warned": (case_hidden_domain, 0, ["warning", "'hidden ball'", "hidden"]),
    "self-intersecting surface, closed test": (lambda tmp: case_self_intersecting(tmp, inside_test="closed"), 2,
                                               ["'part'", "intersects itself", "first: triangle",
                                                "allow_self_intersections"]),
    "self-intersecting surface, automatic": (case_self_intersecting, 0,
                                             ["warning", "'part'", "intersecting triangles", "first: triangle",
                                              "winding number", "wrote"]),
    "self-intersecting surface, automatic, strict": (lambda tmp: case_self_intersecting(tmp) + ["--strict"], 3,
                                                     ["intersecting triangles", "--strict"]),
    "self-intersecting surface allowed": (lambda tmp: case_self_intersecting(tmp, allow_self_intersections=True),
                                          0, ["wrote"]),
    "surface with a hole, closed test": (lambda tmp: case_surface_with_hole(tmp, inside_test="closed"), 2,
                                         ["'part'", "not closed", "1 hole(s)", "length", "winding",
                                          '"inside_test": "winding_number"']),
    "surface with a hole, automatic": (case_surface_with_hole, 0, ["warning", "'part'", "1 hole(s)", "length",
                                                                   "winding number", "wrote"]),
    "open patch encloses no volume": (case_open_patch, 2, ["'part'", "encloses no volume", "open patch"]),
    "merge tolerance out of range": (lambda tmp: case_surface_with_hole(tmp, merge_tolerance=2), 2,
                                     ["$.domains[0].merge_tolerance", "between 0 and 1"]),
    "surface with a hole, winding number": (lambda tmp: case_surface_with_hole(tmp, inside_test="winding_number"),
                                            0, ["warning", "'part'", "1 hole(s)", "wrote"]),
    "unknown inside test": (lambda tmp: case_surface_with_hole(tmp, inside_test="parity"), 2,
                            ["$.domains[0].inside_test", "winding_number"]),
    "facet size 1e-9 refused up front": (case_tiny_facets, 2, ["tiny_facets.json", "the criteria ask for about",
                                                                "vertex budget", "facet_size about", "times larger",
                                                                "maximum_number_of_vertices"]),
    "facet distance 1e-9 ends at the time limit": (case_tiny_facet_distance, 3, ["time limit of 2 s reached in",
                                                                                "vertices", "partial statistics",
                                                                                "time.elapsed"]),
    "negative cell size": (criteria_case("negative", criteria={"cell_size": -2}), 2,
                           ["$.mesh.criteria.cell_size", ">= 0", "-1: not set", "-2"]),
    "null and -1 criteria are unset": (criteria_case("unset", criteria={"cell_size": None, "facet_size": -1}), 0,
                                       ["wrote"]),
    "criteria larger than the part": (criteria_case("huge", criteria={"cell_size": 1000, "facet_size": 1000}), 3,
                                      ["cell_size 1000", "facet_size 1000", "larger than the whole domain",
                                       "units slip", "--strict"]),
    "criteria in metres on a part in millimetres": (criteria_case("small", criteria={"facet_size": 0.001},
                                                                  maximum_number_of_vertices=2000000), 2,
                                                    ["the criteria ask for about", "facet_size about"]),
    "part in metres, criteria in millimetres": (case_metres, 3, ["cell_size 2", "larger than the whole domain",
                                                                 "0.06928", "units slip", "--strict",
                                                                 "e-05"]),  # the volume, not 0.0
    "labels and materials the image lacks": (case_unknown_label, 3, ["label 7", "'no such tissue'",
                                                                     "does not have", "material 9",
                                                                     "no domain has", "--strict"]),
    "everything cut away": (case_everything_cut, 2, ["all_cut.json", "no tetrahedra", "'everything'", "hidden"]),
    "dense feature lines end at the time limit": (case_dense_features, 3, ["time limit of 2 s reached in",
                                                                            "partial statistics"]),
    # within 10x the budget, no time limit: the memory check refuses it (a budget of 2e9 vertices)
    "mesh too big for the memory": (lambda tmp: ["mesh", scene(tmp, "huge", mesh=dict(
        MESH, criteria=dict(MESH["criteria"], facet_size=2e-4), maximum_number_of_vertices=2000000000,
        time_limit=-1)), "-o", os.path.join(tmp, "h.vtu")], 2, ["a mesh of about", "would need", "available",
                                                             "coarsen the criteria"]),
    "time limit out of range": (lambda tmp: ["mesh", scene(tmp, "bad_limit", mesh=dict(MESH, time_limit=-3)),
                                             "-o", os.path.join(tmp, "o.vtu")], 2, ["$.mesh.time_limit", "-3"]),
}


class CommandLine(unittest.TestCase):
    """Every case of CLI_CASES, two at a time."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()

        def one(item):
            name, (make, _, _) = item
            folder = os.path.join(cls.tmp.name, name.replace(" ", "_"))
            os.makedirs(folder)
            return name, run(*make(folder))

        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            cls.results = dict(pool.map(one, CLI_CASES.items()))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_cases(self):
        for name, (_, code, words) in CLI_CASES.items():
            with self.subTest(name):
                result = self.results[name]
                text = (result.stderr + result.stdout).lower()
                self.assertNotIn("traceback", text)
                self.assertEqual(result.returncode, code, f"{name}: {result.stderr[-800:]}")
                for word in words:
                    self.assertIn(word.lower(), text, f"{name}: {result.stderr[-800:]}")
                if code:  # one clear line on stderr, no raw VTK error dumps
                    lines = [line for line in result.stderr.splitlines() if line.strip()]
                    self.assertTrue(lines and lines[-1].startswith("oraclemesh: error:"), result.stderr)


class Signals(unittest.TestCase):
    """SIGINT and SIGTERM while meshing: exit 130 with one line, no KeyboardInterrupt traceback."""

    def test_interrupt(self):
        with tempfile.TemporaryDirectory() as tmp:
            slow = scene(tmp, "slow", mesh=dict(MESH, criteria={"cell_size": 0.12, "facet_size": 0.12,
                                                                "facet_distance": 0.01}))
            prefix = [COMMAND] if COMMAND else [sys.executable, "-m", "oraclemesh"]
            for number in (signal.SIGINT, signal.SIGTERM):
                with self.subTest(signal.Signals(number).name):
                    process = subprocess.Popen(prefix + ["mesh", slow, "-o", os.path.join(tmp, "slow.vtu")],
                                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding="utf-8")
                    time.sleep(2.0)  # into the mesher
                    process.send_signal(number)
                    started = time.monotonic()
                    out, err = process.communicate(timeout=60)
                    self.assertEqual(process.returncode, 130, err)
                    self.assertLess(time.monotonic() - started, 10)
                    self.assertNotIn("Traceback", err)
                    self.assertEqual([line for line in err.splitlines() if line.strip()],
                                     [f"oraclemesh: interrupted ({signal.Signals(number).name})"])
                    self.assertFalse(os.path.exists(os.path.join(tmp, "slow.vtu")))


# ----------------------------------------------------------------------------------------------
# The Python API: the same refusals from the VTK filters, as om.OracleMeshError

class PythonApi(unittest.TestCase):
    def setUp(self):
        self.keep = []

    def oracle(self, *domains):
        oracle = om.vtkHierarchicalOracle()
        for domain in domains:
            oracle.AddInputConnection(domain.GetOutputPort())
        self.keep.extend(domains)
        self.keep.append(oracle)
        return oracle

    def ball(self, radius=3.0, material=1):
        sphere = om.vtkSphereDomain()
        sphere.SetRadius(radius)
        sphere.SetMaterialId(material)
        return sphere

    def mesher(self, oracle=None, cell=1.0):
        mesher = om.vtkFeaturePreservingTetrahedralizer()
        if oracle is not None:
            mesher.SetInputConnection(oracle.GetOutputPort())
        mesher.SetCellSize(cell)
        mesher.SetFacetSize(cell)
        mesher.SetFacetDistance(0.2)
        return mesher

    def assertRefused(self, algorithm, *words, error=om.OracleMeshError):
        with self.assertRaises(error) as caught:
            om.update(algorithm)
        for word in words:
            self.assertIn(word.lower(), str(caught.exception).lower())
        return caught.exception

    def test_wrong_types_on_ports(self):
        image = vtkRTAnalyticSource()
        self.keep.append(image)
        surface = om.vtkSurfaceDomain()
        surface.SetMaterialName("implant")
        surface.SetInputConnection(image.GetOutputPort())
        self.assertRefused(self.mesher(self.oracle(surface)), "'implant'", "port 0", "vtkImageData")
        sphere = vtkSphereSource()
        self.keep.append(sphere)
        labels = om.vtkLabelMapDomain()
        labels.SetDomainName("tissue")
        labels.SetInputConnection(sphere.GetOutputPort())
        self.assertRefused(self.mesher(self.oracle(labels)), "'tissue'", "port 0", "vtkPolyData")
        self.assertRefused(self.mesher(), "no input", "port 0")
        features = self.mesher(self.oracle(self.ball()))
        features.SetInputConnection(1, image.GetOutputPort())
        self.assertRefused(features, "feature lines", "port 1", "vtkImageData")
        vertices = self.mesher(self.oracle(self.ball()))
        pd = vtkPolyData()
        points = vtkPoints()
        points.InsertNextPoint(0, 0, 0)
        verts = vtkCellArray()
        verts.InsertNextCell(1, [0])
        pd.SetPoints(points)
        pd.SetVerts(verts)
        vertices.SetInputData(1, pd)
        self.assertRefused(vertices, "feature lines", "vertex", "line cells")

    def test_out_of_range_properties_are_errors_not_clamped(self):
        for setter, value, words in (("SetFeatureStrategy", 7, ["FeatureStrategy", "7"]),
                                     ("SetInterfaceSliverAngle", 90, ["InterfaceSliverAngle", "90"]),
                                     ("SetCreaseAngle", 0, ["CreaseAngle", "0", "180 = no creases"]),
                                     ("SetPickingSliverAngle", 31, ["PickingSliverAngle", "31"]),
                                     ("SetMaximumNumberOfVertices", -1, ["MaximumNumberOfVertices", "-1"]),
                                     ("SetPerturbationStepsPerVertex", -2, ["PerturbationStepsPerVertex"]),
                                     ("SetOptimisationTimeLimit", -5, ["OptimisationTimeLimit"]),
                                     ("SetTimeLimit", -5, ["TimeLimit", "-5"]),
                                     ("SetFacetSize", math.nan, ["FacetSize", "nan"])):
            with self.subTest(setter):
                mesher = self.mesher(self.oracle(self.ball()))
                getattr(mesher, setter)(value)
                self.assertRefused(mesher, *words)
        mesher = self.mesher(self.oracle(self.ball()))
        mesher.SetMaterialCriteria(1, -1, math.nan, -1, -1, -1, -1)
        self.assertRefused(mesher, "material 1", "FacetSize", "nan")
        cylinder = om.vtkImplicitDomain()
        cylinder.SetHeight(-3)
        self.assertRefused(cylinder, "Height", "-3")
        labels = om.vtkLabelMapDomain()
        labels.SetInputData(label_image())
        labels.SetInterpolation(5)
        self.assertRefused(labels, "Interpolation", "5")
        surface = om.vtkSurfaceDomain()
        surface.SetInputData(sphere_polydata())
        surface.SetInsideTest(5)
        self.assertRefused(surface, "InsideTest", "5")

    def test_surface_options_through_the_python_api(self):
        """AllowSelfIntersections and InsideTest on vtkSurfaceDomain reach the oracle (a mesh)."""
        cubes = om.vtkSurfaceDomain()
        cubes.SetInputData(overlapping_cubes())
        cubes.SetInsideTestToClosed()
        self.assertRefused(cubes, "intersects itself", "first: triangle")
        cubes.AllowSelfIntersectionsOn()
        cubes.SetInsideTestToWindingNumber()
        grid = om.update(self.mesher(self.oracle(cubes), cell=1.0))
        self.assertGreater(grid.GetNumberOfCells(), 0)
        holed = om.vtkSurfaceDomain()
        holed.SetInputData(sphere_with_hole())
        holed.SetInsideTestToClosed()
        self.assertRefused(holed, "not closed", "1 hole(s)")
        holed.SetInsideTestToWindingNumber()
        mesher = self.mesher(self.oracle(holed), cell=1.0)
        grid = om.update(mesher)
        self.assertGreater(grid.GetNumberOfCells(), 0)
        # the default, automatic, meshes both and says what it repaired in the input warnings
        for domain, words in ((cubes, "intersecting triangles"), (holed, "1 hole(s)")):
            domain.SetInsideTestToAutomatic()
            domain.AllowSelfIntersectionsOff()
            grid = om.update(self.mesher(self.oracle(domain), cell=1.0))
            self.assertGreater(grid.GetNumberOfCells(), 0)
            warnings = strings(grid.GetFieldData(), fieldkeys.INPUT_WARNINGS)
            self.assertTrue(any(words in w and "winding number" in w for w in warnings), warnings)

    def test_sampler_memory_and_abort(self):
        sampler = om.vtkOracleSampler()
        sampler.SetInputConnection(self.oracle(self.ball()).GetOutputPort())
        sampler.SetDimensions(100000, 100000, 100000)
        self.assertRefused(sampler, "vtkOracleSampler", "Dimensions", "would need", "available")
        sampler.SetDimensions(64, 64, 64)
        sampler.AddObserver("ProgressEvent", lambda alg, event: alg.SetAbortExecute(1))
        self.assertRefused(sampler, "aborted")

    def test_time_limit_is_an_error_with_the_figures_so_far(self):
        mesher = self.mesher(self.oracle(self.ball()), cell=1.0)
        mesher.SetFacetDistance(1e-9)  # the size estimate does not see it: not refused up front
        mesher.SetMaximumNumberOfVertices(500000)  # the clock comes first; fits the memory check anywhere
        mesher.SetTimeLimit(1)
        error = self.assertRefused(mesher, "meshing failed", "time limit of 1 s reached in", error=om.MeshingError)
        self.assertFalse(error.aborted)
        self.assertEqual(mesher.GetOutputDataObject(0).GetNumberOfCells(), 0)  # no mesh, only the figures
        figures = error.statistics
        self.assertEqual(figures["time_limit"], 1)
        self.assertGreaterEqual(figures["time.elapsed"], 1)
        self.assertGreater(figures["vertices"], 0)

    def test_abort_is_an_error(self):
        mesher = self.mesher(self.oracle(self.ball()), cell=0.1)
        mesher.AddObserver("ProgressEvent", lambda alg, event: alg.SetAbortExecute(1))
        error = self.assertRefused(mesher, "aborted", error=om.MeshingError)
        self.assertTrue(error.aborted)

    def test_surfaces_repaired_not_refused(self):
        cube = vtkCubeSource()
        self.keep.append(cube)
        surface = om.vtkSurfaceDomain()
        surface.SetInputConnection(cube.GetOutputPort())
        domain = om.update(surface)
        self.assertGreater(domain.GetNumberOfPolys(), 0)
        self.assertTrue(all(domain.GetCell(c).GetNumberOfPoints() == 3 for c in range(domain.GetNumberOfCells())))
        mesh = om.update(self.mesher(self.oracle(surface), cell=0.3))
        self.assertGreater(mesh.GetNumberOfCells(), 0)

    def test_feature_segments_merged(self):
        lines = polyline_data([(-2, 0, 0), (2, 0, 0), (-1, 0, 0), (1, 0, 0)], [(0, 1), (1, 0), (2, 3)])
        mesher = self.mesher(self.oracle(self.ball()))
        mesher.SetInputData(1, lines)
        mesh = om.update(mesher)
        warnings = mesh.GetFieldData().GetAbstractArray("Warnings")
        texts = [warnings.GetValue(i) for i in range(warnings.GetNumberOfValues())]
        self.assertTrue(any("merged" in t and "overlapping" in t for t in texts), texts)
        segments = mesher.GetOutputDataObject(2)
        present = segments.GetCellData().GetArray("Present")
        self.assertTrue(all(present.GetValue(i) == 1 for i in range(present.GetNumberOfTuples())))

    def test_hidden_domain_warning(self):
        mesh = om.update(self.mesher(self.oracle(self.ball(5, 1), self.ball(2, 2))))
        warnings = mesh.GetFieldData().GetAbstractArray("Warnings")
        texts = [warnings.GetValue(i) for i in range(warnings.GetNumberOfValues())]
        self.assertTrue(any("hidden" in t and "domain 1" in t for t in texts), texts)


if __name__ == "__main__":
    unittest.main()
