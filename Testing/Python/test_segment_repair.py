# SPDX-License-Identifier: GPL-3.0-or-later
"""The segment repair after perturbation (docs/MESHER.md "Optimisation"). The perturber never moves
a segment's vertices, but a moved neighbour can land in a sub-segment's diametral ball; the mesher
then refines once more so that every piece is a mesh edge again. That round looked at every element,
and at a tight radius-edge bound it also refined every cell the perturber had left above the bound
(which a run without repair keeps): on this generated bone/implant case (seed 0, radius-edge 1.1,
Both) 79 splits doubled the mesh, 559k -> 740k tetrahedra, and lowered the smallest angle from 12 to
9.2 degrees. The round now starts from the broken sub-segments and the removed encroachers only.
Asserted: the repair ran, the mesh is valid with every piece, and the repaired mesh holds at most 5 %
more tetrahedra than the same refinement without optimisation. About 20 s a run: no exudation."""
import json
import os
import tempfile
import unittest

from oraclemesh import cases
from oraclemesh.meshing import mesh
from oraclemesh.report import statistics


class SegmentRepairAfterPerturbation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.TemporaryDirectory()
        path = cases.make_case(os.path.join(cls.work.name, "case"), 0, radius_edge=1.1)
        with open(path) as f:
            cls.scene = json.load(f)
        cls.scene["mesh"]["exude"] = False
        cls.base = os.path.dirname(path)

    @classmethod
    def tearDownClass(cls):
        cls.work.cleanup()

    def run_with(self, perturb):
        scene = json.loads(json.dumps(self.scene))
        scene["mesh"]["perturb"] = perturb
        return statistics(mesh(scene, base_dir=self.base, features="Both").grid)

    def test_repair_stays_local(self):
        refined = self.run_with(False)
        repaired = self.run_with(True)
        self.assertEqual(repaired["refinement_rounds"], 2, "the case no longer needs a repair: pick another")
        for s in (refined, repaired):
            self.assertEqual(s["validity.defects"], 0)
            self.assertGreaterEqual(s["feature_coverage"], 1 - 1e-9)
        self.assertLessEqual(repaired["tetrahedra"], 1.05 * refined["tetrahedra"],
                             f"{repaired['tetrahedra']:.0f} tetrahedra after the repair, "
                             f"{refined['tetrahedra']:.0f} after refinement")


if __name__ == "__main__":
    unittest.main()
