# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 13: feature lines found where the inputs meet (vtkOracleFeatureLines) and the mesher's
Features option at the Python and scene doors."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import oraclemesh as om
from oraclemesh import fieldkeys
from oraclemesh.defaults import FEATURE_SOURCES, mesh_defaults
from oraclemesh.scene import build_scene

CENTER, RADIUS, CUT_AT = (0.1, 0.2, 0.3), 1.0, 0.65


def rim_scene(**mesh):
    """A unit ball cut above z = 0.65: its rim is a circle."""
    return {"domains": [{"name": "cut", "type": "plane", "origin": [0, 0, CUT_AT], "normal": [0, 0, -1], "cut": True},
                        {"name": "ball", "type": "sphere", "center": list(CENTER), "radius": RADIUS, "material": 1}],
            "mesh": dict({"criteria": {"cell_size": 0.3, "facet_size": 0.3, "facet_distance": 0.02, "edge_size": 0.2},
                          "seed": 1}, **mesh)}


class FeatureLinesFilter(unittest.TestCase):
    def test_the_cut_rim_is_one_closed_polyline_on_the_circle(self):
        scene = build_scene(rim_scene())
        lines = om.vtkOracleFeatureLines()
        lines.SetInputConnection(scene.oracle.GetOutputPort())
        lines.SetMaximumSegmentLength(0.15)
        out = om.update(lines)
        self.assertEqual(out.GetNumberOfLines(), 1)
        ids = out.GetCell(0).GetPointIds()
        self.assertEqual(ids.GetId(0), ids.GetId(ids.GetNumberOfIds() - 1))  # closed
        self.assertEqual(out.GetCellData().GetArray("Materials").GetTuple(0), (-1, 1, -2, -2))
        self.assertEqual(out.GetCellData().GetArray("Triple").GetValue(0), 0)
        for i in range(out.GetNumberOfPoints()):
            p = out.GetPoint(i)
            self.assertAlmostEqual(p[2], CUT_AT, delta=1e-6)
            self.assertAlmostEqual(math.dist(p, CENTER), RADIUS, delta=1e-6)
        self.assertEqual(out.GetFieldData().GetAbstractArray("Warnings").GetNumberOfValues(), 0)

    def test_a_box_shows_its_twelve_edges_as_creases(self):
        # a box's edges are creases of the box alone: the scene's box through the ParaView source
        scene = build_scene({"domains": [{"name": "block", "type": "box", "bounds": [0, 2, 0, 1, 0, 0.5],
                                          "material": 4}]})
        lines = om.vtkOracleFeatureLines()
        lines.SetInputConnection(scene.oracle.GetOutputPort())
        lines.SetMaximumSegmentLength(0.4)
        out = om.update(lines)
        self.assertEqual(out.GetNumberOfLines(), 12)
        for c in range(12):
            self.assertEqual(out.GetCellData().GetArray("Crease").GetValue(c), 1)
            self.assertEqual(out.GetCellData().GetArray("Materials").GetTuple(c), (-1, 4, -2, -2))
        on_edge = lambda p: sum(min(abs(x), abs(x - hi)) < 1e-9 for x, hi in zip(p, (2, 1, 0.5))) >= 2  # noqa: E731
        for i in range(out.GetNumberOfPoints()):
            self.assertTrue(on_edge(out.GetPoint(i)), out.GetPoint(i))

    def test_no_input_is_an_error(self):
        with self.assertRaises(om.OracleMeshError):
            om.update(om.vtkOracleFeatureLines())


class FeaturesOption(unittest.TestCase):
    def test_the_default_comes_from_the_cxx(self):
        self.assertEqual(mesh_defaults()["features"]["use"], FEATURE_SOURCES[om.vtkFeaturePreservingTetrahedralizer().GetFeatures()])
        self.assertEqual(mesh_defaults()["features"]["use"], "Given")  # the meshes of before (FeatureSelection.h)

    def test_automatic_features_are_mesh_edges_and_given_alone_has_none(self):
        automatic = om.mesh(rim_scene(features="Automatic"))
        segments = automatic.grid  # the mesh; the kept lines are the mesher's port 2, counted in field data
        count = segments.GetFieldData().GetArray("FeatureSegments").GetValue(0)
        self.assertGreater(count, 20)  # the rim, cut at the mesh vertices on it
        self.assertEqual(automatic.statistics.get("validity.missing_segment_pieces", 0), 0)
        given = om.mesh(rim_scene(features={"use": "Given"}))
        self.assertEqual(given.grid.GetFieldData().GetArray("FeatureSegments").GetValue(0), 0)

    def test_found_pieces_lie_on_interface_triangles_of_their_materials(self):
        """A piece of a found curve that is a mesh edge lies on the interfaces it bounds: a rim on a
        triangle of its two materials, a triple line on triangles of two of its interfaces (an edge
        inside one material beside the curve would not do)."""
        lid = {"domains": [{"name": "lid", "type": "sphere", "center": [0, 0, 1.2], "radius": 0.5, "material": 2},
                           {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": 1}],
               "mesh": rim_scene()["mesh"]}
        for scene in (rim_scene(features="Automatic"), dict(lid, mesh=dict(lid["mesh"], features="Automatic"))):
            mesher = om.meshing.mesher_for(om.meshing.as_scene(scene))
            om.update(mesher)
            interfaces, lines = mesher.GetOutputDataObject(1), mesher.GetOutputDataObject(2)
            pairs_of_edge = {}
            tri_materials = interfaces.GetCellData().GetArray(fieldkeys.MATERIALS)
            for c in range(interfaces.GetNumberOfCells()):
                ids = [interfaces.GetCell(c).GetPointId(k) for k in range(3)]
                pts = [tuple(interfaces.GetPoint(i)) for i in ids]
                pair = tuple(sorted(int(v) for v in tri_materials.GetTuple(c)))
                for k in range(3):
                    pairs_of_edge.setdefault(frozenset((pts[k], pts[(k + 1) % 3])), set()).add(pair)
            present = lines.GetCellData().GetArray("Present")
            origin = lines.GetCellData().GetArray(fieldkeys.ORIGIN)
            materials = lines.GetCellData().GetArray(fieldkeys.MATERIALS)
            checked = 0
            for c in range(lines.GetNumberOfCells()):
                if origin.GetValue(c) != 1 or not present.GetValue(c):
                    continue
                mats = [int(v) for v in materials.GetTuple(c) if v != -2]
                edge = frozenset(tuple(lines.GetPoint(lines.GetCell(c).GetPointId(k))) for k in (0, 1))
                own = {p for p in pairs_of_edge.get(edge, set()) if set(p) <= set(mats)}
                self.assertGreaterEqual(len(own), 2 if len(mats) >= 3 else 1, (mats, sorted(edge)))
                checked += 1
            self.assertGreater(checked, 10)

    def test_the_command_line_keeps_the_rim_with_features_automatic(self):
        with tempfile.TemporaryDirectory() as folder:
            scene = os.path.join(folder, "scene.json")
            with open(scene, "w") as f:
                json.dump(rim_scene(), f)
            out = subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", scene, "-o", os.path.join(folder, "m.vtu"),
                                  "--features", "Automatic"], capture_output=True, text=True, timeout=100)
            self.assertEqual(out.returncode, 0, out.stderr)
            self.assertIn("feature lines present as mesh edges: 100.0%", out.stdout)
            bad = subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", scene, "-o", os.path.join(folder, "m.vtu"),
                                  "--features", "Sometimes"], capture_output=True, text=True, timeout=100)
            self.assertNotEqual(bad.returncode, 0)
            self.assertIn("--features", bad.stderr)

    def _mesher(self, features, time_limit=0):
        from vtkmodules.vtkFiltersSources import vtkLineSource
        scene = build_scene(rim_scene())
        line = vtkLineSource()  # a given line inside the ball, across no curve
        line.SetPoint1(0.1, 0.2, -0.5)
        line.SetPoint2(0.1, 0.2, 0.2)
        mesher = om.vtkFeaturePreservingTetrahedralizer()
        mesher.SetInputConnection(0, scene.oracle.GetOutputPort())
        mesher.SetInputConnection(1, line.GetOutputPort())
        mesher.SetCellSize(0.3)
        mesher.SetFacetSize(0.3)
        mesher.SetFacetDistance(0.02)
        mesher.SetEdgeSize(0.2)
        mesher.SetSeed(1)
        mesher.SetFeatures(FEATURE_SOURCES.index(features))
        mesher.SetTimeLimit(time_limit)
        return scene, line, mesher

    def test_port_2_marks_the_found_lines_and_their_materials(self):
        keep = self._mesher("Both")
        mesher = keep[2]
        om.update(mesher)
        lines = mesher.GetOutputDataObject(2)
        origin = lines.GetCellData().GetArray(fieldkeys.ORIGIN)
        materials = lines.GetCellData().GetArray(fieldkeys.MATERIALS)
        self.assertEqual(lines.GetNumberOfCells(), origin.GetNumberOfTuples())
        seen = set()
        for c in range(lines.GetNumberOfCells()):
            a, b = (lines.GetPoint(lines.GetCell(c).GetPointId(k)) for k in (0, 1))
            seen.add(origin.GetValue(c))
            if origin.GetValue(c) == 1:  # on the rim
                self.assertAlmostEqual(a[2], CUT_AT, delta=1e-6)
                self.assertEqual(materials.GetTuple(c), (-1, 1, -2, -2))
            else:  # on the given line
                self.assertAlmostEqual(math.hypot(a[0] - 0.1, a[1] - 0.2), 0, delta=1e-6)
                self.assertEqual(materials.GetTuple(c), (-2, -2, -2, -2))
        self.assertEqual(seen, {0, 1})

    def test_the_search_runs_under_the_time_limit(self):
        keep = self._mesher("Automatic", time_limit=1e-4)
        with self.assertRaisesRegex(om.OracleMeshError, "time limit .* reached in feature line search"):
            om.update(keep[2])

    def test_a_bad_value_is_named(self):
        with self.assertRaisesRegex(om.OracleMeshError, r"\$\.mesh\.features\.use: must be one of None, Given"):
            build_scene(rim_scene(features={"use": "sometimes"}))


CHAMFER = 0.25
CHAMFER_EDGES = (((1, 1 - CHAMFER, 0), (1, 1 - CHAMFER, 1)), ((1 - CHAMFER, 1, 0), (1 - CHAMFER, 1, 1)))


def chamfered_cube(folder):
    """The unit cube with its edge x = y = 1 chamfered (as the core test's): 90-degree edges, and the
    chamfer's two at 135 degrees (normals 45 apart). Written as a .vtp; returns its path."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    ring = [(0, 0), (1, 0), (1, 1 - CHAMFER), (1 - CHAMFER, 1), (0, 1)]  # counter-clockwise from +z
    points = vtkPoints()
    for z in (0, 1):
        for x, y in ring:
            points.InsertNextPoint(x, y, z)
    triangles = vtkCellArray()
    for i in range(5):
        j = (i + 1) % 5
        triangles.InsertNextCell(3, (i, j, j + 5))
        triangles.InsertNextCell(3, (i, j + 5, i + 5))
    for i in range(1, 4):
        triangles.InsertNextCell(3, (0, i + 1, i))
        triangles.InsertNextCell(3, (5, 5 + i, 6 + i))
    surface = vtkPolyData()
    surface.SetPoints(points)
    surface.SetPolys(triangles)
    path = os.path.join(folder, "chamfered_cube.vtp")
    writer = vtkXMLPolyDataWriter()
    writer.SetInputData(surface)
    writer.SetFileName(path)
    writer.Write()
    return path


def on_segment(p, a, b):
    """Distance from p to the segment ab."""
    ab = [y - x for x, y in zip(a, b)]
    t = max(0.0, min(1.0, sum((q - x) * d for q, x, d in zip(p, a, ab)) / sum(d * d for d in ab)))
    return math.dist(p, [x + t * d for x, d in zip(a, ab)])


class CreaseAngleOption(unittest.TestCase):
    """The crease angle (scene mesh.features.feature_angle, CreaseAngle on the filters) selects which
    edges of a surface Automatic keeps: a chamfered cube's 135-degree edges only below 45 degrees."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()
        cls.surface = chamfered_cube(cls.tmp)

    @classmethod
    def tearDownClass(cls):
        import shutil
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def scene(self, **features):
        return {"domains": [{"name": "part", "type": "surface", "file": self.surface, "material": 1}],
                "mesh": {"criteria": {"cell_size": 0.4, "facet_size": 0.4, "facet_distance": 0.05, "edge_size": 0.3},
                         "features": dict({"use": "Automatic"}, **features), "seed": 1}}

    def kept_lines(self, description, **overrides):
        """The mesher's port 2 (the lines as they stand in the mesh) after meshing the scene."""
        from oraclemesh.meshing import mesher_for
        scene = build_scene(description)
        mesher = mesher_for(scene, **overrides)
        om.update(mesher)
        return mesher.GetOutputDataObject(2)

    def chamfer_segments(self, lines):
        """How many of the lines' segments lie on the chamfer's edges; every segment is an automatic
        one on an edge of the part and present in the mesh."""
        count = 0
        for c in range(lines.GetNumberOfCells()):
            self.assertEqual(lines.GetCellData().GetArray(fieldkeys.ORIGIN).GetValue(c), 1)
            self.assertEqual(lines.GetCellData().GetArray(fieldkeys.PRESENT).GetValue(c), 1)
            a, b = (lines.GetPoint(lines.GetCell(c).GetPointId(k)) for k in (0, 1))
            mid = [0.5 * (x + y) for x, y in zip(a, b)]
            count += any(on_segment(mid, *e) < 1e-9 for e in CHAMFER_EDGES)
        return count

    def test_the_default_is_the_cxx_one_at_every_door(self):
        self.assertEqual(mesh_defaults()["features"]["feature_angle"], om.vtkFeaturePreservingTetrahedralizer().GetCreaseAngle())
        self.assertEqual(mesh_defaults()["features"]["feature_angle"], om.vtkOracleFeatureLines().GetCreaseAngle())
        self.assertEqual(mesh_defaults()["features"]["feature_angle"], 60.0)  # the meshes of before (vtkFeatureEdges' angle)

    def test_the_scene_angle_selects_the_chamfer_edges(self):
        default = self.kept_lines(self.scene())
        self.assertGreater(default.GetNumberOfCells(), 0)  # the 90-degree edges
        self.assertEqual(self.chamfer_segments(default), 0)
        below = self.kept_lines(self.scene(feature_angle=30))
        self.assertGreaterEqual(self.chamfer_segments(below), 2 * 4)  # two edges of length 1, pieces <= 0.3
        # oraclemesh.mesh's keyword (as mesher_for's) overrides the scene's
        self.assertEqual(self.chamfer_segments(self.kept_lines(self.scene(feature_angle=30), feature_angle=60)), 0)

    def test_the_filter_shows_the_creases_per_angle(self):
        scene = build_scene(self.scene())
        lines = om.vtkOracleFeatureLines()
        lines.SetInputConnection(scene.oracle.GetOutputPort())
        lines.SetMaximumSegmentLength(0.3)
        for angle, count in ((60, 9), (30, 15), (100, 0), (180, 0)):  # curves between corners of 3 creases
            with self.subTest(angle):
                lines.SetCreaseAngle(angle)
                out = om.update(lines)
                self.assertEqual(out.GetNumberOfLines(), count)
                for c in range(count):
                    self.assertEqual(out.GetCellData().GetArray("Crease").GetValue(c), 1)

    def test_the_command_line_sets_the_angle_through_the_scene(self):
        scene = os.path.join(self.tmp, "scene.json")
        with open(scene, "w") as f:  # the short form "features": "Automatic" takes --set features.x too
            json.dump(dict(self.scene(), mesh=dict(self.scene()["mesh"], features="Automatic")), f)
        out = os.path.join(self.tmp, "none.vtu")
        run = subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", scene, "-o", out,
                              "--set", "features.feature_angle=180"], capture_output=True, text=True, timeout=100)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("feature lines: none given", run.stdout)  # 180: no creases, and nothing else meets
        bad = subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", scene, "-o", out,
                              "--set", "features.feature_angle=0"], capture_output=True, text=True, timeout=100)
        self.assertEqual(bad.returncode, 2, bad.stderr)
        self.assertIn("$.mesh.features.feature_angle: must be a positive number, got 0", bad.stderr)

    def test_bad_angles_are_named_at_each_door(self):
        for angle, words in ((0, "must be a positive number, got 0"), (181, "must be at most 180 degrees"),
                             ("steep", "must be a positive number, got 'steep'")):
            with self.subTest(angle):
                with self.assertRaisesRegex(om.OracleMeshError, r"\$\.mesh\.features\.feature_angle: " + words):
                    build_scene(self.scene(feature_angle=angle))
        with self.assertRaisesRegex(om.OracleMeshError, "feature_angle: must be a number above 0 and at most 180"):
            om.mesh(self.scene(), feature_angle=-5)
        scene = build_scene(self.scene())  # kept alive: the filters hold no reference to its domains
        for filter_class in (om.vtkOracleFeatureLines, om.vtkFeaturePreservingTetrahedralizer):
            with self.subTest(filter_class.__name__):
                f = filter_class()
                f.SetInputConnection(scene.oracle.GetOutputPort())
                f.SetCreaseAngle(math.nan)
                with self.assertRaisesRegex(om.OracleMeshError, filter_class.__name__ + ": CreaseAngle nan is out of range"):
                    om.update(f)


if __name__ == "__main__":
    unittest.main()


class FoundLinesBesideGivenSharpEdges(unittest.TestCase):
    """A generated bone/implant case (oraclemesh_cases.cases, seed 0) whose scene gives the implant's sharp
    edges (from_surface): in Automatic those given lines are not meshed, so every line of port 2 was
    found (Origin 1), the implant's creases included (they were marked given, being near the unused
    given lines); in Both the given edges win where they and the creases coincide."""

    @classmethod
    def setUpClass(cls):
        from oraclemesh_cases import cases
        cls.tmp = tempfile.mkdtemp()
        cls.folder = os.path.join(cls.tmp, "case")
        cases.make_case(cls.folder, 0)
        with open(os.path.join(cls.folder, "scene.json")) as f:
            cls.description = json.load(f)
        assert cls.description["mesh"]["features"]["from_surface"] == "implant"

    @classmethod
    def tearDownClass(cls):
        import shutil
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def meshed(self, use):
        """The tetrahedralizer run on the case: (segments of port 2 as numpy (n, 2, 3), Origin, statistics)."""
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from oraclemesh.meshing import mesher_for
        from oraclemesh.report import statistics
        description = json.loads(json.dumps(self.description))
        description["mesh"]["features"]["use"] = use
        mesher = mesher_for(build_scene(description, base_dir=self.folder))
        om.update(mesher)
        lines = mesher.GetOutputDataObject(2)
        points = vtk_to_numpy(lines.GetPoints().GetData())
        cells = vtk_to_numpy(lines.GetLines().GetData()).reshape(-1, 3)[:, 1:]
        return (points[cells], vtk_to_numpy(lines.GetCellData().GetArray(fieldkeys.ORIGIN)),
                statistics(mesher.GetOutput()))

    def test_automatic_marks_every_line_found(self):
        segments, origin, _ = self.meshed("Automatic")
        self.assertGreater(len(segments), 0)
        self.assertEqual(set(origin.tolist()), {1})
        _, origin, _ = self.meshed("Both")  # the given edges win where they and the creases coincide
        self.assertEqual(set(origin.tolist()), {0, 1})


class TwoSharpEdgeSearchesAgree(unittest.TestCase):
    """Two implementations find a surface's sharp edges: the scene's from_surface (vtkFeatureEdges,
    given lines, Python side) and Automatic's creases (SurfaceDomain::creases, CGAL's
    detect_sharp_edges, in the core). At one angle they must give the same edges: the demo's implant
    and a generated one, at the default angle and below it."""

    @staticmethod
    def segments(poly):
        import numpy as np
        from vtkmodules.util.numpy_support import vtk_to_numpy
        points = vtk_to_numpy(poly.GetPoints().GetData())
        offsets = vtk_to_numpy(poly.GetLines().GetOffsetsArray())
        ids = vtk_to_numpy(poly.GetLines().GetConnectivityArray())
        pairs = [(ids[k], ids[k + 1]) for start, end in zip(offsets, offsets[1:]) for k in range(start, end - 1)]
        return np.array([(points[a], points[b]) for a, b in pairs])

    @staticmethod
    def farthest(from_segments, to_segments):
        """Largest distance from points along `from_segments` (ends, quarters) to the segments `to_segments`."""
        import numpy as np
        a, b = to_segments[:, 0], to_segments[:, 1]
        ab = b - a
        worst = 0.0
        for s in from_segments:
            for t in (0.0, 0.25, 0.5, 0.75, 1.0):
                p = s[0] + t * (s[1] - s[0])
                u = np.clip(((p - a) * ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-300), 0, 1)
                worst = max(worst, np.linalg.norm(a + u[:, None] * ab - p, axis=1).min())
        return worst

    def test_the_same_edges_at_the_same_angle(self):
        import numpy as np
        from vtkmodules.vtkFiltersCore import vtkFeatureEdges
        from oraclemesh_cases import cases
        with tempfile.TemporaryDirectory() as tmp:
            cases.make_case(tmp, 0)
            surfaces = {"demo": os.path.join(os.path.dirname(__file__), "..", "..", "Data", "demo", "implant.vtp"),
                        "generated": os.path.join(tmp, "implant.vtp")}
            for (name, path), angle in ((s, a) for s in surfaces.items() for a in (60, 30)):
                with self.subTest(name, angle=angle):
                    scene = build_scene({"domains": [{"name": name, "type": "surface", "file": path, "material": 1}]})
                    edges = vtkFeatureEdges()  # as meshing.py's from_surface
                    edges.SetInputConnection(scene.domains[0].GetInputConnection(0, 0))
                    edges.BoundaryEdgesOff()
                    edges.NonManifoldEdgesOff()
                    edges.ManifoldEdgesOff()
                    edges.SetFeatureAngle(angle)
                    given = self.segments(om.update(edges))
                    search = om.vtkOracleFeatureLines()  # a surface alone: its creases are all it finds
                    search.SetInputConnection(scene.oracle.GetOutputPort())
                    search.SetCreaseAngle(angle)
                    found = self.segments(om.update(search))
                    self.assertGreater(len(given), 0)
                    scale = 1e-7 * float(np.ptp(given.reshape(-1, 3), axis=0).max())  # float coordinates of the file
                    self.assertLess(self.farthest(given, found), scale)
                    self.assertLess(self.farthest(found, given), scale)
                    length = lambda s: float(np.linalg.norm(s[:, 1] - s[:, 0], axis=1).sum())
                    self.assertAlmostEqual(length(given), length(found), delta=1e3 * scale)
