# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 11 item 8: warnings about the inputs (printed, in the report, in the field data as
Warnings and InputWarnings): a scale mismatch of 100x or more (units), bounding boxes that barely
overlap (frames), a material or label without a tetrahedron although its input is not empty. Exit 0
stays; --strict makes them exit 3."""
import json
import os
import subprocess
import tempfile
import unittest

import numpy as np
import oraclemesh as om

COMMAND = os.environ.get("ORACLEMESH_COMMAND")
MESH = {"strategy": "None", "criteria": {"cell_size": 10, "facet_size": 10, "facet_distance": 2}, "seed": 1}


def sphere(name, center, radius, material):
    return {"name": name, "type": "sphere", "center": center, "radius": radius, "material": material}


class InputWarnings(unittest.TestCase):
    def test_units_mismatch(self):
        # an implant in metres inside a bone in millimetres
        result = om.mesh({"domains": [sphere("implant", [0, 0, 0], 0.05, 2), sphere("bone", [0, 0, 0], 50, 1)],
                          "mesh": MESH})
        text = "\n".join(result.input_warnings)
        self.assertIn("differ in size by 1000x", text)
        for w in result.input_warnings:
            self.assertIn(w, result.warnings)
            self.assertIn(w, result.report)

    def test_apart_inputs(self):
        result = om.mesh({"domains": [sphere("a", [0, 0, 0], 10, 1), sphere("b", [100, 0, 0], 10, 2)],
                          "mesh": MESH})
        self.assertTrue(any("do not overlap" in w for w in result.input_warnings), result.input_warnings)

    def test_a_matching_scene_has_none(self):
        result = om.mesh({"domains": [sphere("a", [0, 0, 0], 10, 2), sphere("b", [0, 0, 0], 20, 1)], "mesh": MESH})
        self.assertEqual(result.input_warnings, [])

    def test_a_label_of_two_voxels_is_dropped_with_a_warning(self):
        from vtkmodules.util.numpy_support import numpy_to_vtk
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

        labels = np.zeros((30, 30, 30), dtype=np.int32)  # z, y, x
        labels[5:25, 5:25, 5:25] = 1
        labels[15, 15, 15:17] = 7
        image = vtkImageData()
        image.SetDimensions(30, 30, 30)
        array = numpy_to_vtk(labels.ravel(), deep=True)
        array.SetName("labels")
        image.GetPointData().AddArray(array)
        with tempfile.TemporaryDirectory() as tmp:
            writer = vtkXMLImageDataWriter()
            writer.SetFileName(os.path.join(tmp, "labels.vti"))
            writer.SetInputData(image)
            writer.Write()
            scene = {"domains": [{"name": "bone", "type": "labelmap", "file": "labels.vti"}],
                     "mesh": {"criteria": {"cell_size": 4, "facet_size": 4, "facet_distance": 1}, "seed": 1}}
            result = om.mesh(scene, base_dir=tmp)
            self.assertTrue(any(w.startswith("label 7 of") and "dropped" in w for w in result.input_warnings),
                            result.input_warnings)
            if COMMAND:
                path = os.path.join(tmp, "scene.json")
                with open(path, "w") as f:
                    json.dump(scene, f)
                out = os.path.join(tmp, "out.vtu")
                plain = subprocess.run([COMMAND, "mesh", path, "-o", out], capture_output=True, text=True)
                self.assertEqual(plain.returncode, 0, plain.stderr)
                self.assertIn("label 7 of", plain.stdout)
                strict = subprocess.run([COMMAND, "mesh", path, "-o", out, "--strict"], capture_output=True, text=True)
                self.assertEqual(strict.returncode, 3, strict.stderr)
                self.assertIn("warning(s) about the inputs (--strict)", strict.stderr)
                self.assertTrue(os.path.exists(out))
                report = subprocess.run([COMMAND, "report", out, "--no-png", "--strict"], capture_output=True, text=True)
                self.assertEqual(report.returncode, 3, report.stderr)


if __name__ == "__main__":
    unittest.main()
