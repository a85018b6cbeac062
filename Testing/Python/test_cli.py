# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of the command line (mesh formats, report, batch, the installed command), the scene format
(validation, per-domain criteria) and the readers by extension (world placement of label maps).
Run by ctest with /usr/bin/python3 and PYTHONPATH set to the build tree."""
import csv
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import oraclemesh as om
from oraclemesh.report import statistics
from oraclemesh.scene import build_scene, load_scene
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

COMMAND = os.environ.get("ORACLEMESH_COMMAND")  # <build>/bin/oraclemesh
BUILD_DIR = os.environ.get("ORACLEMESH_BUILD_DIR")

# A small two-material scene that meshes in about a second: a ball (material 2) inside a block (1).
SMALL_SCENE = {
    "domains": [
        {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 3, "material": 2},
        {"name": "block", "type": "box", "bounds": [-5, 5, -5, 5, -5, 5], "material": 1},
    ],
    "mesh": {"strategy": "None", "criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.5}, "seed": 1},
}


def run(*args, command=None):
    """Runs the command line (python3 -m oraclemesh, or `command`); returns the CompletedProcess."""
    prefix = [command] if command else [sys.executable, "-m", "oraclemesh"]
    return subprocess.run(prefix + [str(a) for a in args], capture_output=True, encoding="utf-8", check=False)


def write_json(path, description):
    with open(path, "w") as f:
        json.dump(description, f)
    return path


def read_vtu(path):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def material_counts(values):
    ids, counts = np.unique(np.asarray(values), return_counts=True)
    return {int(i): int(c) for i, c in zip(ids, counts)}


class MeshOutputs(unittest.TestCase):
    """One small mesh written in every format, read back with meshio."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.scene = write_json(os.path.join(cls.tmp.name, "small.json"), SMALL_SCENE)
        cls.files = {ext: os.path.join(cls.tmp.name, "out", "small" + ext) for ext in (".vtu", ".inp", ".msh", ".mesh")}
        args = ["mesh", cls.scene, "--histogram", os.path.join(cls.tmp.name, "mesh_hist.png")]
        for path in cls.files.values():
            args += ["-o", path]
        cls.result = run(*args)
        if cls.result.returncode == 0:
            cls.grid = read_vtu(cls.files[".vtu"])
            cls.material = vtk_to_numpy(cls.grid.GetCellData().GetArray("Material"))
            cls.points = vtk_to_numpy(cls.grid.GetPoints().GetData())

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)

    def test_vtu_has_both_materials_and_their_names(self):
        self.assertEqual(set(material_counts(self.material)), {1, 2})
        from oraclemesh.report import material_names

        self.assertEqual(material_names(self.grid), {1: "block", 2: "ball"})
        self.assertTrue(os.path.getsize(os.path.join(self.tmp.name, "mesh_hist.png")) > 1000)

    def read(self, ext):
        import meshio

        mesh = meshio.read(self.files[ext])
        self.assertEqual(len(mesh.points), self.grid.GetNumberOfPoints())
        np.testing.assert_allclose(mesh.points, self.points, rtol=0, atol=1e-9)
        tets = [block for block in mesh.cells if block.type == "tetra"]
        self.assertEqual(len(tets), 1)
        self.assertEqual(len(tets[0].data), self.grid.GetNumberOfCells())
        return mesh

    def test_abaqus_has_one_element_set_per_material_named_after_it(self):
        mesh = self.read(".inp")
        sets = {name: sum(len(part) for part in parts) for name, parts in mesh.cell_sets.items()}
        self.assertEqual(sets, {"BALL": material_counts(self.material)[2], "BLOCK": material_counts(self.material)[1]})
        with open(self.files[".inp"]) as f:
            self.assertIn("*ELEMENT, TYPE=C3D4", f.read())

    def test_gmsh_physical_tags_are_the_materials(self):
        mesh = self.read(".msh")
        physical = mesh.cell_data_dict["gmsh:physical"]["tetra"]
        np.testing.assert_array_equal(physical, self.material)
        self.assertEqual({name: int(v[0]) for name, v in mesh.field_data.items() if v[1] == 3}, {"ball": 2, "block": 1})

    def test_medit_references_are_the_materials(self):
        mesh = self.read(".mesh")
        np.testing.assert_array_equal(mesh.cell_data_dict["medit:ref"]["tetra"], self.material)

    def test_report_gives_the_per_material_counts_and_a_png(self):
        png = os.path.join(self.tmp.name, "report.png")
        text = os.path.join(self.tmp.name, "report.txt")
        result = run("report", self.files[".vtu"], "--png", png, "--report", text)
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = {}
        for line in result.stdout.splitlines():
            parts = line.split()
            if len(parts) >= 3 and parts[0] in ("1", "2"):
                rows[int(parts[0])] = int(parts[2])  # material, name, tets, ...
        self.assertEqual(rows, material_counts(self.material))
        self.assertIn(f"{self.grid.GetNumberOfCells()} tetrahedra", result.stdout)
        self.assertIn("feature lines: none given", result.stdout)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        self.assertGreater(os.path.getsize(png), 1000)
        with open(text) as f:
            self.assertEqual(f.read().strip(), result.stdout.strip())

    def test_report_volumes_equal_the_mesher_statistics(self):
        from oraclemesh.report import quality, statistics

        q, stats = quality(self.grid), statistics(self.grid)  # numpy here, C++ in the mesher
        for m in (1, 2):
            self.assertAlmostEqual(q["materials"][m]["volume"], stats[f"volume.material_{m}"], places=6)
        self.assertAlmostEqual(sum(m["volume"] for m in q["materials"].values()), q["volume"])
        self.assertLess(q["volume"], 1000.0 + 1e-9)  # inside the block

    def test_bad_report_inputs_name_the_file(self):
        missing = os.path.join(self.tmp.name, "none.vtu")
        result = run("report", missing)
        self.assertEqual(result.returncode, 2)
        self.assertIn(f"{missing}: file not found", result.stderr)
        other = os.path.join(self.tmp.name, "mesh.stl")
        with open(other, "w") as f:
            f.write("solid x\nendsolid x\n")
        result = run("report", other)
        self.assertEqual(result.returncode, 2)
        self.assertIn(f"{other}: the report reads meshes written by 'oraclemesh mesh'", result.stderr)

    def test_report_checks_validity_and_strict_fails_on_defects(self):
        result = run("report", self.files[".vtu"], "--no-png", "--strict")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("validity: no defects", result.stdout)
        # the same mesh with one tetrahedron inverted and one point moved onto another
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

        grid = read_vtu(self.files[".vtu"])
        ids = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
        ids[[0, 1]] = ids[[1, 0]]
        grid.GetCells().Modified()
        points = vtk_to_numpy(grid.GetPoints().GetData())
        a, b = ids[4], ids[5]  # two vertices of the second tetrahedron: a flat, duplicated one now
        points[b] = points[a] * (1 + 1e-14)
        grid.GetPoints().Modified()
        broken = os.path.join(self.tmp.name, "broken.vtu")
        writer = vtkXMLUnstructuredGridWriter()
        writer.SetInputData(grid)
        writer.SetFileName(broken)
        writer.Write()
        result = run("report", broken, "--no-png")
        self.assertEqual(result.returncode, 0, result.stderr)  # without --strict: reported only
        self.assertRegex(result.stdout, r"validity: \d+ DEFECTS: .*2 duplicate vertices.*inverted tetrahedra")
        result = run("report", broken, "--no-png", "--strict")
        self.assertEqual(result.returncode, 3)
        self.assertIn(f"{broken}: ", result.stderr)
        self.assertIn("validity defects (--strict)", result.stderr)

    def test_unknown_output_format_is_refused_before_meshing(self):
        result = run("mesh", self.scene, "-o", os.path.join(self.tmp.name, "x.stl"))
        self.assertEqual(result.returncode, 2)
        self.assertIn("x.stl: unknown mesh format '.stl'", result.stderr)


def _two_tetrahedra(materials):
    from vtkmodules.util.vtkConstants import VTK_TETRA
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, -1)):
        points.InsertNextPoint(p)
    grid.SetPoints(points)
    array = vtkIntArray()
    array.SetName("Material")
    for ids, m in zip(((0, 1, 2, 3), (0, 2, 1, 4)), materials):
        grid.InsertNextCell(VTK_TETRA, 4, ids)
        array.InsertNextValue(m)
    grid.GetCellData().AddArray(array)
    return grid


class Writers(unittest.TestCase):
    def test_abaqus_set_names_are_valid_and_distinct(self):
        import meshio

        from oraclemesh.writers import write_mesh

        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "two.inp")
            write_mesh(_two_tetrahedra((1, 2)), path, {1: "cortical bone", 2: "Cortical-Bone"})
            sets = meshio.read(path).cell_sets
            self.assertEqual({k: [list(p) for p in v] for k, v in sets.items()},
                             {"CORTICAL_BONE": [[0]], "CORTICAL_BONE_2": [[1]]})
            write_mesh(_two_tetrahedra((0, 7)), path)
            self.assertEqual(set(meshio.read(path).cell_sets), {"MATERIAL_0", "MATERIAL_7"})

    def test_bad_meshes_and_formats_are_named(self):
        from oraclemesh.writers import write_mesh

        with tempfile.TemporaryDirectory() as tmp:
            with self.assertRaises(om.OracleMeshError) as ctx:
                write_mesh(_two_tetrahedra((0, 1)), os.path.join(tmp, "zero.msh"))
            self.assertIn("zero.msh: material 0 cannot be a Gmsh physical tag", str(ctx.exception))
            with self.assertRaises(om.OracleMeshError) as ctx:
                write_mesh(_two_tetrahedra((1, 2)), os.path.join(tmp, "a.off"))
            self.assertIn("a.off: unknown mesh format '.off'", str(ctx.exception))
            grid = _two_tetrahedra((1, 2))
            grid.GetCellData().RemoveArray("Material")
            with self.assertRaises(om.OracleMeshError) as ctx:
                write_mesh(grid, os.path.join(tmp, "b.mesh"))
            self.assertIn("b.mesh: no cell array 'Material'", str(ctx.exception))


class Batch(unittest.TestCase):
    def test_two_scenes_mesh_and_the_broken_ones_are_reported(self):
        with tempfile.TemporaryDirectory() as tmp:
            small = write_json(os.path.join(tmp, "small.json"), SMALL_SCENE)
            other = dict(SMALL_SCENE, domains=[dict(SMALL_SCENE["domains"][0], radius=2), SMALL_SCENE["domains"][1]])
            smaller = write_json(os.path.join(tmp, "smaller.json"), other)
            broken = os.path.join(tmp, "broken.json")
            with open(broken, "w") as f:
                f.write('{"domains": [')
            missing = os.path.join(tmp, "missing.json")
            out = os.path.join(tmp, "out")
            result = run("batch", small, broken, smaller, missing, "--jobs", "2", "-o", out, "-f", "vtu", "-f", "inp")
            self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
            self.assertIn(f"{broken}: not valid JSON", result.stderr)
            self.assertIn(f"{missing}: scene file not found", result.stderr)
            with open(os.path.join(out, "summary.csv")) as f:
                rows = {os.path.basename(r["scene"]): r for r in csv.DictReader(f)}
            self.assertEqual({k: r["status"] for k, r in rows.items()},
                             {"small.json": "ok", "smaller.json": "ok", "broken.json": "failed",
                              "missing.json": "failed"})
            self.assertIn("not valid JSON", rows["broken.json"]["error"])
            for name in ("small", "smaller"):
                row = rows[name + ".json"]
                grid = read_vtu(os.path.join(out, name, "mesh.vtu"))  # a folder per case
                self.assertEqual(int(row["tets"]), grid.GetNumberOfCells())
                self.assertEqual(int(row["vertices"]), grid.GetNumberOfPoints())
                angles = vtk_to_numpy(grid.GetCellData().GetArray("MinDihedralAngle"))
                self.assertAlmostEqual(float(row["min_dihedral"]), angles.min(), places=2)
                self.assertGreater(float(row["seconds"]), 0)
                self.assertEqual(row["error"], "")
                self.assertTrue(os.path.getsize(os.path.join(out, name, "mesh.inp")) > 0)
                self.assertTrue(os.path.getsize(os.path.join(out, name, "report.txt")) > 0)
            # the smaller ball has fewer tetrahedra in material 2: the two scenes were not mixed up
            counts = {n: material_counts(vtk_to_numpy(read_vtu(os.path.join(out, n, "mesh.vtu")).GetCellData()
                                                      .GetArray("Material"))) for n in ("small", "smaller")}
            self.assertLess(counts["smaller"][2], counts["small"][2])

    def test_a_scene_over_its_timeout_is_stopped_and_reported(self):
        with tempfile.TemporaryDirectory() as tmp:
            small = write_json(os.path.join(tmp, "small.json"), SMALL_SCENE)
            result = run("batch", small, "--timeout", "0.05", "-o", tmp)
            self.assertEqual(result.returncode, 1)
            self.assertIn("stopped after the 0.05 s timeout", result.stderr)

    def test_bad_jobs_is_a_usage_error(self):
        result = run("batch", "a.json", "--jobs", "0")
        self.assertEqual(result.returncode, 2)
        self.assertIn("--jobs: must be at least 1", result.stderr)


@unittest.skipUnless(COMMAND, "ORACLEMESH_COMMAND not set")
class Command(unittest.TestCase):
    def test_build_tree_command_runs_without_pythonpath(self):
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        result = subprocess.run([COMMAND, "--help"], capture_output=True, encoding="utf-8", env=env, check=False)
        self.assertEqual(result.returncode, 0, result.stderr)
        for sub in ("sample", "mesh", "report", "batch"):
            self.assertIn(sub, result.stdout)

    @unittest.skipUnless(BUILD_DIR, "ORACLEMESH_BUILD_DIR not set")
    def test_installed_command_meshes_a_scene(self):
        with tempfile.TemporaryDirectory() as tmp:
            prefix = os.path.join(tmp, "prefix")
            subprocess.run(["cmake", "--install", BUILD_DIR, "--prefix", prefix], check=True, capture_output=True)
            env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
            scene = write_json(os.path.join(tmp, "small.json"), SMALL_SCENE)
            out = os.path.join(tmp, "small.mesh")
            result = subprocess.run([os.path.join(prefix, "bin", "oraclemesh"), "mesh", scene, "-o", out],
                                    capture_output=True, encoding="utf-8", env=env, cwd=tmp, check=False)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn("Tetrahedra", open(out).read())
            # compiled at install: users who cannot write there do not compile the package on every start
            import glob
            self.assertTrue(glob.glob(os.path.join(prefix, "**", "oraclemesh", "__pycache__", "meshing.*.pyc"),
                                      recursive=True), "no bytecode installed")

    def test_no_numpy_before_meshing(self):
        # numpy (20 MB, 0.1 s) is for the report and the writers: the process floor and the mesher's
        # peak memory go without it (Benchmarks/small_cases.py)
        code = ("import sys, oraclemesh.__main__; from oraclemesh.meshing import as_scene, mesher_for; "
                "mesher_for(as_scene(%r)); print(sorted(m for m in sys.modules if m.split('.')[0] == 'numpy'))"
                % SMALL_SCENE)
        result = subprocess.run([sys.executable, "-c", code], capture_output=True, encoding="utf-8", check=False)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout.strip(), "[]")


class Threads(unittest.TestCase):
    """The parallel refinement through every door (--threads, the scene's "threads", threads=), whose
    default is one and the same at each (the C++'s)."""

    def test_default_is_the_cxx_one_at_every_door(self):
        from oraclemesh import vtkFeaturePreservingTetrahedralizer
        from oraclemesh.defaults import mesh_defaults

        self.assertEqual(mesh_defaults()["threads"], vtkFeaturePreservingTetrahedralizer().GetThreads())
        self.assertEqual(mesh_defaults()["threads"], 1)  # sequential: identical meshes per seed
        self.assertIn('"threads", else 1)', " ".join(run("mesh", "--help").stdout.split()))
        self.assertEqual(om.mesh(SMALL_SCENE).statistics["refinement_threads"], 1)

    def test_two_threads_keep_the_volumes_and_validity(self):
        """The parallel mesh approximates the materials' volumes as well as the sequential one (its
        error at most 1.5 times the sequential's, plus 0.5%): a different mesh, the same accuracy."""
        scene = json.loads(json.dumps(SMALL_SCENE))
        scene["mesh"]["criteria"]["facet_distance"] = 0.1
        seq = om.mesh(scene).statistics
        par = om.mesh(scene, threads=2).statistics
        self.assertEqual(par["refinement_threads"], 2)
        self.assertEqual(par["validity.defects"], 0)
        ball = 4 / 3 * math.pi * 3 ** 3
        for key, exact in (("volume.material_2", ball), ("volume.material_1", 10 ** 3 - ball)):
            self.assertLessEqual(abs(par[key] - exact), 1.5 * abs(seq[key] - exact) + 0.005 * exact, key)

    def test_command_line_and_scene_key(self):
        with tempfile.TemporaryDirectory() as tmp:
            scene = write_json(os.path.join(tmp, "threads.json"),
                               dict(SMALL_SCENE, mesh=dict(SMALL_SCENE["mesh"], threads=2)))
            out = os.path.join(tmp, "threads.vtu")
            result = run("mesh", scene, "-o", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(statistics(read_vtu(out))["refinement_threads"], 2)
            result = run("mesh", scene, "-o", out, "--threads", 1)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(statistics(read_vtu(out))["refinement_threads"], 1)
            result = run("mesh", scene, "-o", out, "--threads", -1)
            self.assertEqual(result.returncode, 2)
            self.assertIn("threads: must be an integer >= 0", result.stderr)
            bad = write_json(os.path.join(tmp, "bad.json"), dict(SMALL_SCENE, mesh=dict(SMALL_SCENE["mesh"], threads=-1)))
            result = run("mesh", bad, "-o", out)
            self.assertEqual(result.returncode, 2)
            self.assertIn("$.mesh.threads: -1 is out of range", result.stderr)


class SceneFormat(unittest.TestCase):
    def test_mesh_block_problems_are_listed_with_their_json_paths(self):
        description = {
            "domains": [
                {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 1, "material": 1,
                 "criteria": {"cell_sise": 1}},
                {"name": "cut", "type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1], "cut": True,
                 "criteria": {"cell_size": 1}},
            ],
            "space": "XYZ",
            "colour": "red",
            "mesh": {"strategy": "Fast", "criteria": {"cell_size": "big"}, "materials": {"x": {}},
                     "features": {"from_surface": "ball"}, "seed": 1.5},
            "outputs": {"mesh": ["a.vtu", "a.stl"]},
        }
        with self.assertRaises(om.OracleMeshError) as ctx:
            build_scene(description, base_dir=tempfile.gettempdir())
        text = str(ctx.exception)
        for fragment in ("$.domains[0].criteria.cell_sise: unknown criterion",
                         "$.domains[1].criteria: a cut domain has no material",
                         "$.space: must be one of LPS, RAS", "$.colour: unknown key",
                         "$.mesh.strategy: must be one of", "$.mesh.criteria.cell_size: must be a number",
                         "$.mesh.materials.x: key must be an integer", "$.mesh.features.from_surface: no surface domain named 'ball'",
                         "$.mesh.seed: must be an integer", "$.outputs.mesh[1]: unknown mesh format '.stl'"):
            self.assertIn(fragment, text)

    def test_domain_criteria_apply_to_the_domain_materials(self):
        with tempfile.TemporaryDirectory() as tmp:
            labels = _label_image()
            from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

            writer = vtkXMLImageDataWriter()
            writer.SetFileName(os.path.join(tmp, "labels.vti"))
            writer.SetInputData(labels)
            writer.Write()
            scene = build_scene({
                "domains": [
                    {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": 7, "criteria": {"cell_size": 0.5}},
                    {"type": "labelmap", "file": "labels.vti", "criteria": {"facet_distance": 0.2}},
                ],
                "mesh": {"materials": {"7": {"cell_size": 0.3, "facet_size": 0.4}}},
            }, base_dir=tmp)
            # the domains carry their own criteria (the core merges them), "mesh.materials" is the table
            self.assertEqual(scene.domains[0].GetCellSize(), 0.5)
            self.assertEqual(scene.domains[1].GetFacetDistance(), 0.2)
            self.assertLess(scene.domains[1].GetCellSize(), 0)  # not set
            self.assertEqual(scene.mesh["materials"], {7: {"cell_size": 0.3, "facet_size": 0.4}})
            # two domains, one material, two values: the core's error (the same through every door)
            clash = build_scene({"domains": [
                {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": 1, "criteria": {"cell_size": 1}},
                {"type": "sphere", "center": [3, 0, 0], "radius": 1, "material": 1, "criteria": {"cell_size": 2}},
            ]})
            from oraclemesh.meshing import mesher_for

            with self.assertRaises(om.OracleMeshError) as ctx:
                om.update(mesher_for(clash))
            self.assertIn("criteria: material 1 gets CellSize 1 from domain 'sphere0' and 2 from domain 'sphere1'",
                          str(ctx.exception))

    def test_finer_domain_criteria_give_more_tetrahedra_in_that_material(self):
        from oraclemesh.meshing import mesher_for

        counts = []
        for criteria in ({}, {"cell_size": 0.7}):
            description = json.loads(json.dumps(SMALL_SCENE))
            if criteria:
                description["domains"][0]["criteria"] = criteria
            grid = om.update(mesher_for(build_scene(description)))
            counts.append(material_counts(vtk_to_numpy(grid.GetCellData().GetArray("Material"))))
        self.assertGreater(counts[1][2], 2 * counts[0][2])

    def test_feature_lines_from_a_surface_and_from_files_are_joined(self):
        from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkFeatureEdges, vtkTriangleFilter
        from vtkmodules.vtkFiltersSources import vtkCubeSource
        from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

        from oraclemesh.meshing import mesher_for

        with tempfile.TemporaryDirectory() as tmp:
            cube = vtkCubeSource()
            triangles = vtkTriangleFilter()
            triangles.SetInputConnection(cube.GetOutputPort())
            clean = vtkCleanPolyData()
            clean.SetInputConnection(triangles.GetOutputPort())
            edges = vtkFeatureEdges()
            edges.SetInputConnection(clean.GetOutputPort())
            edges.BoundaryEdgesOff()
            edges.NonManifoldEdgesOff()
            edges.ManifoldEdgesOff()
            for name, algorithm in (("cube.vtp", clean), ("edges.vtp", edges)):
                writer = vtkXMLPolyDataWriter()
                writer.SetFileName(os.path.join(tmp, name))
                writer.SetInputConnection(algorithm.GetOutputPort())
                writer.Write()
            scene = build_scene({"domains": [{"name": "cube", "type": "surface", "file": "cube.vtp", "material": 1}],
                                 "mesh": {"features": {"from_surface": "cube", "files": ["edges.vtp"]}}}, base_dir=tmp)
            mesher = mesher_for(scene)
            lines = om.update(mesher.GetInputAlgorithm(1, 0))
            self.assertEqual(lines.GetNumberOfLines(), 2 * 12)  # the cube's 12 edges, twice

    def test_outputs_section_is_used_when_no_output_is_given(self):
        with tempfile.TemporaryDirectory() as tmp:
            description = dict(SMALL_SCENE, outputs={"mesh": ["out/a.vtu", "out/a.mesh"], "report": "out/r.txt",
                                                     "histogram": "out/h.png"})
            scene = write_json(os.path.join(tmp, "s.json"), description)
            result = run("mesh", scene, "--progress")
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn("meshing: 100%", result.stderr)  # not a terminal: a line every 10 %
            for name in ("a.vtu", "a.mesh", "r.txt", "h.png"):
                self.assertTrue(os.path.getsize(os.path.join(tmp, "out", name)) > 0, name)
            no_output = write_json(os.path.join(tmp, "n.json"), SMALL_SCENE)
            result = run("mesh", no_output)
            self.assertEqual(result.returncode, 2)
            self.assertIn("no output: give -o OUT", result.stderr)


# --- readers by extension ----------------------------------------------------------------------------

SPACING = np.array([0.5, 1.0, 2.0])
ORIGIN = np.array([10.0, -20.0, 30.0])
DIRECTION = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 degrees about z
LABELS = np.zeros((8, 10, 12), np.uint8)  # [k, j, i]
LABELS[2:5, 3:7, 2:6] = 5  # points i 2..5, j 3..6, k 2..4: the region's centre is at index (3.5, 4.5, 3)
LABEL_CENTRE = ORIGIN + DIRECTION @ (SPACING * np.array([3.5, 4.5, 3.0]))
LABEL_VOLUME = 4 * 4 * 3 * SPACING.prod()
LPS_FROM_RAS = np.diag([-1.0, -1.0, 1.0])


def _label_image(origin=ORIGIN, direction=DIRECTION):
    from vtkmodules.vtkCommonDataModel import vtkImageData

    image = vtkImageData()
    image.SetDimensions(12, 10, 8)
    image.SetSpacing(*SPACING)
    image.SetOrigin(*origin)
    image.SetDirectionMatrix(*np.asarray(direction).ravel())
    array = numpy_to_vtk(LABELS.ravel(), deep=True)
    array.SetName("labels")
    image.GetPointData().SetScalars(array)
    return image


def _region(scene, material, dims=80):
    """(centroid, volume) of `material` in the scene's sampled oracle."""
    sampler = om.vtkOracleSampler()
    sampler.SetInputConnection(scene.oracle.GetOutputPort())
    sampler.SetDimensions(dims, dims, dims)
    image = om.update(sampler)
    values = vtk_to_numpy(image.GetPointData().GetArray("Material"))
    points = np.array([image.GetPoint(int(i)) for i in np.flatnonzero(values == material)])
    fd = image.GetFieldData()
    ids, volumes = fd.GetArray("MaterialIds"), fd.GetArray("MaterialVolume")
    volume = {ids.GetValue(i): volumes.GetValue(i) for i in range(ids.GetNumberOfTuples())}[material]
    return points.mean(axis=0), volume


class Readers(unittest.TestCase):
    """Files written in each format, read back through a scene: the material lands where the file says."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def assertPlaced(self, file, centre, space=None, volume=LABEL_VOLUME):
        # Trilinear: the 4 x 4 x 3 voxel block keeps about its voxel volume (Smooth, the default,
        # rounds a block this small: its edges and corners are all there is of it)
        description = {"domains": [{"type": "labelmap", "file": file, "interpolation": "trilinear"}]}
        if space:
            description["space"] = space
        found, found_volume = _region(build_scene(description, base_dir=self.dir), 5)
        step = 0.2 * SPACING.max()  # sampling error: the sampler's grid does not match the voxels
        np.testing.assert_allclose(found, centre, atol=step, err_msg=file)
        self.assertAlmostEqual(found_volume, volume, delta=0.15 * volume, msg=file)

    def write(self, writer_class, name, image, **setters):
        writer = writer_class()
        writer.SetFileName(os.path.join(self.dir, name))
        writer.SetInputData(image)
        for key, value in setters.items():
            getattr(writer, "Set" + key)(value)
        writer.Write()
        self.assertTrue(os.path.isfile(os.path.join(self.dir, name)), name)

    def test_vti_keeps_origin_spacing_and_direction(self):
        from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

        self.write(vtkXMLImageDataWriter, "a.vti", _label_image())
        self.assertPlaced("a.vti", LABEL_CENTRE)

    def test_metaimage_origin_spacing_and_transform_matrix(self):
        from vtkmodules.vtkIOImage import vtkMetaImageWriter

        # VTK's writer keeps origin and spacing (no direction): .mha and .mhd (+ .raw)
        plain = ORIGIN + SPACING * np.array([3.5, 4.5, 3.0])
        self.write(vtkMetaImageWriter, "a.mha", _label_image(direction=np.eye(3)), Compression=True)
        self.assertPlaced("a.mha", plain)
        self.write(vtkMetaImageWriter, "b.mhd", _label_image(direction=np.eye(3)), Compression=False)
        self.assertPlaced("b.mhd", plain)
        # ITK writes the direction as TransformMatrix (the direction of axis i is the i-th triple)
        header = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
                  "CompressedData = False\nTransformMatrix = " + " ".join(f"{v:g}" for v in DIRECTION.T.ravel())
                  + "\nOffset = " + " ".join(f"{v:g}" for v in ORIGIN)
                  + "\nElementSpacing = 0.5 1 2\nDimSize = 12 10 8\nAnatomicalOrientation = RAI\n"
                  "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
        with open(os.path.join(self.dir, "itk.mha"), "wb") as f:
            f.write(header.encode() + LABELS.tobytes())
        self.assertPlaced("itk.mha", LABEL_CENTRE)

    def _nifti(self, name, form):
        from vtkmodules.vtkCommonMath import vtkMatrix4x4
        from vtkmodules.vtkIOImage import vtkNIFTIImageWriter

        matrix = vtkMatrix4x4()  # NIfTI's world (RAS): rotation and offset
        for i in range(3):
            for j in range(3):
                matrix.SetElement(i, j, DIRECTION[i, j])
            matrix.SetElement(i, 3, ORIGIN[i])
        self.write(vtkNIFTIImageWriter, name, _label_image(origin=(0, 0, 0), direction=np.eye(3)),
                   **{form + "Matrix": matrix})

    def test_nifti_qform_and_sform_place_the_labels(self):
        for name, form in (("q.nii", "QForm"), ("s.nii.gz", "SForm")):
            self._nifti(name, form)
            self.assertPlaced(name, LABEL_CENTRE, space="RAS")
            self.assertPlaced(name, LPS_FROM_RAS @ LABEL_CENTRE)  # the default scene frame is LPS

    def test_nrrd_space_directions_origin_and_frame(self):
        columns = DIRECTION * SPACING  # column i: the step along axis i
        directions = " ".join("(" + ",".join(f"{v:g}" for v in columns[:, i]) + ")" for i in range(3))
        origin = "(" + ",".join(f"{v:g}" for v in ORIGIN) + ")"

        def header(space, encoding, extra=""):
            return (f"NRRD0004\n# written by the test\ntype: unsigned char\ndimension: 3\nspace: {space}\n"
                    f"sizes: 12 10 8\nspace directions: {directions}\nkinds: domain domain domain\n"
                    f"endian: little\nencoding: {encoding}\nspace origin: {origin}\n{extra}")

        with open(os.path.join(self.dir, "lps.nrrd"), "wb") as f:
            f.write((header("left-posterior-superior", "gzip") + "\n").encode() + gzip.compress(LABELS.tobytes()))
        self.assertPlaced("lps.nrrd", LABEL_CENTRE)
        with open(os.path.join(self.dir, "ras.nhdr"), "w") as f:  # detached header, raw data
            f.write(header("right-anterior-superior", "raw", "data file: ras.raw\n"))
        with open(os.path.join(self.dir, "ras.raw"), "wb") as f:
            f.write(LABELS.tobytes())
        self.assertPlaced("ras.nhdr", LPS_FROM_RAS @ LABEL_CENTRE)
        self.assertPlaced("ras.nhdr", LABEL_CENTRE, space="RAS")

    def test_inrimage_spacing_and_translation(self):
        import struct

        values = LABELS.astype(np.uint16)  # 16 bits, big-endian ("sun"), gzip-compressed
        header = ("#INRIMAGE-4#{\nXDIM=12\nYDIM=10\nZDIM=8\nVDIM=1\nTYPE=unsigned fixed\nPIXSIZE=16 bits\n"
                  "SCALE=2**0\nCPU=sun\nVX=0.5\nVY=1\nVZ=2\n" + "".join(f"T{a}={v:g}\n" for a, v in zip("XYZ", ORIGIN)))
        header = header + "\n" * (256 - len(header) - 4) + "##}\n"
        with gzip.open(os.path.join(self.dir, "a.inr.gz"), "wb") as f:
            f.write(header.encode() + struct.pack(f">{values.size}H", *values.ravel()))
        self.assertPlaced("a.inr.gz", ORIGIN + SPACING * np.array([3.5, 4.5, 3.0]))

    def test_bad_nrrd_is_named(self):
        with open(os.path.join(self.dir, "four.nrrd"), "wb") as f:
            f.write(b"NRRD0004\ntype: uint8\ndimension: 4\nsizes: 1 2 2 2\nencoding: raw\n\n12345678")
        scene = build_scene({"domains": [{"type": "labelmap", "file": "four.nrrd"}]}, base_dir=self.dir)
        with self.assertRaises(om.OracleMeshError) as ctx:
            _region(scene, 5, 10)
        self.assertIn("four.nrrd: a label map must be a 3-D scalar volume", str(ctx.exception))

    def test_surfaces_in_every_format(self):
        from vtkmodules.vtkFiltersSources import vtkSphereSource
        from vtkmodules.vtkIOGeometry import vtkOBJWriter, vtkSTLWriter
        from vtkmodules.vtkIOLegacy import vtkPolyDataWriter
        from vtkmodules.vtkIOPLY import vtkPLYWriter
        from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

        source = vtkSphereSource()
        source.SetCenter(5, -3, 2)
        source.SetRadius(2)
        source.SetThetaResolution(48)
        source.SetPhiResolution(48)
        source.Update()
        for name, writer in (("s.vtp", vtkXMLPolyDataWriter), ("s.vtk", vtkPolyDataWriter),
                             ("s.stl", vtkSTLWriter), ("s.obj", vtkOBJWriter), ("s.ply", vtkPLYWriter)):
            self.write(writer, name, source.GetOutput())
            scene = build_scene({"domains": [{"type": "surface", "file": name, "material": 3}]}, base_dir=self.dir)
            centre, volume = _region(scene, 3, 60)
            np.testing.assert_allclose(centre, [5, -3, 2], atol=0.05, err_msg=name)
            self.assertAlmostEqual(volume, 4 / 3 * math.pi * 8, delta=0.03 * 4 / 3 * math.pi * 8, msg=name)


if __name__ == "__main__":
    unittest.main()
