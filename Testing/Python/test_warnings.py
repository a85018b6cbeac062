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

    def test_parts_touching_inside_a_third_are_placed_alike(self):
        # two implant parts meeting face to face (their boxes share a face only) inside a bone
        parts = [{"name": "a", "type": "box", "bounds": [0, 10, 0, 10, 0, 10], "material": 1},
                 {"name": "b", "type": "box", "bounds": [10, 20, 0, 10, 0, 10], "material": 2}]
        result = om.mesh({"domains": parts + [sphere("bone", [10, 5, 5], 16, 3)], "mesh": MESH})
        self.assertEqual(result.input_warnings, [])
        # the same parts far from the bone: one warning, the bone against the group of the first input
        result = om.mesh({"domains": parts + [sphere("bone", [200, 5, 5], 16, 3)], "mesh": MESH})
        apart = [w for w in result.input_warnings if "overlap" in w]
        self.assertEqual(len(apart), 1, result.input_warnings)
        self.assertRegex(apart[0], r"of .*'bone' do not overlap those of .*'a'.*'b'")

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

    def test_a_label_map_in_another_frame_than_the_surfaces_declare(self):
        """A NIfTI label map (RAS, placed in the scene's LPS) under a surface whose STL header says
        SPACE=RAS (3D Slicer's): the orientations differ, a warning says so and names the fix; with
        "space": "RAS", or a surface declaring LPS, none. Both are centred on the origin, so the
        bounding-box warnings stay out of it."""
        from vtkmodules.util.numpy_support import numpy_to_vtk
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkFiltersSources import vtkCubeSource
        from vtkmodules.vtkFiltersCore import vtkTriangleFilter
        from vtkmodules.vtkIOGeometry import vtkSTLWriter
        from vtkmodules.vtkIOImage import vtkNIFTIImageWriter

        labels = np.zeros((20, 20, 20), dtype=np.uint8)
        labels[4:16, 4:16, 4:16] = 1
        image = vtkImageData()
        image.SetDimensions(20, 20, 20)
        image.SetOrigin(-9.5, -9.5, -9.5)
        array = numpy_to_vtk(labels.ravel(), deep=True)
        array.SetName("labels")
        image.GetPointData().SetScalars(array)
        cube = vtkCubeSource()
        cube.SetXLength(4)
        cube.SetYLength(4)
        cube.SetZLength(4)
        triangles = vtkTriangleFilter()
        triangles.SetInputConnection(cube.GetOutputPort())
        with tempfile.TemporaryDirectory() as tmp:
            nifti = vtkNIFTIImageWriter()
            nifti.SetFileName(os.path.join(tmp, "labels.nii.gz"))
            nifti.SetInputData(image)
            nifti.Write()
            for frame in ("RAS", "LPS"):
                stl = vtkSTLWriter()
                stl.SetFileName(os.path.join(tmp, f"implant_{frame}.stl"))
                stl.SetInputConnection(triangles.GetOutputPort())
                stl.SetFileTypeToBinary()
                stl.SetHeader(f"SPACE={frame}")
                stl.Write()

            def scene(surface_frame, space=None):
                description = {"domains": [
                    {"name": "implant", "type": "surface", "file": f"implant_{surface_frame}.stl", "material": 2},
                    {"name": "bone", "type": "labelmap", "file": "labels.nii.gz"}],
                    "mesh": {"criteria": {"cell_size": 4, "facet_size": 4, "facet_distance": 1}, "seed": 1}}
                if space:
                    description["space"] = space
                return description

            result = om.mesh(scene("RAS"), base_dir=tmp)
            frames = [w for w in result.input_warnings if "declares SPACE=RAS" in w]
            self.assertEqual(len(frames), 1, result.input_warnings)
            self.assertIn("bone (RAS file)", frames[0])
            self.assertIn('set "space": "RAS"', frames[0])
            self.assertIn(frames[0], result.warnings)
            self.assertIn(frames[0], result.report)
            for fine in (scene("RAS", space="RAS"), scene("LPS")):
                self.assertFalse([w for w in om.mesh(fine, base_dir=tmp).input_warnings if "SPACE=" in w])
            if COMMAND:
                path = os.path.join(tmp, "scene.json")
                with open(path, "w") as f:
                    json.dump(scene("RAS"), f)
                out = os.path.join(tmp, "out.vtu")
                plain = subprocess.run([COMMAND, "mesh", path, "-o", out], capture_output=True, text=True)
                self.assertEqual(plain.returncode, 0, plain.stderr)
                self.assertIn("declares SPACE=RAS", plain.stdout)
                strict = subprocess.run([COMMAND, "mesh", path, "-o", out, "--strict"], capture_output=True,
                                        text=True)
                self.assertEqual(strict.returncode, 3, strict.stderr)
                report = subprocess.run([COMMAND, "report", out, "--no-png", "--strict"], capture_output=True,
                                        text=True)
                self.assertEqual(report.returncode, 3, report.stderr)  # the warning is in the file


class CommandLineWarnings(unittest.TestCase):
    @unittest.skipUnless(COMMAND, "needs ORACLEMESH_COMMAND")
    def test_each_warning_printed_once(self):
        """The report lists the mesher's warnings; VTK's own print of them (another format, on
        stderr) is left out, while messages the report does not hold still reach stderr."""
        scene = {"domains": [sphere("big", [0, 0, 0], 20, 1), sphere("hidden", [0, 0, 0], 5, 2)], "mesh": MESH}
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            run = subprocess.run([COMMAND, "mesh", path, "-o", os.path.join(tmp, "out.vtu")],
                                 capture_output=True, text=True)
            self.assertEqual(run.returncode, 0, run.stderr)
            both = run.stdout + run.stderr
            self.assertEqual(both.count("'hidden' is hidden"), 1, both)
            self.assertNotIn("WARN|", run.stderr)
            # a message no report holds: a scene whose surface file VTK cannot read is an error
            # with VTK's own words on stderr
            with open(os.path.join(tmp, "broken.vtp"), "w") as f:
                f.write("<VTKFile type='PolyData'><PolyData>")
            broken = {"domains": [{"name": "part", "type": "surface", "file": "broken.vtp", "material": 1}],
                      "mesh": MESH}
            with open(path, "w") as f:
                json.dump(broken, f)
            run = subprocess.run([COMMAND, "mesh", path, "-o", os.path.join(tmp, "out.vtu")],
                                 capture_output=True, text=True)
            self.assertNotEqual(run.returncode, 0)
            self.assertIn("broken.vtp", run.stderr)


if __name__ == "__main__":
    unittest.main()
