# SPDX-License-Identifier: GPL-3.0-or-later
"""The paper's radius-edge bound B = 1.1 (issue 9 item 3) on a generated CAD-like implant alone
(oraclemesh_cases.cases, variant implant_only: flat faces, sharp edges, a chamfered stem tip in the void):
refinement ends before the vertex budget, the mesh is valid, every feature line is a chain of mesh
edges, the simplified feature lines are the given ones (no convex corner bypassed by a chord inside
the part), and the minimal dihedral angle is above the paper's 8.7 degrees after optimisation and
above the sliver rule's 1 degree before it."""
import os
import tempfile
import unittest

from oraclemesh_cases import cases
from oraclemesh.fielddata import strings
from oraclemesh.meshing import mesh
from oraclemesh.report import statistics


class PaperRadiusEdge(unittest.TestCase):
    def test_implant_at_radius_edge_1_1(self):
        with tempfile.TemporaryDirectory() as work:
            scene = cases.make_case(os.path.join(work, "implant"), 1, variant="implant_only", radius_edge=1.1)
            result = mesh(scene)
            s = statistics(result.grid)
            warnings = strings(result.grid.GetFieldData(), "Warnings")
            self.assertFalse([w for w in warnings if "MaximumNumberOfVertices =" in w or "stalled" in w], warnings)
            self.assertEqual(s["validity.defects"], 0)
            self.assertGreaterEqual(s["feature_coverage"], 1 - 1e-9)
            self.assertEqual(s["validity.missing_segment_pieces"], 0)
            # the lines stay on the implant's edges: resampling only drops points on a straight chain
            self.assertLess(s["feature_network.given_to_simplified"], 1e-6)
            self.assertGreaterEqual(s["min_dihedral_angle"], 8.7)
            self.assertGreaterEqual(s["optimisation.min_dihedral_before"], 1.0 - 1e-9)


if __name__ == "__main__":
    unittest.main()
