# SPDX-License-Identifier: GPL-3.0-or-later
"""The slips a new user makes, caught at every door with a message naming them (the command line's
and the scene's in test_bad_inputs.py): the VTK filters' property checks, the mesh files the report
is given, the defaults' shape, and what pvpython prints (warnings without VTK's object addresses,
the first error of a failed pipeline, a label map too big refused before its reader allocates it)."""
import json
import os
import re
import subprocess
import sys
import tempfile
import unittest

from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

import oraclemesh as om
from oraclemesh.defaults import CRITERIA_KEYS, MESH_PROPERTIES, mesh_defaults

COMMAND = os.environ.get("ORACLEMESH_COMMAND")
PVPYTHON = os.environ.get("ORACLEMESH_PVPYTHON")
PLUGIN = os.environ.get("ORACLEMESH_PLUGIN")
# a C++ object's address as VTK prints it (not a temporary folder's name that holds "0x")
OBJECT_ADDRESS = re.compile(r"0x[0-9a-fA-F]{6,}")
HIDDEN = {"domains": [{"name": "big", "type": "sphere", "center": [0, 0, 0], "radius": 5, "material": 1},
                      {"name": "small", "type": "sphere", "center": [0, 0, 0], "radius": 2, "material": 2}],
          "mesh": {"criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.5}}}


def run(*args):
    prefix = [COMMAND] if COMMAND else [sys.executable, "-m", "oraclemesh"]
    return subprocess.run(prefix + [str(a) for a in args], capture_output=True, text=True, timeout=300)


def ball_oracle(keep):
    ball = om.vtkSphereDomain()
    ball.SetRadius(2)
    oracle = om.vtkHierarchicalOracle()
    oracle.AddInputConnection(ball.GetOutputPort())
    keep += [ball, oracle]
    return oracle


class Filters(unittest.TestCase):
    """Bad values at the VTK filters: errors naming them, before anything reads them."""

    def setUp(self):
        self.keep = []

    def test_a_feature_line_naming_a_point_past_the_end_is_refused(self):
        points = vtkPoints()
        for p in ((0, 0, 0), (1, 0, 0), (1, 1, 0)):
            points.InsertNextPoint(p)
        lines = vtkCellArray()
        lines.InsertNextCell(2, [0, 1])
        lines.InsertNextCell(2, [1, 7])  # 7: past the end of 3 points
        polydata = vtkPolyData()
        polydata.SetPoints(points)
        polydata.SetLines(lines)
        mesher = om.vtkFeaturePreservingTetrahedralizer()
        mesher.SetInputConnection(0, ball_oracle(self.keep).GetOutputPort())
        mesher.SetInputData(1, polydata)
        mesher.SetCellSize(1)
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.update(mesher)
        self.assertIn("feature lines (input port 1): line 1 names point 7, but the lines have 3 points",
                      str(ctx.exception))

    def test_negative_criteria_are_errors_and_minus_one_is_the_default(self):
        mesher = om.vtkFeaturePreservingTetrahedralizer()
        mesher.SetInputConnection(0, ball_oracle(self.keep).GetOutputPort())
        mesher.SetCellSize(-2)
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.update(mesher)
        self.assertIn("CellSize (cell_size) is -2: it cannot be negative", str(ctx.exception))
        mesher.SetCellSize(1)
        mesher.SetMaterialCriteria(1, -1, -1, -3, -1, -1, -1)
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.update(mesher)
        self.assertIn("material criteria for material 1: FacetDistance (facet_distance) is -3", str(ctx.exception))
        mesher.SetMaterialCriteria(1, -1, -1, -1, -1, -1, -1)  # every criterion "not set"
        mesher.SetFacetAngle(-1)  # the default
        self.assertGreater(om.update(mesher).GetNumberOfCells(), 0)

    def test_inverted_sampler_bounds_are_refused(self):
        sampler = om.vtkOracleSampler()
        sampler.SetInputConnection(ball_oracle(self.keep).GetOutputPort())
        sampler.SetDimensions(8, 8, 8)
        self.assertGreater(om.update(sampler).GetNumberOfPoints(), 0)  # the default: the oracle's bounds
        sampler.SetBounds(-2, 2, 3, -3, -2, 2)
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.update(sampler)
        self.assertIn("Bounds are inverted on y: 3 > -3", str(ctx.exception))

    def test_a_label_map_too_big_is_refused_before_its_reader_allocates_it(self):
        from vtkmodules.vtkIOImage import vtkMetaImageReader

        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "huge.mha")
            with open(path, "w") as f:
                f.write("ObjectType = Image\nNDims = 3\nDimSize = 100000 100000 100000\n"
                        "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
            reader = vtkMetaImageReader()  # VTK's own: it would allocate 1e15 bytes and abort
            reader.SetFileName(path)
            domain = om.vtkLabelMapDomain()
            domain.SetDomainName("tibia")
            domain.SetInputConnection(reader.GetOutputPort())
            with self.assertRaises(om.OracleMeshError) as ctx:
                om.update(domain)
            self.assertIn("vtkLabelMapDomain 'tibia': its input image of 100000 x 100000 x 100000 voxels "
                          "(refused before it is read)", str(ctx.exception))
            self.assertIn("would need", str(ctx.exception))


class Defaults(unittest.TestCase):
    def test_mesh_defaults_are_a_scene_mesh_block_that_changes_nothing(self):
        defaults = mesh_defaults()
        self.assertEqual(defaults["features"], {"use": "Given", "feature_angle": 60.0, "resample": False})
        self.assertNotIn("resample_feature_lines", defaults)
        scene = dict(HIDDEN, mesh=defaults)
        given = om.meshing.mesher_for(om.scene.build_scene(scene))
        fresh = om.vtkFeaturePreservingTetrahedralizer()
        for prop in list(CRITERIA_KEYS.values()) + list(MESH_PROPERTIES.values()) + ["CreaseAngle", "Features"]:
            self.assertEqual(getattr(given, "Get" + prop)(), getattr(fresh, "Get" + prop)(), prop)


class Files(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.scene = os.path.join(cls.tmp.name, "hidden.json")
        with open(cls.scene, "w") as f:
            json.dump(HIDDEN, f)
        cls.vtu, cls.inp = (os.path.join(cls.tmp.name, name) for name in ("out.vtu", "out.inp"))
        cls.section = os.path.join(cls.tmp.name, "section.png")
        cls.mesh_run = run("mesh", cls.scene, "-o", cls.vtu, "-o", cls.inp, "--section", cls.section)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_the_section_prints_no_numpy_warnings(self):
        self.assertEqual(self.mesh_run.returncode, 0, self.mesh_run.stderr)
        self.assertTrue(os.path.isfile(self.section))
        self.assertNotIn("RuntimeWarning", self.mesh_run.stderr)

    def test_report_says_what_a_surfaces_file_is(self):
        result = run("report", os.path.join(self.tmp.name, "out_surfaces.vtu"))
        self.assertEqual(result.returncode, 2)
        self.assertIn("out_surfaces.vtu: holds", result.stderr)
        self.assertIn("no tetrahedra: the boundary and interface sets that 'oraclemesh mesh' writes beside a mesh; "
                      "report on the mesh itself, out.vtu", result.stderr)

    def test_each_format_gets_its_own_histogram(self):
        for path, picture in ((self.vtu, "out_vtu_dihedral.png"), (self.inp, "out_inp_dihedral.png")):
            result = run("report", path)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn(f"wrote {os.path.join(self.tmp.name, picture)}", result.stdout)
            self.assertTrue(os.path.isfile(os.path.join(self.tmp.name, picture)))

    def test_the_command_line_prints_each_warning_once_without_addresses(self):
        self.assertEqual(self.mesh_run.stdout.count("domain 1 'small' is hidden"), 1, self.mesh_run.stdout)
        self.assertNotRegex(self.mesh_run.stdout + self.mesh_run.stderr, OBJECT_ADDRESS)

    def test_sample_prints_the_domains_warnings_once_without_addresses(self):
        result = run("sample", self.scene, "--dims", 16, 16, 16)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stderr.count("oraclemesh: warning: domain 1 'small' is hidden"), 1, result.stderr)
        self.assertNotRegex(result.stderr, OBJECT_ADDRESS)

    def test_no_set_of_files_half_written(self):
        result = om.mesh(self.scene)
        blocker = os.path.join(self.tmp.name, "blocker")
        with open(blocker, "w") as f:
            f.write("a file where a folder is needed")
        first = os.path.join(self.tmp.name, "first.vtu")
        with self.assertRaises(om.OracleMeshError):
            result.save(first, os.path.join(blocker, "second.inp"))
        self.assertFalse(os.path.exists(first))
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "first_surfaces.vtu")))


def noisy_box(path, seed=7):
    """A scanned CAD part: a 20 x 10 x 8 box of 12,288 triangles with seeded noise of 0.03 mm, whose
    sharp edges at 5 degrees are thousands of short segments."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkTriangleFilter
    from vtkmodules.vtkFiltersModeling import vtkLinearSubdivisionFilter
    from vtkmodules.vtkFiltersSources import vtkCubeSource
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    cube = vtkCubeSource()
    cube.SetXLength(20)
    cube.SetYLength(10)
    cube.SetZLength(8)
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(cube.GetOutputPort())
    welded = vtkCleanPolyData()
    welded.SetInputConnection(triangles.GetOutputPort())
    finer = vtkLinearSubdivisionFilter()
    finer.SetInputConnection(welded.GetOutputPort())
    finer.SetNumberOfSubdivisions(5)
    finer.Update()
    surface = finer.GetOutput()
    points = vtk_to_numpy(surface.GetPoints().GetData()).copy()
    points += np.random.default_rng(seed).normal(scale=0.03, size=points.shape)
    surface.GetPoints().SetData(numpy_to_vtk(points, deep=True))
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(surface)
    writer.Write()
    return path


class DenseFeatureLines(unittest.TestCase):
    """A noisy CAD part whose sharp edges at 5 degrees are ~12,000 short segments: not resampled, it
    ends at the time limit with a message naming the dense lines and the fix; resampled (the
    default for a surface's sharp edges), it meshes in seconds."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        part = noisy_box(os.path.join(cls.tmp.name, "part.vtp"))
        cls.scene = {"domains": [{"name": "part", "type": "surface", "file": part, "material": 1}],
                     "mesh": {"criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.2},
                              "features": {"from_surface": "part", "feature_angle": 5}}}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def write(self, name, **features):
        scene = json.loads(json.dumps(self.scene))
        scene["mesh"]["features"].update(features)
        path = os.path.join(self.tmp.name, name + ".json")
        with open(path, "w") as f:
            json.dump(scene, f)
        return path

    def test_unresampled_ends_within_the_limit_naming_the_dense_lines(self):
        import time

        started = time.monotonic()
        result = run("mesh", self.write("dense", resample=False), "-o", os.path.join(self.tmp.name, "d.vtu"),
                     "--time-limit", 5)
        elapsed = time.monotonic() - started
        self.assertEqual(result.returncode, 3, result.stderr)
        self.assertIn("time limit of 5 s reached in", result.stderr)
        self.assertIn("the feature lines are dense", result.stderr)
        self.assertIn("features.resample", result.stderr)  # the scene's spelling of the fix
        self.assertLess(elapsed, 5 + 25)  # the limit, plus Python's start and the surface's checks
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "d.vtu")))

    def test_resampled_meshes_with_every_line_kept(self):
        out = os.path.join(self.tmp.name, "r.vtu")
        result = run("mesh", self.write("resampled"), "-o", out, "--time-limit", 120)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("feature lines simplified", result.stdout)
        self.assertIn("feature lines present as mesh edges: 100.0%", result.stdout)
        self.assertIn("validity: no defects", result.stdout)


@unittest.skipUnless(PVPYTHON and PLUGIN, "pvpython or the plugin not given")
class PvPython(unittest.TestCase):
    """What a pvpython user sees."""

    def pvpython(self, script, *args):
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "script.py")
            with open(path, "w") as f:
                f.write(script)
            return subprocess.run([PVPYTHON, path, PLUGIN, tmp] + list(args), capture_output=True, text=True,
                                  timeout=300)

    def test_warnings_have_no_object_addresses(self):
        script = f"""
import sys
import oraclemesh as om
result = om.mesh({HIDDEN!r})
print("result warnings", len(result.warnings))
mesher = om.meshing.mesher_for(om.scene.build_scene({HIDDEN!r}))
om.update(mesher)
"""
        result = self.pvpython(script)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("result warnings 2", result.stdout)
        output = result.stdout + result.stderr
        self.assertNotRegex(output, OBJECT_ADDRESS)
        self.assertNotIn("vtkFeaturePreservingTetrahedralizer (", output)
        # om.mesh keeps its warnings in the result; a plain update prints them once each, cleanly
        self.assertEqual(result.stderr.count("oraclemesh: warning: domain 1 'small' is hidden"), 1, result.stderr)

    def test_a_broken_input_reports_its_own_error_not_a_follow_up(self):
        script = """
import os, sys
from paraview import servermanager, simple as pv
pv.LoadPlugin(sys.argv[1], remote=False)
path = os.path.join(sys.argv[2], "broken.vtp")
with open(path, "wb") as f:
    f.write(b"not xml at all")
surface = pv.SurfaceDomain(Input=pv.XMLPolyDataReader(FileName=path))
oracle = pv.HierarchicalOracle(Input=[surface])
mesher = pv.FeaturePreservingTetrahedralizer(Input=oracle)
oracle.UpdatePipeline()  # ParaView updates each filter on its own (Apply, Fetch)
mesher.UpdatePipeline()
"""
        output = self.pvpython(script).stderr
        self.assertIn("Error parsing", output)  # the reader's own error comes first
        self.assertLess(output.index("Error parsing"), output.index("is empty"))
        # the follow-ups say that something before failed, not something misleading
        self.assertNotIn("is not an OracleMesh domain", output)
        self.assertNotIn("the oracle has no domains", output)
        self.assertIn("is empty: the filter before it failed or produced nothing", output)
        self.assertIn("the oracle is empty: vtkHierarchicalOracle or a filter before it failed", output)

    def test_the_label_map_reader_names_the_file_and_the_problem(self):
        script = """
import os, sys
from paraview import servermanager, simple as pv
pv.LoadPlugin(sys.argv[1], remote=False)
for name, text in (("short.nrrd", b"NRRD0004\\ntype: uchar\\ndimension: 3\\nsizes: 10 10 10\\nencoding: raw\\n\\n" + bytes(100)),
                   ("huge.mha", b"ObjectType = Image\\nNDims = 3\\nDimSize = 100000 100000 100000\\n"
                                b"ElementType = MET_UCHAR\\nElementDataFile = LOCAL\\n")):
    path = os.path.join(sys.argv[2], name)
    with open(path, "wb") as f:
        f.write(text)
    servermanager.Fetch(pv.OracleMeshLabelMapReader(FileName=path))
print("ended")
"""
        result = self.pvpython(script)
        self.assertIn("ended", result.stdout)  # no abort
        self.assertIn("short.nrrd: the file is truncated or too long: 100 values for sizes 10 x 10 x 10",
                      result.stderr)
        self.assertIn("huge.mha: DimSize 100000 x 100000 x 100000", result.stderr)
        self.assertNotIn("ProcessRequest", result.stderr)


if __name__ == "__main__":
    unittest.main()
