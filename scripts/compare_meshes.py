#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Meshes a few scenes with a fixed seed through two builds and compares the meshes bit for bit
(points, tetrahedra, materials, interface triangles and the mesher's statistics other than times;
statistics only the build writes are listed as new, not as differences):
a restructuring that claims to change no behaviour is checked against the build before it.

    scripts/compare_meshes.py --snapshot DIR [--build BUILD]    # copy BUILD's binaries to DIR
    scripts/compare_meshes.py --reference DIR [--build BUILD] [--work WORK] [--scenes NAME...] [--set KEY=VALUE...]

A snapshot holds the command line, the Python package and the VTK module library of a build; it
runs with LD_LIBRARY_PATH set to it (the build's libraries carry a RUNPATH, which that overrides).
Scenes: the demo (Data/demo/scene.json, fewer vertices), a generated bone/implant case
(oraclemesh_cases.cases), a cube with all edges as features, a noisy organic surface with automatic
sharp edges (Benchmarks/noisy_features.py), a ball cut by a plane with the automatic feature lines
(its rim) and 10-node tetrahedra (the paths the other four do not take). Exits 1 when any mesh
differs. `--both` passes settings to both builds' runs (e.g. `--both strategy=None`: every scene
with another strategy); `--set` passes `oraclemesh mesh --set` settings to the build's runs only: a new option at
the value that should give the reference's meshes (e.g. a new behaviour turned off).
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
SCENES = ("demo", "bone_implant", "featured_cube", "noisy_sphere", "cut_ball_automatic_p2")


def snapshot(build, folder):
    lib = os.path.join(folder, "lib")
    os.makedirs(os.path.join(folder, "bin"), exist_ok=True)
    os.makedirs(lib, exist_ok=True)
    shutil.copytree(os.path.join(build, "lib", "python3.11"), os.path.join(lib, "python3.11"), symlinks=False,
                    dirs_exist_ok=True)
    for so in glob.glob(os.path.join(build, "lib", "libOracleMeshFilters.so*")):
        shutil.copy(so, lib, follow_symlinks=True)
    shutil.copy(os.path.join(build, "bin", "oraclemesh"), os.path.join(folder, "bin"))


def environment(root):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(root, "lib", "python3.11", "site-packages")
    env["LD_LIBRARY_PATH"] = os.path.join(root, "lib")
    return env


def make_scenes(work, names, build):
    env = environment(build)
    sys.path.insert(0, env["PYTHONPATH"])
    scenes = {}
    if "demo" in names:
        with open(os.path.join(SOURCE, "Data", "demo", "scene.json")) as f:
            demo = json.load(f)
        for d in demo["domains"]:
            if "file" in d:
                d["file"] = os.path.join(SOURCE, "Data", "demo", d["file"])
        demo["mesh"].update(maximum_number_of_vertices=20000, seed=3)
        scenes["demo"] = demo
    if "bone_implant" in names:
        from oraclemesh_cases import cases

        path = cases.make_case(os.path.join(work, "bone_implant"), 4, variant="random", radius_edge=1.3)
        with open(path) as f:
            case = json.load(f)
        for d in case["domains"]:
            if "file" in d:
                d["file"] = os.path.join(work, "bone_implant", d["file"])
        case["mesh"]["seed"] = 5
        scenes["bone_implant"] = case
    if "featured_cube" in names:
        scenes["featured_cube"] = {
            "domains": [{"name": "cube", "type": "box", "bounds": [0, 1, 0, 1, 0, 1], "material": 1}],
            "mesh": {"strategy": "Conforming", "seed": 2,
                     "criteria": {"cell_size": 0.2, "facet_size": 0.2, "facet_distance": 0.02, "edge_size": 0.2},
                     "features": {"files": [os.path.join(work, "cube_edges.vtp")]}},
        }
        cube_edges(os.path.join(work, "cube_edges.vtp"))
    if "noisy_sphere" in names:
        sys.path.insert(0, os.path.join(SOURCE, "Benchmarks"))
        import noisy_features

        path = noisy_features.make_case(os.path.join(work, "noisy_sphere"), "tiny", True)
        with open(path) as f:
            case = json.load(f)
        case["domains"][0]["file"] = os.path.join(work, "noisy_sphere", case["domains"][0]["file"])
        scenes["noisy_sphere"] = case
    if "cut_ball_automatic_p2" in names:
        scenes["cut_ball_automatic_p2"] = {
            "domains": [{"name": "cut", "type": "plane", "origin": [0, 0, 0.3], "normal": [0, 0, -1], "cut": True},
                        {"name": "ball", "type": "sphere", "center": [0.1, -0.05, 0], "radius": 1, "material": 1}],
            "mesh": {"strategy": "Conforming", "seed": 4, "element_order": 2, "features": "Automatic",
                     "criteria": {"cell_size": 0.25, "facet_size": 0.2, "facet_distance": 0.02, "edge_size": 0.15}},
        }
    paths = {}
    for name, scene in scenes.items():
        paths[name] = os.path.join(work, f"{name}.json")
        with open(paths[name], "w") as f:
            json.dump(scene, f, indent=1)
    return paths


def cube_edges(path):
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    points = vtkPoints()
    for k in range(8):
        points.InsertNextPoint(k & 1, (k >> 1) & 1, (k >> 2) & 1)
    lines = vtkCellArray()
    for a in range(8):
        for bit in (1, 2, 4):
            if not a & bit:
                lines.InsertNextCell(2, (a, a | bit))
    poly = vtkPolyData()
    poly.SetPoints(points)
    poly.SetLines(lines)
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(poly)
    writer.Write()


def mesh(root, scene, out, settings=()):
    cmd = [sys.executable, os.path.join(root, "bin", "oraclemesh"), "mesh", scene, "-o", out]
    for setting in settings:
        cmd += ["--set", setting]
    subprocess.run(cmd, env=environment(root), check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def fingerprint(path):
    """Everything of a written mesh that a seed fixes: arrays as bytes, statistics but the times (and the
    time limit)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    parts = {"points": vtk_to_numpy(grid.GetPoints().GetData()).tobytes(),
             "cells": vtk_to_numpy(grid.GetCells().GetConnectivityArray()).tobytes()}
    for data, kind in ((grid.GetCellData(), "cell"), (grid.GetPointData(), "point")):
        for i in range(data.GetNumberOfArrays()):
            array = data.GetArray(i)
            if array is not None:
                parts[f"{kind}:{array.GetName()}"] = vtk_to_numpy(array).tobytes()
    from oraclemesh.fielddata import labelled

    for name, value in labelled(grid.GetFieldData(), "StatisticValues"):
        # times depend on the load; time_limit is the run's limit (a setting echoed, not a result)
        if not name.startswith(("time.", "cpu.")) and name != "time_limit":
            parts[f"statistic:{name}"] = repr(value)
    return parts


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(SOURCE, "build"))
    parser.add_argument("--snapshot", help="copy the build's binaries to this folder and stop")
    parser.add_argument("--reference", help="a snapshot to compare the build with")
    parser.add_argument("--work", default=None)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene mesh key for the build's runs only (repeat for several)")
    parser.add_argument("--both", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene mesh key for both builds' runs, e.g. strategy=None (repeat for several)")
    args = parser.parse_args(argv)
    if args.snapshot:
        snapshot(args.build, args.snapshot)
        print(f"snapshot of {args.build} in {args.snapshot}")
        return 0
    if not args.reference:
        parser.error("give --snapshot or --reference")
    work = args.work or tempfile.mkdtemp(prefix="compare_meshes_")
    scenes = make_scenes(work, args.scenes, args.build)
    differ = 0
    for name, scene in scenes.items():
        meshes = {}
        for tag, root in (("reference", args.reference), ("build", args.build)):
            meshes[tag] = os.path.join(work, f"{name}_{tag}.vtu")
            mesh(root, scene, meshes[tag], args.both + (args.set if tag == "build" else []))
        a, b = fingerprint(meshes["reference"]), fingerprint(meshes["build"])
        # statistics only the build writes are new figures, not differences
        new = sorted(k for k in set(b) - set(a) if k.startswith("statistic:"))
        diff = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k) and k not in new)
        differ += bool(diff)
        extra = f" ({len(new)} new statistics, e.g. {new[0][len('statistic:'):]})" if new else ""
        print(f"{name:<14} {'identical' + extra if not diff else 'DIFFERENT: ' + ', '.join(diff[:8])}", flush=True)
    print(f"work folder: {work}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
