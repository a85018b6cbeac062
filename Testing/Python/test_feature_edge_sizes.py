# SPDX-License-Identifier: GPL-3.0-or-later
"""The per-feature level of the edge size (global < per material < per feature) at the scene,
Python and command-line doors: each line keeps its own bound; bad and contradictory values are
errors naming the line."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import oraclemesh as om
from oraclemesh.scene import build_scene
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

LINE_A = ((0, 0, 0), (1, 0, 0))  # a cube edge along x at y = z = 0
LINE_B = ((0, 1, 1), (1, 1, 1))  # the opposite one


def write_line(path, ends, edge_size=None, pieces=2):
    """One polyline (of `pieces` equal segments) as .vtp, with an "EdgeSize" cell array when given."""
    points = vtkPoints()
    for k in range(pieces + 1):
        points.InsertNextPoint(tuple(a + k / pieces * (b - a) for a, b in zip(*ends)))
    cells = vtkCellArray()
    cells.InsertNextCell(pieces + 1, list(range(pieces + 1)))
    lines = vtkPolyData()
    lines.SetPoints(points)
    lines.SetLines(cells)
    if edge_size is not None:
        sizes = vtkDoubleArray()
        sizes.SetName("EdgeSize")
        sizes.InsertNextValue(edge_size)
        lines.GetCellData().AddArray(sizes)
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(lines)
    writer.Write()
    return path


def cube_scene(files):
    return {"domains": [{"name": "cube", "type": "box", "bounds": [0, 1, 0, 1, 0, 1], "material": 1}],
            "mesh": {"strategy": "Conforming", "seed": 2, "features": {"files": files},
                     "criteria": {"cell_size": 0.5, "facet_size": 0.5, "facet_distance": 0.05, "edge_size": 0.25}}}


def edges_along(grid, ends):
    """Lengths of the mesh edges whose both ends lie on the segment `ends`."""
    a, b = ends

    def on_line(p):
        t = sum((pi - ai) * (bi - ai) for pi, ai, bi in zip(p, a, b)) / math.dist(a, b) ** 2
        q = [ai + t * (bi - ai) for ai, bi in zip(a, b)]
        return -1e-9 <= t <= 1 + 1e-9 and math.dist(p, q) < 1e-9

    on = {i for i in range(grid.GetNumberOfPoints()) if on_line(grid.GetPoint(i))}
    edges = set()
    for c in range(grid.GetNumberOfCells()):
        ids = [grid.GetCell(c).GetPointId(k) for k in range(4)]
        for i in range(4):
            for j in range(i + 1, 4):
                if ids[i] in on and ids[j] in on:
                    edges.add((min(ids[i], ids[j]), max(ids[i], ids[j])))
    return [math.dist(grid.GetPoint(i), grid.GetPoint(j)) for i, j in edges]


class FeatureEdgeSizes(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()
        self.addCleanup(self.folder.cleanup)

    def path(self, name):
        return os.path.join(self.folder.name, name)

    def test_each_line_keeps_its_own_edge_size(self):
        # line A's edge size from the scene entry, line B's from the file's cell array
        a = write_line(self.path("a.vtp"), LINE_A)
        b = write_line(self.path("b.vtp"), LINE_B, edge_size=0.4)
        result = om.mesh(cube_scene([{"file": a, "edge_size": 0.1}, b]))
        self.assertEqual(result.statistics["feature_coverage"], 1.0)  # every segment piece is a mesh edge
        along_a, along_b = edges_along(result.grid, LINE_A), edges_along(result.grid, LINE_B)
        self.assertAlmostEqual(sum(along_a), 1.0, delta=1e-9)  # the pieces cover the line: all are mesh edges
        self.assertAlmostEqual(sum(along_b), 1.0, delta=1e-9)
        self.assertLessEqual(max(along_a), 0.1 * (1 + 1e-9))
        self.assertLessEqual(max(along_b), 0.4 * (1 + 1e-9))
        self.assertGreater(max(along_b), 0.1, "line B was meshed at line A's edge size")

    def test_port_2_names_the_given_segment_of_each_piece_of_resampled_lines(self):
        # 20 segments a line, resampled (points closer than the finest edge size, 0.1, merged; chords
        # up to it): the mesher renumbers the segments, but port 2's InputSegment is the given one a
        # piece comes from (A's are 0-19, B's 20-39), one that its chord replaced.
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from oraclemesh.fielddata import strings
        from oraclemesh.meshing import as_scene, mesher_for
        a = write_line(self.path("a.vtp"), LINE_A, edge_size=0.1, pieces=20)
        b = write_line(self.path("b.vtp"), LINE_B, edge_size=0.4, pieces=20)
        scene = cube_scene([a, b])
        scene["mesh"]["features"]["resample"] = True
        mesher = mesher_for(as_scene(scene))
        grid = om.update(mesher)
        self.assertIn("feature lines simplified: 40 segments became", "\n".join(strings(grid.GetFieldData(), "Warnings")))
        lines = mesher.GetOutputDataObject(2)
        points = vtk_to_numpy(lines.GetPoints().GetData())
        cells = vtk_to_numpy(lines.GetLines().GetData()).reshape(-1, 3)[:, 1:]
        given = vtk_to_numpy(lines.GetCellData().GetArray("InputSegment"))
        self.assertTrue(vtk_to_numpy(lines.GetCellData().GetArray("Present")).all())
        for (p, q), s in zip(points[cells], given):
            on_a = p[1] == 0 and q[1] == 0  # line A lies on y = 0, B on y = 1
            self.assertIn(s, range(0, 20) if on_a else range(20, 40), (p, q))
            k = s % 20  # the given segment [k / 20, (k + 1) / 20] lies in the piece's chord (at most 0.1 long)
            self.assertGreaterEqual(min(p[0], q[0]), k / 20 - 0.1 - 1e-6, (p, q, s))
            self.assertLessEqual(max(p[0], q[0]), (k + 1) / 20 + 0.1 + 1e-6, (p, q, s))  # float input points

    def test_a_bad_scene_value_is_named_with_its_path(self):
        a = write_line(self.path("a.vtp"), LINE_A)
        for bad in (-0.1, "fine", float("nan")):
            with self.assertRaisesRegex(om.OracleMeshError, r"\$\.mesh\.features\.files\[0\]\.edge_size: must be"):
                build_scene(cube_scene([{"file": a, "edge_size": bad}]))
        with self.assertRaisesRegex(om.OracleMeshError, r"\$\.mesh\.features\.files\[0\]\.size: unknown"):
            build_scene(cube_scene([{"file": a, "size": 0.1}]))

    def test_a_bad_file_value_is_the_cores_error(self):
        b = write_line(self.path("b.vtp"), LINE_B, edge_size=-0.5)
        with self.assertRaisesRegex(om.OracleMeshError, r"feature lines: segment \d+ \(0, 1, 1\) - \(0.5, 1, 1\) "
                                                        r"has EdgeSize -0.5"):
            om.mesh(cube_scene([b]))

    def test_two_sources_giving_one_line_different_values_are_a_contradiction(self):
        b = write_line(self.path("b.vtp"), LINE_B, edge_size=0.4)
        with self.assertRaisesRegex(om.OracleMeshError, r"line 0 of .*b\.vtp gets EdgeSize 0.4 from the file and 0.2 "
                                                        r"from the scene's edge_size"):
            om.mesh(cube_scene([{"file": b, "edge_size": 0.2}]))
        # the same line in two files: the core's contradiction, through Python and the command line
        again = write_line(self.path("again.vtp"), LINE_B, edge_size=0.3)
        scene = cube_scene([b, again])
        message = r"feature lines: segment \(.*\) gets EdgeSize 0.4 and 0.3 from two lines that overlap there"
        with self.assertRaisesRegex(om.OracleMeshError, message):
            om.mesh(scene)
        with open(self.path("scene.json"), "w") as f:
            json.dump(scene, f)
        out = subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", self.path("scene.json"), "-o",
                              self.path("m.vtu")], capture_output=True, text=True, timeout=100)
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertRegex(out.stderr, message.replace("EdgeSize", "edge_size"))  # the scene's spelling

    def test_a_surface_domains_own_edge_size_bounds_its_sharp_edges(self):
        # the per-material level: the domain's criteria, finer than the global edge size
        from vtkmodules.vtkFiltersCore import vtkTriangleFilter
        from vtkmodules.vtkFiltersSources import vtkCubeSource
        from vtkmodules.vtkIOGeometry import vtkSTLWriter

        cube = vtkCubeSource()  # [-0.5, 0.5]^3
        triangles = vtkTriangleFilter()
        triangles.SetInputConnection(cube.GetOutputPort())
        writer = vtkSTLWriter()
        writer.SetInputConnection(triangles.GetOutputPort())
        writer.SetFileName(self.path("cube.stl"))
        writer.Write()
        scene = {"domains": [{"name": "part", "type": "surface", "file": self.path("cube.stl"), "material": 1,
                              "criteria": {"edge_size": 0.15}}],
                 "mesh": {"seed": 1, "features": {"from_surface": "part"},
                          "criteria": {"cell_size": 0.5, "facet_size": 0.5, "facet_distance": 0.05, "edge_size": 0.5}}}
        result = om.mesh(scene)
        self.assertEqual(result.statistics["feature_coverage"], 1.0)
        corners = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
        edges = [(p, q) for p in corners for q in corners if p < q and math.dist(p, q) == 1.0]
        self.assertEqual(len(edges), 12)
        for ends in edges:
            along = edges_along(result.grid, ends)
            self.assertAlmostEqual(sum(along), 1.0, delta=1e-9, msg=f"cube edge {ends}")
            self.assertLessEqual(max(along), 0.15 * (1 + 1e-9), f"cube edge {ends}")


if __name__ == "__main__":
    unittest.main()
