# SPDX-License-Identifier: GPL-3.0-or-later
"""Python tests of the wrapped module and the oraclemesh package (run by ctest with
/usr/bin/python3 and PYTHONPATH set to the build tree)."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import oraclemesh as om
from oraclemesh.scene import build_scene, load_scene
from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkCubeSource, vtkSphereSource

from demo_counts import SAMPLES, counts_of, reference_counts

DATA = os.environ.get("ORACLEMESH_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
DEMO_SCENE = os.path.join(DATA, "demo", "scene.json")


def sample(oracle_algorithm, n=SAMPLES):
    sampler = om.vtkOracleSampler()
    sampler.SetInputConnection(oracle_algorithm.GetOutputPort())
    sampler.SetDimensions(n, n, n)
    return om.update(sampler)


def oracle_of(*domains):
    oracle = om.vtkHierarchicalOracle()
    for d in domains:
        oracle.AddInputConnection(d.GetOutputPort())
    return oracle


class DemoScene(unittest.TestCase):
    def test_same_counts_as_the_cxx_pipeline(self):
        scene = load_scene(DEMO_SCENE)
        image = sample(scene.oracle)
        counts = counts_of(image.GetPointData().GetArray("Material"))
        self.assertEqual(counts, reference_counts())
        self.assertEqual(set(counts) - {-1}, {1, 2, 3, 4})

    def test_other_file_formats_give_the_same_oracle(self):
        from vtkmodules.vtkIOGeometry import vtkSTLWriter
        from vtkmodules.vtkIOImage import vtkMetaImageWriter

        scene = load_scene(DEMO_SCENE)
        with tempfile.TemporaryDirectory() as tmp:
            stl = vtkSTLWriter()
            stl.SetInputConnection(scene.readers[0].GetOutputPort())
            stl.SetFileName(os.path.join(tmp, "implant.stl"))
            stl.SetFileTypeToBinary()
            stl.Write()
            mha = vtkMetaImageWriter()
            mha.SetInputConnection(scene.readers[1].GetOutputPort())
            mha.SetFileName(os.path.join(tmp, "tibia.mha"))
            mha.SetCompression(True)
            mha.Write()
            description = json.load(open(DEMO_SCENE))
            description["domains"][0]["file"] = os.path.join(tmp, "implant.stl")
            description["domains"][3]["file"] = "tibia.mha"
            description["domains"][3]["array"] = None  # MetaImage names its scalars itself
            description["domains"][3].pop("array")
            other = build_scene(description, base_dir=tmp)
            counts = counts_of(sample(other.oracle).GetPointData().GetArray("Material"))
        self.assertEqual(counts, reference_counts())


class Sampler(unittest.TestCase):
    def test_a_label_map_domain_sampled_alone_prints_nothing(self):
        # the domain's output carries its image's extent keys: the sampler asks for all of it
        # without leaving VTK an extent to complain about ("No update extent has been set")
        code = (
            "import oraclemesh as om\n"
            "from vtkmodules.vtkIOXML import vtkXMLImageDataReader\n"
            "r = vtkXMLImageDataReader(); r.SetFileName(%r)\n"
            "d = om.vtkLabelMapDomain(); d.SetInputConnection(r.GetOutputPort()); d.SetInterpolation(1)\n"
            "s = om.vtkOracleSampler(); s.SetInputConnection(d.GetOutputPort()); s.SetDimensions(8, 8, 8)\n"
            "s.SetBounds(-40, 40, -30, 30, 0, 90); s.Update()\n"
            "print(s.GetOutput().GetPointData().GetArray('Material').GetRange())\n"
        ) % os.path.join(DATA, "demo", "tibia_labels.vti")
        result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stderr.strip(), "")
        self.assertIn("(-1.0, 2.0)", result.stdout)


class DemoData(unittest.TestCase):
    def test_the_generator_reproduces_the_bundled_files(self):
        with tempfile.TemporaryDirectory() as tmp:
            subprocess.run([sys.executable, os.path.join(DATA, "make_demo_scene.py"), tmp], check=True,
                           capture_output=True)
            for name in ("tibia_labels.vti", "implant.vtp", "scene.json"):
                with open(os.path.join(tmp, name), "rb") as new, open(os.path.join(DATA, "demo", name), "rb") as old:
                    self.assertEqual(new.read(), old.read(), f"{name} differs from a fresh run of the generator")

    def test_the_implant_is_a_closed_surface_with_sharp_edges(self):
        from vtkmodules.vtkFiltersCore import vtkFeatureEdges
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

        reader = vtkXMLPolyDataReader()
        reader.SetFileName(os.path.join(DATA, "demo", "implant.vtp"))
        edges = vtkFeatureEdges()
        edges.SetInputConnection(reader.GetOutputPort())
        edges.BoundaryEdgesOn()
        edges.NonManifoldEdgesOn()
        edges.FeatureEdgesOff()
        edges.ManifoldEdgesOff()
        edges.Update()
        self.assertEqual(edges.GetOutput().GetNumberOfCells(), 0)
        edges.BoundaryEdgesOff()
        edges.NonManifoldEdgesOff()
        edges.FeatureEdgesOn()
        edges.SetFeatureAngle(60)
        edges.Update()
        self.assertGreater(edges.GetOutput().GetNumberOfCells(), 100)


class Volumes(unittest.TestCase):
    def test_sphere_and_surface_volumes(self):
        sphere = om.vtkSphereDomain()
        sphere.SetRadius(2.0)
        sphere.SetMaterialId(2)
        volumes = self._volumes(sample(oracle_of(sphere), 120))
        self.assertAlmostEqual(volumes[2], 4 / 3 * math.pi * 8, delta=0.02 * 4 / 3 * math.pi * 8)

    def test_label_map_volume_is_voxel_count_times_voxel_volume(self):
        image = vtkImageData()
        image.SetDimensions(10, 10, 10)
        image.SetSpacing(0.5, 1.0, 2.0)
        labels = vtkFloatArray()  # float storage holding integers is accepted
        labels.SetName("labels")
        for k in range(10):
            for j in range(10):
                for i in range(10):
                    labels.InsertNextValue(7 if 2 <= i < 8 and 3 <= j < 6 and 1 <= k < 5 else 0)
        image.GetPointData().SetScalars(labels)
        domain = om.vtkLabelMapDomain()
        domain.SetInputData(image)
        domain.SetInterpolationToNearest()  # each voxel owns its box (Trilinear rounds the block's edges)
        volumes = self._volumes(sample(oracle_of(domain), 117))  # not commensurate with the voxels
        exact = 6 * 3 * 4 * 0.5 * 1.0 * 2.0
        self.assertAlmostEqual(volumes[7], exact, delta=0.03 * exact)

    @staticmethod
    def _volumes(image):
        fd = image.GetFieldData()
        ids, vols = fd.GetArray("MaterialIds"), fd.GetArray("MaterialVolume")
        return {ids.GetValue(i): vols.GetValue(i) for i in range(ids.GetNumberOfTuples())}


class BadInput(unittest.TestCase):
    def assertFails(self, algorithm, fragment):
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.update(algorithm)
        self.assertIn(fragment, str(ctx.exception))

    def test_open_surface_names_its_open_edges(self):
        source = vtkSphereSource()
        source.Update()
        surface = vtkPolyData()
        surface.DeepCopy(source.GetOutput())
        surface.BuildCells()
        surface.DeleteCell(5)
        surface.RemoveDeletedCells()
        domain = om.vtkSurfaceDomain()
        domain.SetInputData(surface)
        domain.SetMaterialName("implant")
        domain.SetInsideTestToClosed()  # the default, automatic, meshes it with a warning
        oracle = oracle_of(domain)
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.update(oracle)
        text = str(ctx.exception)  # the domain's own error comes first
        self.assertIn("vtkSurfaceDomain 'implant': surface is not closed: 3 open edge(s)", text)
        self.assertRegex(text, r"edge \d+ \([^)]*\) - \d+ \([^)]*\) used by 1 triangle")
        # updating again (the failed domain is not re-run) still points at the domain
        self.assertFails(oracle, "its vtkSurfaceDomain produced no domain")

    def test_quads_are_triangulated(self):
        cube = vtkCubeSource()
        domain = om.vtkSurfaceDomain()
        domain.SetInputConnection(cube.GetOutputPort())
        surface = om.update(domain)
        self.assertTrue(all(surface.GetCell(c).GetNumberOfPoints() == 3 for c in range(surface.GetNumberOfCells())))

    def test_label_maps(self):
        empty = om.vtkLabelMapDomain()
        empty.SetInputData(vtkImageData())
        self.assertFails(empty, "label")
        image = vtkImageData()
        image.SetDimensions(3, 3, 3)
        values = vtkFloatArray()
        values.SetName("density")
        for i in range(27):
            values.InsertNextValue(0.25 * i)
        image.GetPointData().SetScalars(values)
        fractional = om.vtkLabelMapDomain()
        fractional.SetInputData(image)
        self.assertFails(fractional, "label map is not integer: value 0.25 at point 1")

    def test_spheres(self):
        for radius in (0.0, -1.0, float("nan")):
            s = om.vtkSphereDomain()
            s.SetRadius(radius)
            self.assertFails(s, "sphere radius must be positive")
        s = om.vtkSphereDomain()
        s.SetCenter(float("nan"), 0, 0)
        self.assertFails(s, "NaN")

    def test_oracle_inputs(self):
        self.assertFails(om.vtkHierarchicalOracle(), "no domains connected")
        source = vtkSphereSource()
        plain = oracle_of(source)
        self.assertFails(plain, "input 0 (vtkPolyData) is not an OracleMesh domain")

    def test_scene_validation_lists_every_problem_with_its_json_path(self):
        description = {"domains": [
            {"type": "sphere", "center": [0, 0], "radius": -2, "material": 1},
            {"type": "torus"},
            {"type": "surface", "material": 2},
            {"type": "labelmap", "file": "missing.vti"},
            {"type": "labelmap", "file": os.path.join(os.path.dirname(DEMO_SCENE), "tibia_labels.vti"),
             "interpolation": "cubic"},
        ]}
        with self.assertRaises(om.OracleMeshError) as ctx:
            build_scene(description, base_dir=tempfile.gettempdir())
        text = str(ctx.exception)
        for fragment in ("$.domains[0].center: must be a list of 3", "$.domains[0].radius: must be a positive",
                         "$.domains[1].type: must be one of", "$.domains[2].file: missing",
                         "$.domains[3].file:", "file not found",
                         "$.domains[4].interpolation: must be 'smooth', 'trilinear' or 'nearest'"):
            self.assertIn(fragment, text)
        with self.assertRaises(om.OracleMeshError):
            build_scene({"domains": []})


class Tetrahedralizer(unittest.TestCase):
    """The mesher through its VTK adapter (the core is tested by GoogleTest)."""

    def mesh(self, oracle, lines=None, strategy="None", **criteria):
        t = om.vtkFeaturePreservingTetrahedralizer()
        t.SetInputConnection(0, oracle.GetOutputPort())
        if lines is not None:
            t.SetInputData(1, lines)
        getattr(t, "SetFeatureStrategyTo" + strategy)()
        for name, value in criteria.items():
            getattr(t, "Set" + name)(value)
        return t, om.update(t)

    def test_volumes_materials_and_outputs(self):
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter

        ball = om.vtkSphereDomain()
        ball.SetRadius(1.0)
        ball.SetMaterialId(2)
        t, grid = self.mesh(oracle_of(ball), CellSize=0.2, FacetSize=0.2, FacetDistance=0.01)
        self.assertGreater(grid.GetNumberOfCells(), 100)
        self.assertEqual(set(vtk_to_numpy(grid.GetCellData().GetArray("Material"))), {2})
        sizes = vtkCellSizeFilter()
        sizes.SetInputData(grid)
        sizes.Update()
        volumes = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
        self.assertTrue((volumes > 0).all(), "every tetrahedron is positively oriented")
        self.assertAlmostEqual(volumes.sum(), 4 / 3 * math.pi, delta=0.02 * 4 / 3 * math.pi)
        angles = vtk_to_numpy(grid.GetCellData().GetArray("MinDihedralAngle"))
        self.assertGreater(angles.min(), 5.0)
        interfaces = t.GetOutputDataObject(1)
        self.assertGreater(interfaces.GetNumberOfCells(), 50)
        sides = vtk_to_numpy(interfaces.GetCellData().GetArray("Materials"))
        self.assertTrue(((sides == [-1, 2]) | (sides == [2, -1])).all(axis=1).all())
        names = grid.GetFieldData().GetAbstractArray("StatisticNames")
        self.assertIn("min_dihedral_angle", [names.GetValue(i) for i in range(names.GetNumberOfValues())])

    def test_domain_criteria_and_their_override(self):
        from vtkmodules.util.numpy_support import vtk_to_numpy

        def largest_circumradius(grid, material):
            materials = vtk_to_numpy(grid.GetCellData().GetArray("Material"))
            pts = vtk_to_numpy(grid.GetPoints().GetData())
            cells = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)[materials == material]
            a, b, c, d = (pts[cells[:, k]] for k in range(4))
            # circumcentre x of each tetrahedron: 2 (p_k - a) . x = |p_k|^2 - |a|^2, k = b, c, d
            m = 2 * np.stack([b - a, c - a, d - a], axis=1)
            rhs = np.stack([(q * q).sum(1) - (a * a).sum(1) for q in (b, c, d)], axis=1)
            x = np.linalg.solve(m, rhs[..., None])[..., 0]
            return np.linalg.norm(x - a, axis=1).max()

        inner, outer = om.vtkSphereDomain(), om.vtkSphereDomain()
        inner.SetRadius(1.0); inner.SetMaterialId(2); inner.SetCellSize(0.25)   # the domain's own bound
        outer.SetRadius(2.0); outer.SetMaterialId(1)
        oracle = om.vtkHierarchicalOracle()
        oracle.AddInputConnection(inner.GetOutputPort()); oracle.AddInputConnection(outer.GetOutputPort())
        t, grid = self.mesh(oracle, None, "None", CellSize=0.8, Perturb=False, Exude=False)
        self.assertLessEqual(largest_circumradius(grid, 2), 0.25 * (1 + 1e-9))
        self.assertGreater(largest_circumradius(grid, 1), 0.4)  # the global bound, not the ball's
        t.SetMaterialCriteria(2, -1, -1, -1, 0.5, -1, -1)  # the tetrahedralizer's value wins
        grid = om.update(t)
        radius = largest_circumradius(grid, 2)
        self.assertLessEqual(radius, 0.5 * (1 + 1e-9))
        self.assertGreater(radius, 0.25)

    def test_protecting_balls_keep_the_cube_edges(self):
        from vtkmodules.vtkFiltersCore import vtkFeatureEdges, vtkTriangleFilter
        from vtkmodules.util.numpy_support import vtk_to_numpy

        cube = vtkCubeSource()
        tri = vtkTriangleFilter()
        tri.SetInputConnection(cube.GetOutputPort())
        clean = __import__("vtkmodules.vtkFiltersCore", fromlist=["vtkCleanPolyData"]).vtkCleanPolyData()
        clean.SetInputConnection(tri.GetOutputPort())
        surface = om.vtkSurfaceDomain()
        surface.SetInputConnection(clean.GetOutputPort())
        edges = vtkFeatureEdges()
        edges.SetInputConnection(clean.GetOutputPort())
        edges.BoundaryEdgesOff()
        edges.NonManifoldEdgesOff()
        edges.ManifoldEdgesOff()
        edges.Update()
        self.assertEqual(edges.GetOutput().GetNumberOfCells(), 12)
        t, grid = self.mesh(oracle_of(surface), edges.GetOutput(), "ProtectingBalls",
                            CellSize=0.2, FacetSize=0.2, FacetDistance=0.01)
        present = vtk_to_numpy(t.GetOutputDataObject(2).GetCellData().GetArray("Present"))
        self.assertTrue(len(present) >= 12 and present.all(), "every cube edge is a chain of mesh edges")

    def test_bad_input(self):
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray

        self.assertRaises(om.OracleMeshError, self.mesh, om.vtkHierarchicalOracle())
        ball = om.vtkSphereDomain()
        lines = vtkPolyData()
        points = vtkPoints()
        points.InsertNextPoint(0, 0, 0)
        points.InsertNextPoint(float("nan"), 0, 0)
        cells = vtkCellArray()
        cells.InsertNextCell(2, (0, 1))
        lines.SetPoints(points)
        lines.SetLines(cells)
        with self.assertRaises(om.OracleMeshError) as ctx:
            self.mesh(oracle_of(ball), lines, "ProtectingBalls", CellSize=0.3)
        self.assertIn("feature lines (input port 1): point 1", str(ctx.exception))
        self.assertIn("NaN", str(ctx.exception))


class CommandLine(unittest.TestCase):
    def test_mesh_writes_the_demo_mesh_and_its_report(self):
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "demo.vtu")
            result = subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", DEMO_SCENE, "-o", out],
                                    capture_output=True, text=True, check=False)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn("feature lines present as mesh edges: 100.0%", result.stdout)
            reader = vtkXMLUnstructuredGridReader()
            reader.SetFileName(out)
            reader.Update()
            materials = set(vtk_to_numpy(reader.GetOutput().GetCellData().GetArray("Material")).tolist())
            self.assertEqual(materials, {1, 2, 3, 4})
            # the paper's quality after optimisation (8.72 degrees), with every feature line kept
            angles = vtk_to_numpy(reader.GetOutput().GetCellData().GetArray("MinDihedralAngle"))
            self.assertGreater(angles.min(), 8.72)


    def test_sample_writes_an_image_and_a_report(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "oracle.vti")
            result = subprocess.run([sys.executable, "-m", "oraclemesh", "sample", DEMO_SCENE, "-o", out,
                                     "--dims", "40", "40", "40"], capture_output=True, text=True, check=False)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertTrue(os.path.getsize(out) > 0)
            for name in ("cortical bone", "cancellous bone", "implant", "screw"):
                self.assertIn(name, result.stdout)
            bad = subprocess.run([sys.executable, "-m", "oraclemesh", "sample", os.path.join(tmp, "none.json")],
                                 capture_output=True, text=True, check=False)
            self.assertEqual(bad.returncode, 2)
            self.assertIn("scene file not found", bad.stderr)


if __name__ == "__main__":
    unittest.main()
