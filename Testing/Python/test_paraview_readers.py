# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 11 item 7: the plugin's label-map reader (File > Open .nii .nii.gz .nrrd .nhdr .mha .mhd .inr)
gives what the command line's reader gives. Generated files with a rotated, anisotropic, offset
placement (NIfTI sform, NRRD space directions, an ITK MetaImage TransformMatrix) are read here by
oraclemesh.readers.label_map_reader and in pvpython through the plugin's reader proxy; dimensions,
spacing, origin, direction and every label must be equal, in LPS and RAS. pvpython runs without
oraclemesh on PYTHONPATH, as the ParaView GUI does: the reader finds the package next to the plugin."""
import gzip
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

from oraclemesh.readers import label_map_reader

PVPYTHON = os.environ.get("ORACLEMESH_PVPYTHON")
PLUGIN = os.environ.get("ORACLEMESH_PLUGIN")

SPACING = np.array([0.5, 1.0, 2.0])
ORIGIN = np.array([10.0, -20.0, 30.0])
ROTATION = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 degrees about z
LABELS = np.zeros((8, 10, 12), np.uint8)  # [k, j, i]
LABELS[2:5, 3:7, 2:6] = 5
LABELS[5:7, 1:3, 7:11] = 9


def write_nifti(path):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkCommonMath import vtkMatrix4x4
    from vtkmodules.vtkIOImage import vtkNIFTIImageWriter

    image = vtkImageData()
    image.SetDimensions(12, 10, 8)
    image.SetSpacing(*SPACING)
    array = numpy_to_vtk(LABELS.ravel(), deep=True)
    array.SetName("labels")
    image.GetPointData().SetScalars(array)
    sform = vtkMatrix4x4()  # NIfTI's world (RAS): rotation and offset
    for i in range(3):
        for j in range(3):
            sform.SetElement(i, j, ROTATION[i, j])
        sform.SetElement(i, 3, ORIGIN[i])
    writer = vtkNIFTIImageWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.SetSFormMatrix(sform)
    writer.Write()


def write_nrrd(path):
    columns = ROTATION * SPACING  # column i: the step along axis i
    directions = " ".join("(" + ",".join(f"{v:g}" for v in columns[:, i]) + ")" for i in range(3))
    header = ("NRRD0004\ntype: unsigned char\ndimension: 3\nspace: right-anterior-superior\nsizes: 12 10 8\n"
              f"space directions: {directions}\nkinds: domain domain domain\nendian: little\nencoding: gzip\n"
              f"space origin: ({','.join(f'{v:g}' for v in ORIGIN)})\n\n")
    with open(path, "wb") as f:
        f.write(header.encode() + gzip.compress(LABELS.tobytes()))


def write_metaimage(path):
    header = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
              "CompressedData = False\nTransformMatrix = " + " ".join(f"{v:g}" for v in ROTATION.T.ravel())
              + "\nOffset = " + " ".join(f"{v:g}" for v in ORIGIN)
              + "\nElementSpacing = 0.5 1 2\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
    with open(path, "wb") as f:
        f.write(header.encode() + LABELS.tobytes())


def cli_reading(path, space):
    """What `oraclemesh mesh` reads: oraclemesh.readers.label_map_reader."""
    reader = label_map_reader(path, space)
    reader.Update()
    image = reader.GetOutputDataObject(0)
    scalars = image.GetPointData().GetScalars()
    return {
        "dimensions": list(image.GetDimensions()),
        "spacing": list(image.GetSpacing()),
        "origin": list(image.GetOrigin()),
        "direction": [image.GetDirectionMatrix().GetElement(i, j) for i in range(3) for j in range(3)],
        "labels": [scalars.GetTuple1(i) for i in range(scalars.GetNumberOfTuples())],
    }


@unittest.skipUnless(PVPYTHON and PLUGIN, "pvpython or the plugin not given")
class PluginReaders(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp()
        cls.files = {}
        for name, write in (("labels.nii.gz", write_nifti), ("labels.nrrd", write_nrrd), ("itk.mha", write_metaimage)):
            cls.files[name] = os.path.join(cls.dir, name)
            write(cls.files[name])
        items = [f"{path}:{space}" for path in cls.files.values() for space in ("LPS", "RAS")]
        out = os.path.join(cls.dir, "pv.json")
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # as the GUI: no oraclemesh on the path
        run = subprocess.run([PVPYTHON, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pvpython_readers.py"),
                              PLUGIN, out] + items, capture_output=True, text=True, env=env, timeout=240)
        if run.returncode != 0:
            raise AssertionError(f"pvpython failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")
        with open(out) as f:
            cls.pv = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_file_open_offers_the_plugin_reader(self):
        for name, path in self.files.items():
            self.assertIn("OracleMeshLabelMapReader", self.pv[f"{path}:LPS"]["offered"], name)
        # ParaView 5.11 has no NIfTI reader of its own (.mha and .nrrd: its readers are offered too)
        self.assertEqual(self.pv[f"{self.files['labels.nii.gz']}:LPS"]["default"], "OracleMeshLabelMapReader")

    def test_the_plugin_reads_what_the_command_line_reads(self):
        for name, path in self.files.items():
            for space in ("LPS", "RAS"):
                with self.subTest(file=name, space=space):
                    pv, cli = self.pv[f"{path}:{space}"], cli_reading(path, space)
                    self.assertEqual(pv["dimensions"], cli["dimensions"])
                    np.testing.assert_array_equal(pv["spacing"], cli["spacing"])
                    np.testing.assert_array_equal(pv["origin"], cli["origin"])
                    np.testing.assert_array_equal(pv["direction"], cli["direction"])
                    self.assertEqual(pv["labels"], cli["labels"])

    def test_the_placement_is_the_files(self):
        # Not just equal to each other: the labels sit where the files put them (RAS files, LPS scene).
        flip = np.diag([-1.0, -1.0, 1.0])
        for name in ("labels.nii.gz", "labels.nrrd"):
            lps, ras = self.pv[f"{self.files[name]}:LPS"], self.pv[f"{self.files[name]}:RAS"]
            self.assertEqual(ras["dimensions"], [12, 10, 8], name)
            np.testing.assert_allclose(ras["spacing"], SPACING, err_msg=name)
            np.testing.assert_allclose(ras["origin"], ORIGIN, err_msg=name)
            np.testing.assert_allclose(np.reshape(ras["direction"], (3, 3)), ROTATION, atol=1e-12, err_msg=name)
            np.testing.assert_allclose(lps["origin"], flip @ ORIGIN, err_msg=name)
            self.assertEqual(sorted(set(lps["labels"])), [0, 5, 9], name)
        mha = self.pv[f"{self.files['itk.mha']}:LPS"]  # MetaImage is LPS; ParaView's own reader drops the direction
        np.testing.assert_allclose(np.reshape(mha["direction"], (3, 3)), ROTATION, atol=1e-12)


if __name__ == "__main__":
    sys.exit(unittest.main())
