# SPDX-License-Identifier: GPL-3.0-or-later
"""The tetrahedralizer executed again on the same inputs with another Features option, as
ParaView does when a property changes (Apply): every run gives a valid mesh. Both, Automatic,
Given, Both on the demo scene used to crash in the fourth run: the feature search's step that
collapses short pieces between two junctions read the materials of a crossing that did not exist
when two junctions were joined directly (an index past the crossings)."""
import json
import os
import unittest

from oraclemesh.errors import update
from oraclemesh.meshing import as_scene, mesher_for
from oraclemesh.report import statistics

DEMO = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data", "demo", "scene.json")


class ReExecute(unittest.TestCase):
    def test_features_option_changed_between_runs(self):
        with open(DEMO) as f:
            spec = json.load(f)
        spec["mesh"]["maximum_number_of_vertices"] = 4000  # the search is the point, not the mesh
        spec["mesh"]["perturb"] = spec["mesh"]["exude"] = False
        scene = as_scene(spec, os.path.dirname(DEMO))
        mesher = mesher_for(scene, None, None, "Both", None)
        for k, features in enumerate(("Both", "Automatic", "Given", "Both")):
            with self.subTest(run=k, features=features):
                getattr(mesher, "SetFeaturesTo" + features)()
                mesher.SetSeed(k + 1)
                grid = update(mesher)
                s = statistics(grid)
                self.assertGreater(grid.GetNumberOfCells(), 1000)
                # stopped at the vertex budget: criteria unmet, but the triangulation is consistent
                for key in ("validity.duplicate_vertices", "validity.inverted_tetrahedra",
                            "validity.non_manifold_faces", "validity.unused_vertices"):
                    self.assertEqual(s[key], 0, key)
                self.assertGreater(mesher.GetOutputDataObject(2).GetNumberOfCells(), 0)


if __name__ == "__main__":
    unittest.main()
