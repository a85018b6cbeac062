# SPDX-License-Identifier: GPL-3.0-or-later
"""Memory and time of the mesh writers on a large tetrahedral mesh: what writing each format adds to
the process's peak memory beside the mesh itself. Prints a Markdown table; not a test.

The mesh is a block of cubes, each split into six tetrahedra around its diagonal (conforming), the
points jittered so that coordinates have all their digits; three materials (a ball, a top slab, the
rest) give interfaces and boundaries. It is built once with numpy, with its boundary and interface
faces (what the mesher hands the writers as SeparatingFaces), and kept as .npy files. Each format is
then written by a fresh process that loads it into a vtkUnstructuredGrid like the mesher's (float64
points, int64 connectivity, int32 Material), resets its peak memory (/proc/self/clear_refs) and
saves the mesh as ``MeshResult.save`` does (MeshArrays with the mesher's faces, then write_mesh):
"added" is the peak resident memory during the save less the resident memory before it.

``--baseline REV`` also runs the package's writers as they are at git revision REV (the compiled
module and fieldkeys.py of the current package beside them), side by side.

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 Benchmarks/writer_memory.py \\
        --tets 10000000 --baseline HEAD~3
"""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

FORMATS = (".vtu", ".inp", ".msh", ".mesh")
NAMES = {1: "block", 2: "ball", 3: "top slab"}
# The six tetrahedra of a cube around its diagonal 0-7, corners numbered by their bits (x 1, y 2, z 4):
# 0, one axis, two axes, 7, for each order of the axes.
KUHN = [[0, 1 << a, (1 << a) | (1 << b), 7] for a, b in ((0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1))]
EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # VTK's 10-node tetrahedron


def block_mesh(tets, order=1):
    """(points [n x 3] float64, nodes [m x 4 or 10] int64, material [m] int32) of about `tets` tetrahedra."""
    n = max(1, round((tets / 6) ** (1 / 3)))
    shape = np.array([n, n, n])
    h = 1.0 / n
    rng = np.random.default_rng(1)
    grid = np.stack(np.meshgrid(*(np.arange(s + 1) for s in shape), indexing="ij"), axis=-1)
    points = grid.transpose(2, 1, 0, 3).reshape(-1, 3) * h  # point (i, j, k) is i + (n + 1) (j + (n + 1) k)
    points = points + rng.uniform(-0.02 * h, 0.02 * h, points.shape)
    stride = np.array([1, n + 1, (n + 1) ** 2])
    corner = np.array([((b & 1), (b >> 1) & 1, (b >> 2) & 1) for b in range(8)]) @ stride
    cubes = np.stack(np.meshgrid(*(np.arange(s) for s in shape), indexing="ij"), axis=-1)
    cubes = cubes.transpose(2, 1, 0, 3).reshape(-1, 3)
    base = cubes @ stride
    templates = corner[np.array(KUHN)]
    unit = np.array([((b & 1), (b >> 1) & 1, (b >> 2) & 1) for b in range(8)], dtype=float)[np.array(KUHN)]
    negative = np.einsum("ij,ij->i", np.cross(unit[:, 1] - unit[:, 0], unit[:, 2] - unit[:, 0]),
                         unit[:, 3] - unit[:, 0]) < 0
    templates[negative] = templates[negative][:, [0, 2, 1, 3]]  # positive volume, as VTK orders them
    nodes = (base[:, None, None] + templates[None]).reshape(-1, 4)
    del base
    centre = (cubes + 0.5) * h
    del cubes
    material = np.ones(len(centre), dtype=np.int32)
    material[np.einsum("ij,ij->i", centre - 0.5, centre - 0.5) < 0.3 ** 2] = 2
    material[centre[:, 2] > 0.8] = 3
    material = np.repeat(material, 6)
    if order == 2:
        points, nodes = _quadratic(points, nodes)
    return points, nodes, material


def _quadratic(points, nodes):
    """Adds a mid-edge node per edge: 10-node tetrahedra in VTK's order."""
    ends = np.sort(np.stack([nodes[:, list(e)] for e in EDGES], axis=1), axis=2)  # [m, 6, 2]
    keys = ends[..., 0] * len(points) + ends[..., 1]
    unique, index = np.unique(keys.ravel(), return_inverse=True)
    a, b = unique // len(points), unique % len(points)
    points = np.concatenate([points, (points[a] + points[b]) / 2])
    mids = index.reshape(-1, 6) + (len(points) - len(unique))
    return points, np.concatenate([nodes, mids], axis=1)


def prepare(folder, tets, order):
    """Builds the mesh and its separating faces into `folder` (.npy files); returns the tetrahedra."""
    from oraclemesh.surfaces import separating_faces

    points, nodes, material = block_mesh(tets, order)
    rows, other = separating_faces(points, nodes[:, :4], material)
    for name, array in (("points", points), ("nodes", nodes), ("material", material),
                        ("separating", np.stack([rows, other], axis=1))):
        np.save(os.path.join(folder, name + ".npy"), array)
    return len(nodes)


def grid_from(folder):
    """The saved mesh as a vtkUnstructuredGrid with the mesher's arrays and field data."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.util.vtkConstants import VTK_ID_TYPE, VTK_QUADRATIC_TETRA, VTK_TETRA
    from vtkmodules.vtkCommonCore import vtkPoints, vtkStringArray
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid

    from oraclemesh import fieldkeys
    from oraclemesh.fielddata import add_material_names

    def load(name):
        return np.load(os.path.join(folder, name + ".npy"))

    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(load("points"), deep=True))
    grid.SetPoints(points)
    nodes = load("nodes")
    width = nodes.shape[1]
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtk(np.arange(0, nodes.size + 1, width, dtype=np.int64), deep=True, array_type=VTK_ID_TYPE),
                  numpy_to_vtk(nodes.ravel(), deep=True, array_type=VTK_ID_TYPE))
    del nodes
    grid.SetCells(VTK_QUADRATIC_TETRA if width == 10 else VTK_TETRA, cells)
    material = numpy_to_vtk(load("material"), deep=True)
    material.SetName(fieldkeys.MATERIAL)
    grid.GetCellData().AddArray(material)
    separating = numpy_to_vtk(load("separating"), deep=True, array_type=VTK_ID_TYPE)
    separating.SetName(fieldkeys.SEPARATING_FACES)
    grid.GetFieldData().AddArray(separating)
    add_material_names(grid.GetFieldData(), NAMES)
    warnings = vtkStringArray()
    warnings.SetName(fieldkeys.WARNINGS)
    warnings.InsertNextValue("a warning, as the mesher's field data has")
    grid.GetFieldData().AddArray(warnings)
    return grid


def _status(key):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith(key + ":"))


def _digest(paths):
    """The first hex digits of the SHA-256 of the files' text, less the Abaqus heading's line that
    names the program that wrote it."""
    digest = hashlib.sha256()
    for path in paths:
        with open(path, "rb") as f:
            for number, line in enumerate(f):
                if not (path.endswith(".inp") and number == 2 and line.startswith(b"written by ")):
                    digest.update(line)
    return digest.hexdigest()[:10]


def child(folder, ext, out, block_rows):
    """Writes the saved mesh to `out` in a fresh process; prints a JSON line of the figures."""
    import gc

    import oraclemesh
    from oraclemesh.meshing import separating_faces_of
    from oraclemesh.writers import MeshArrays, write_mesh

    grid = grid_from(folder)
    gc.collect()
    before = _status("VmRSS")
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")  # the peak resident memory starts again from the current
    started = time.perf_counter()
    arrays = MeshArrays(grid, NAMES, separating=separating_faces_of(grid))
    options = {"block_rows": block_rows} if block_rows else {}
    written = write_mesh(grid, out, NAMES, arrays, **options)
    seconds = time.perf_counter() - started
    peak = _status("VmHWM")
    print(json.dumps({"tets": grid.GetNumberOfCells(), "mesh": grid.GetActualMemorySize() * 1024,
                      "before": before, "added": peak - before, "seconds": seconds,
                      "file": sum(os.path.getsize(p) for p in written), "digest": _digest(written),
                      "package": oraclemesh.__file__}))
    for path in written:
        os.remove(path)


def baseline_package(revision, folder):
    """The package at git `revision` in `folder`, with the current package's compiled module and
    fieldkeys.py; returns the folder to put on PYTHONPATH."""
    import oraclemesh

    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    archive = subprocess.run(["git", "-C", root, "archive", revision, "Wrapping/Python/oraclemesh"],
                             capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", folder], input=archive, check=True)
    package = os.path.join(folder, "Wrapping", "Python", "oraclemesh")
    for name in os.listdir(os.path.dirname(oraclemesh.__file__)):
        if name.startswith("OracleMeshFilters") or name == "fieldkeys.py":
            os.symlink(os.path.realpath(os.path.join(os.path.dirname(oraclemesh.__file__), name)),
                       os.path.join(package, name))
    return os.path.dirname(package)


def run_child(folder, ext, pythonpath, block_rows):
    env = dict(os.environ, PYTHONPATH=pythonpath)
    out = os.path.join(folder, "mesh" + ext)
    command = [sys.executable, os.path.abspath(__file__), "--child", folder, ext, out]
    if block_rows:
        command += ["--block-rows", str(block_rows)]
    result = subprocess.run(command, env=env, capture_output=True, encoding="utf-8", check=False)
    if result.returncode:
        raise SystemExit(f"{ext} ({pythonpath}) failed:\n{result.stderr}")
    return json.loads(result.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tets", type=float, default=2e6, help="about this many tetrahedra (default 2e6)")
    parser.add_argument("--order", type=int, choices=(1, 2), default=1, help="2: 10-node tetrahedra")
    parser.add_argument("--formats", nargs="+", default=list(FORMATS), choices=FORMATS)
    parser.add_argument("--baseline", metavar="REV", help="also the writers at this git revision")
    parser.add_argument("--block-rows", type=int, help="rows formatted at a time by the text writers")
    parser.add_argument("--child", nargs=3, metavar=("FOLDER", "EXT", "OUT"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        return child(*args.child, args.block_rows)
    with tempfile.TemporaryDirectory(prefix="writer_memory.") as folder:
        started = time.perf_counter()
        tets = prepare(folder, int(args.tets), args.order)
        print(f"{tets} tetrahedra ({'10' if args.order == 2 else '4'}-node) built in "
              f"{time.perf_counter() - started:.1f} s", file=sys.stderr)
        packages = [("current", os.environ.get("PYTHONPATH", ""))]
        if args.baseline:
            os.mkdir(os.path.join(folder, "baseline"))
            packages.insert(0, (args.baseline, baseline_package(args.baseline, os.path.join(folder, "baseline"))))
        mib = 1 << 20
        print("| format | writers | tetrahedra | mesh MiB | RSS before MiB | added MiB | added / mesh | seconds "
              "| file MiB | text SHA-256 |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for ext in args.formats:
            for label, path in packages:
                r = run_child(folder, ext, path, args.block_rows if label == "current" else None)
                print(f"| {ext} | {label} | {r['tets']} | {r['mesh'] / mib:.0f} | {r['before'] / mib:.0f} "
                      f"| {r['added'] / mib:.0f} | {r['added'] / r['mesh']:.2f} | {r['seconds']:.1f} "
                      f"| {r['file'] / mib:.0f} | {r['digest']} |", flush=True)
        shutil.rmtree(os.path.join(folder, "baseline"), ignore_errors=True)


if __name__ == "__main__":
    main()
