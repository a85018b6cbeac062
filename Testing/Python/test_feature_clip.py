# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmarks/cad_defects item 5: given feature lines clipped to the meshed domain
(clipFeatureSegments, FeatureClip.h). Pieces where no material is (outside every domain, cut away)
and a part's sharp edges covered by a higher-priority input are removed before meshing, a line
leaving the domain is split exactly where it leaves, and the coverage and validity checks count only
what is kept: no false "missing pieces" any more."""
import os
import shutil
import tempfile
import unittest

import oraclemesh as om
from oraclemesh import fieldkeys

CRITERIA = {"facet_size": 0.5, "facet_distance": 0.05, "cell_size": 0.6, "edge_size": 0.4,
            "cell_radius_edge_ratio": 2.0}


def write_box(path, bounds):
    """A closed box surface (12 triangles) as a .vtp."""
    from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkTriangleFilter
    from vtkmodules.vtkFiltersSources import vtkCubeSource
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    cube = vtkCubeSource()
    cube.SetBounds(*bounds)
    merged = vtkCleanPolyData()  # one point per corner (the source repeats them per face)
    merged.SetInputConnection(cube.GetOutputPort())
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(merged.GetOutputPort())
    writer = vtkXMLPolyDataWriter()
    writer.SetInputConnection(triangles.GetOutputPort())
    writer.SetFileName(path)
    writer.Write()
    return path


def write_polyline(path, points):
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(*p)
    cells = vtkCellArray()
    cells.InsertNextCell(len(points))
    for i in range(len(points)):
        cells.InsertCellPoint(i)
    lines = vtkPolyData()
    lines.SetPoints(pts)
    lines.SetLines(cells)
    writer = vtkXMLPolyDataWriter()
    writer.SetInputData(lines)
    writer.SetFileName(path)
    writer.Write()
    return path


def mesh_points(grid):
    return {grid.GetPoint(i) for i in range(grid.GetNumberOfPoints())}


class FeatureClip(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="oraclemesh_clip_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def assertCleanMesh(self, result):
        self.assertEqual(result.statistics.get("validity.defects", 0), 0, result.warnings)
        self.assertEqual(result.statistics.get("validity.missing_segment_pieces", 0), 0, result.warnings)
        self.assertEqual(result.statistics[fieldkeys.FEATURE_COVERAGE], 1.0, result.warnings)
        self.assertFalse([w for w in result.warnings if "lie outside every domain" in w], result.warnings)

    def clip_warning(self, result):
        clipped = [w for w in result.warnings if w.startswith("feature lines clipped to the meshed domain")]
        self.assertEqual(len(clipped), 1, result.warnings)
        return clipped[0]

    def test_a_part_cut_in_half_keeps_its_edges_up_to_the_cut_plane(self):
        # the reduction of study seed 11 (cut_part_lines_missing): before, the removed half's edges
        # were kept, warned as outside every domain and counted as 8 missing pieces (coverage 42 %)
        part = write_box(self.path("part.vtp"), (-3, 1, 0, 1, 0, 1))
        for use in ("Given", "Both"):
            with self.subTest(use=use):
                scene = {"domains": [
                    {"name": "cut", "type": "plane", "origin": [-1, 0, 0], "normal": [1, 0, 0], "cut": True},
                    {"name": "part", "type": "surface", "file": part, "material": 4},
                    {"name": "housing", "type": "box", "bounds": [-4, 4, -2, 3, -2, 3], "material": 1}],
                    "mesh": {"seed": 1, "criteria": CRITERIA,
                             "features": {"from_surface": "part", "feature_angle": 20, "resample": False, "use": use}}}
                result = om.mesh(scene)
                self.assertCleanMesh(result)
                # the part's 4 edges along x end exactly on the plane, at a mesh vertex
                points = mesh_points(result.grid)
                for y in (0.0, 1.0):
                    for z in (0.0, 1.0):
                        self.assertIn((-1.0, y, z), points)
                self.assertIn("the sharp edges of", self.clip_warning(result))
                self.assertIn("4 removed, 4 split", self.clip_warning(result))
                # nothing of the part is left beyond the plane: no corner there
                self.assertNotIn((-3.0, 0.0, 0.0), points)

    def test_a_line_partly_outside_the_whole_domain_is_clipped_where_it_leaves(self):
        line = write_polyline(self.path("line.vtp"), [(-1.0, 0.3, 0.2), (1.5, 0.3, 0.2), (7.1, 0.3, 0.2), (7.1, 2.0, 0.2)])
        scene = {"domains": [{"name": "housing", "type": "box", "bounds": [-2, 4, -1, 2, -1, 2], "material": 1}],
                 "mesh": {"seed": 1, "criteria": CRITERIA, "features": {"files": [line], "use": "Given"}}}
        result = om.mesh(scene)
        self.assertCleanMesh(result)
        points = mesh_points(result.grid)
        self.assertIn((4.0, 0.3, 0.2), points)  # on the box's face, exactly
        self.assertIn("the given lines: 1 removed, 1 split", self.clip_warning(result))

    def test_a_parts_edges_covered_by_a_higher_priority_part_are_clipped_a_users_line_there_is_kept(self):
        # "inner" sticks out of "block" (higher priority) at x = 2: inside the block its sharp edges
        # are no edges of the combined domain (the block's material covers them), so they are
        # clipped there; the part beyond x = 2 keeps its edges. A user's own line inside the block
        # is a line the user wants: kept, and present in the mesh.
        inner = write_box(self.path("inner.vtp"), (-0.5, 3, -0.5, 0.5, -0.5, 0.5))
        line = write_polyline(self.path("user.vtp"), [(-1.5, -1.2, -1.2), (1.5, -1.2, -1.2)])
        scene = {"domains": [
            {"name": "block", "type": "box", "bounds": [-2, 2, -2, 2, -2, 2], "material": 2},
            {"name": "inner", "type": "surface", "file": inner, "material": 3},
            {"name": "housing", "type": "box", "bounds": [-3, 5, -3, 3, -3, 3], "material": 1}],
            "mesh": {"seed": 1, "criteria": CRITERIA,
                     "features": {"from_surface": "inner", "files": [line], "feature_angle": 20, "resample": False,
                                  "use": "Given"}}}
        result = om.mesh(scene)
        self.assertCleanMesh(result)
        warning = self.clip_warning(result)
        self.assertIn("the sharp edges of", warning)
        self.assertIn("4 removed, 4 split", warning)
        self.assertNotIn("the given lines", warning)  # the user's line is kept whole
        points = mesh_points(result.grid)
        for y in (-0.5, 0.5):
            for z in (-0.5, 0.5):
                self.assertNotIn((-0.5, y, z), points)  # the hidden corners are no mesh vertices
                self.assertIn((2.0, y, z), points)     # the edges end on the block's face
                self.assertIn((3.0, y, z), points)     # the visible corners are
        self.assertIn((-1.5, -1.2, -1.2), points)
        self.assertIn((1.5, -1.2, -1.2), points)


if __name__ == "__main__":
    unittest.main()
