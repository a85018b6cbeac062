# SPDX-License-Identifier: GPL-3.0-or-later
"""The report a solver's user reads (issue 34 item 3): per material the worst tetrahedron's largest
dihedral angle, radius ratio, mean ratio and edge ratio, a histogram of the largest angles, the worst
tetrahedra with where they are, the MaxDihedralAngle cell array beside MinDihedralAngle, and
--strict MIN,MAX failing on a dihedral angle outside the window. The measures are checked on
tetrahedra whose values are known in closed form."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import oraclemesh as om
from oraclemesh import fieldkeys
from oraclemesh.report import centroid, quality, read_mesh
from oraclemesh.shape import shape_measures
from oraclemesh.writers import tetrahedra

COMMAND = os.environ.get("ORACLEMESH_COMMAND")
SCENE = {"domains": [{"name": "implant", "type": "sphere", "center": [0, 0, 0], "radius": 2, "material": 2},
                     {"name": "bone", "type": "box", "bounds": [-5, 5, -5, 5, -5, 5], "material": 1}],
         "mesh": {"criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.2}, "seed": 1}}


def run(*args):
    prefix = [COMMAND] if COMMAND else [sys.executable, "-m", "oraclemesh"]
    return subprocess.run(prefix + [str(a) for a in args], capture_output=True, text=True, timeout=300)


class ShapeMeasures(unittest.TestCase):
    def test_known_tetrahedra(self):
        regular = [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]
        corner = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
        flat = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
        s = shape_measures(np.array(regular + corner + flat, float), np.arange(12).reshape(3, 4))
        dihedral = math.degrees(math.acos(1 / 3))  # 70.53
        np.testing.assert_allclose(s["min_dihedral"], [dihedral, math.degrees(math.atan(math.sqrt(2))), 0], atol=1e-9)
        np.testing.assert_allclose(s["max_dihedral"], [dihedral, 90, 180], atol=1e-9)
        # the trirectangular corner: r = 1 / (3 + sqrt 3), R = sqrt(3) / 2; mean ratio 12 (1/2)^(2/3) / 9
        np.testing.assert_allclose(s["radius_ratio"], [1, 3 / (3 + math.sqrt(3)) / (math.sqrt(3) / 2), 0], atol=1e-9)
        np.testing.assert_allclose(s["mean_ratio"], [1, 12 * 0.5 ** (2 / 3) / 9, 0], atol=1e-9)
        np.testing.assert_allclose(s["edge_ratio"], [1, 1 / math.sqrt(2), 1 / math.sqrt(2)], atol=1e-9)


    def test_the_report_histogram_counts_as_numpy_does(self):
        from oraclemesh.report import MAX_TEXT_BINS, TEXT_BINS, histogram

        random = np.random.default_rng(3)
        for bins in (TEXT_BINS, MAX_TEXT_BINS):
            values = np.concatenate([random.uniform(-10, 190, 5000), np.array(bins, float)])  # edges exactly too
            np.testing.assert_array_equal(histogram(values, bins), np.histogram(values, bins=bins)[0])


class Report(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.result = om.mesh(SCENE)
        cls.vtu = os.path.join(cls.tmp.name, "mesh.vtu")
        cls.result.save(cls.vtu)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_the_vtu_carries_the_largest_angle_as_the_geometry_gives_it(self):
        from vtkmodules.util.numpy_support import vtk_to_numpy

        grid = read_mesh(self.vtu)
        largest = vtk_to_numpy(grid.GetCellData().GetArray("MaxDihedralAngle"))
        smallest = vtk_to_numpy(grid.GetCellData().GetArray("MinDihedralAngle"))
        points, cells, _ = tetrahedra(grid)
        shape = shape_measures(points, cells)
        np.testing.assert_allclose(largest, shape["max_dihedral"], atol=1e-6)
        np.testing.assert_allclose(smallest, shape["min_dihedral"], atol=1e-6)
        self.assertTrue((largest > 70.52).all() and (largest < 180).all())

    def test_a_fresh_mesh_reports_the_mesher_figures_equal_to_an_independent_measure(self):
        """The result's quality comes from the mesher's one measuring pass (ShapeSummary); measured
        again here from the corners alone (shape.py, numpy) every figure agrees."""
        fresh, again = self.result.quality, quality(self.result.grid)
        self.assertNotIn("radius_ratio", fresh["shape"], "the fresh quality is the mesher's, not measured again")
        self.assertEqual(set(fresh["materials"]), set(again["materials"]))
        for m, row in again["materials"].items():
            for key, value in row.items():
                self.assertAlmostEqual(fresh["materials"][m][key], value, delta=1e-9 * max(1.0, abs(value)),
                                       msg=f"material {m}: {key}")
        for key in ("tets", "vertices", "volume", "min_dihedral", "max_dihedral"):
            self.assertAlmostEqual(fresh[key], again[key], delta=1e-9 * max(1.0, abs(again[key])), msg=key)
        for key, value in again["worst"].items():
            self.assertAlmostEqual(fresh["worst"][key], value, delta=1e-9, msg=key)
        for key in ("min_dihedral", "max_dihedral"):
            np.testing.assert_allclose(fresh["shape"][key], again["shape"][key], atol=1e-9)

    def test_the_mesher_counts_the_report_histograms_as_numpy_does(self):
        """The report's angle histograms of a fresh mesh are the mesher's counts (one measuring pass,
        statistics shape.*_bin.*): those numpy counts from the cell arrays, for every bin."""
        from oraclemesh.report import MAX_TEXT_BINS, TEXT_BINS, counted_bins, report_lines

        q, stats = self.result.quality, self.result.statistics
        for key, values, bins in ((fieldkeys.SHAPE_MIN_DIHEDRAL_BIN, q["angles"], TEXT_BINS),
                                  (fieldkeys.SHAPE_MAX_DIHEDRAL_BIN, q["shape"]["max_dihedral"], MAX_TEXT_BINS)):
            counted = counted_bins(stats, key, bins, q["tets"])
            self.assertIsNotNone(counted, f"{key}: the mesher counted the report's bins")
            self.assertEqual(list(counted), np.histogram(values, bins=bins)[0].tolist())
        again, _ = report_lines(self.result.grid, "t", recheck=True)
        fresh, _ = report_lines(self.result.grid, "t", recheck=False)
        self.assertEqual([l for l in fresh if "dihedral angle per tetrahedron" in l],
                         [l for l in again if "dihedral angle per tetrahedron" in l])

    def test_the_mesher_names_the_worst_tetrahedra_a_full_sort_gives(self):
        """A fresh mesh's worst tetrahedra come from the mesher's measuring pass (statistics
        shape.*_tet.<rank>): those a stable sort of the cell arrays puts first."""
        from oraclemesh.report import WORST_SHOWN, worst_tetrahedra

        q = self.result.quality
        self.assertIn("worst_first", q["shape"], "the mesher named them")
        for key in ("min_dihedral", "max_dihedral"):
            values = q["shape"][key]
            full = np.argsort(values if key == "min_dihedral" else -values, kind="stable")[:WORST_SHOWN]
            np.testing.assert_array_equal(worst_tetrahedra(q, key), full)

    def test_the_worst_tetrahedra_are_those_a_full_sort_gives(self):
        from oraclemesh.report import worst_tetrahedra

        q = dict(self.result.quality)
        values = np.round(q["shape"]["min_dihedral"], 1)  # many ties
        q["shape"] = {"min_dihedral": values, "max_dihedral": -values}
        for key in ("min_dihedral", "max_dihedral"):
            full = np.argsort(values if key == "min_dihedral" else values, kind="stable")[:7]
            np.testing.assert_array_equal(worst_tetrahedra(q, key, 7), full)

    def test_the_report_names_the_worst_tetrahedra_and_where_they_are(self):
        q, report = self.result.quality, self.result.report
        self.assertIn("maximal dihedral angle per tetrahedron: 60-90°:", report)
        self.assertIn("(max dihedral and the ratios are the worst tetrahedron's", report)
        shape = q["shape"]
        worst = int(np.argmax(shape["max_dihedral"]))
        centre = centroid(q, worst)
        line = next(text for text in report.splitlines() if text.startswith("worst tetrahedra by largest"))
        self.assertIn(f"{shape['max_dihedral'][worst]:.2f}° in #{worst} (material {int(q['material'][worst])}) at "
                      f"({', '.join(f'{x:.4g}' for x in centre)})", line.split(";")[0])
        self.assertEqual(line.count(" in #"), 5)
        for m, row in q["materials"].items():
            self.assertAlmostEqual(row["worst_max_dihedral"], shape["max_dihedral"][q["material"] == m].max())
            self.assertGreater(row["worst_radius_ratio"], 0)
            self.assertLessEqual(row["worst_mean_ratio"], 1)

    def test_strict_takes_a_dihedral_window(self):
        q = self.result.quality
        low, high = q["min_dihedral"], q["max_dihedral"]
        tight = run("report", self.vtu, "--no-png", "--strict", f"{low + 0.5:.3f},{high - 0.5:.3f}")
        self.assertEqual(tight.returncode, 3, tight.stderr)
        self.assertIn("tetrahedra have a dihedral angle outside", tight.stderr)
        wide = run("report", self.vtu, "--no-png", "--strict", f"{low - 0.5:.3f},{high + 0.5:.3f}")
        self.assertEqual(wide.returncode, 0, wide.stderr)
        bad = run("report", self.vtu, "--no-png", "--strict", "155,15")
        self.assertEqual(bad.returncode, 2)
        self.assertIn("need 0 <= MIN < MAX <= 180", bad.stderr)


class QualityStep(unittest.TestCase):
    """The quality step through the doors: on by default (the filter, the scene's defaults), its
    window checked by --strict, off by the scene key, its keys validated."""

    def mesh(self, tmp, *extra):
        import json

        scene = os.path.join(tmp, "scene.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f)
        out = os.path.join(tmp, "mesh.vtu")
        result = run("mesh", scene, "-o", out, "--report", os.path.join(tmp, "report.txt"), *extra)
        return result, read_mesh(out) if result.returncode == 0 else None

    def test_on_by_default_and_every_angle_in_its_window(self):
        from oraclemesh import vtkFeaturePreservingTetrahedralizer
        from oraclemesh.defaults import mesh_defaults

        self.assertTrue(vtkFeaturePreservingTetrahedralizer().GetImproveAngles())
        self.assertEqual((mesh_defaults()["improvement_min_angle"], mesh_defaults()["improvement_max_angle"]),
                         (15.0, 155.0))
        with tempfile.TemporaryDirectory() as tmp:
            off, grid = self.mesh(tmp, "--set", "improve_angles=false")
            self.assertEqual(off.returncode, 0, off.stderr)
            points, cells, _ = tetrahedra(grid)
            shape = shape_measures(points, cells)
            outside = int(((shape["min_dihedral"] < 15) | (shape["max_dihedral"] > 155)).sum())
            self.assertGreater(outside, 0, "the scene no longer has tetrahedra for the step to raise")
            self.assertNotIn("quality step:", off.stdout)
            on, grid = self.mesh(tmp, "--strict", "15,155")
            self.assertEqual(on.returncode, 0, on.stderr)
            self.assertRegex(on.stdout, r"quality step: \d+ tetrahedra with a dihedral angle outside \[15, 155\] "
                                        r"degrees before it, 0 after")
            points, cells, _ = tetrahedra(grid)
            shape = shape_measures(points, cells)
            self.assertGreaterEqual(shape["min_dihedral"].min(), 15.0)
            self.assertLessEqual(shape["max_dihedral"].max(), 155.0)

    def test_scene_keys_are_checked(self):
        import json

        from oraclemesh.errors import OracleMeshError
        from oraclemesh.scene import load_scene

        for key, value, words in (("improve_angles", "yes", "true or false"),
                                  ("improvement_max_angle", 100, "between 120 and 179"),
                                  ("improvement_min_angle", 0, "between 1 and 60")):
            with tempfile.TemporaryDirectory() as tmp:
                path = os.path.join(tmp, "scene.json")
                with open(path, "w") as f:
                    json.dump({**SCENE, "mesh": {**SCENE["mesh"], key: value}}, f)
                with self.assertRaises(OracleMeshError) as e:
                    load_scene(path)
            self.assertIn(f"$.mesh.{key}", str(e.exception))
            self.assertIn(words, str(e.exception))


if __name__ == "__main__":
    unittest.main()
