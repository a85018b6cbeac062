# SPDX-License-Identifier: GPL-3.0-or-later
"""Interfaces that meet at a small angle along a curve that is no feature line, at the paper's
radius-edge bound 1.1 (MaterialCriteria3.h, kShapeFloorDivisor). On the generated case
face_on_voxel_boundary the implant's collar lies on a voxel boundary of the label map and the cut
plane crosses it at 14 degrees; with the given feature lines only (the implant's sharp edges) that
crossing is unprotected, and radius-edge refinement converged onto one point of it: mesh seed 2
(one thread) and 3 of 4 runs on 2 threads ended at the 300k-vertex budget with edges down to
1e-11 mm and, depending on the run, thousands of micro tetrahedra. Asserted, on one thread and on
two: refinement ends before a 150k-vertex budget, the mesh is valid, every given line is present,
no edge is shorter than 1/1000 of the finest size bound (0.5 mm) and no dihedral angle is below
the picking angle 8.7 degrees. No optimisation, for speed (and so the angles are refinement's)."""
import json
import os
import tempfile
import unittest

from oraclemesh_cases import cases
from oraclemesh.fielddata import strings
from oraclemesh.meshing import mesh
from oraclemesh.report import statistics


class SmallAngleInterfaces(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.TemporaryDirectory()
        path = cases.make_case(os.path.join(cls.work.name, "case"), 102, variant="face_on_voxel_boundary",
                               radius_edge=1.1)
        with open(path) as f:
            cls.scene = json.load(f)
        cls.scene["mesh"].update(seed=2, perturb=False, exude=False, maximum_number_of_vertices=150000)
        cls.base = os.path.dirname(path)
        finest = cls.scene["mesh"]["materials"]["3"]["edge_size"]
        cls.shortest_allowed = finest / 1000

    @classmethod
    def tearDownClass(cls):
        cls.work.cleanup()

    def check(self, threads):
        result = mesh(self.scene, base_dir=self.base, threads=threads)
        s = statistics(result.grid)
        warnings = strings(result.grid.GetFieldData(), "Warnings")
        self.assertFalse([w for w in warnings if "MaximumNumberOfVertices =" in w or "stalled" in w], warnings)
        self.assertEqual(s["validity.defects"], 0)
        self.assertGreaterEqual(s["feature_coverage"], 1 - 1e-9)
        self.assertGreater(s["validity.shortest_edge"], self.shortest_allowed)
        # the floor is on the radius-edge rule only: the sliver rule (picked points) still holds
        self.assertGreaterEqual(s["min_dihedral_angle"], 8.7 - 1e-6)

    def test_one_thread(self):
        self.check(1)

    def test_two_threads(self):
        self.check(2)


if __name__ == "__main__":
    unittest.main()
