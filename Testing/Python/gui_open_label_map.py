# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by the ParaView GUI (under Xvfb, PV_PLUGIN_PATH = the plugin, no oraclemesh on PYTHONPATH):
File > Open of a .nii.gz picks the plugin's OracleMeshLabelMapReader, which reads the labels placed
by the file's sform (converted from NIfTI's RAS to LPS). Writes to fd 1 and ends with os._exit, as
the GUI swallows print() and does not exit by itself."""
import os
import shutil
import tempfile

try:
    from paraview import servermanager
    from paraview.simple import OpenDataFile, Show, Render
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkCommonMath import vtkMatrix4x4
    from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
    from vtkmodules.vtkIOImage import vtkNIFTIImageWriter

    folder = tempfile.mkdtemp()
    path = os.path.join(folder, "labels.nii.gz")
    image = vtkImageData()
    image.SetDimensions(6, 5, 4)
    image.SetSpacing(0.5, 1.0, 2.0)
    labels = vtkUnsignedCharArray()
    labels.SetName("labels")
    for i in range(6 * 5 * 4):
        labels.InsertNextValue(3 if i % 7 == 0 else 0)
    image.GetPointData().SetScalars(labels)
    sform = vtkMatrix4x4()
    for i, v in enumerate((10.0, -20.0, 30.0)):
        sform.SetElement(i, 3, v)
    writer = vtkNIFTIImageWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.SetSFormMatrix(sform)
    writer.Write()

    reader = OpenDataFile(path)
    name = reader.GetXMLName() if reader is not None else None
    if name != "OracleMeshLabelMapReader":
        os.write(1, f"File > Open of a .nii.gz used {name}, not OracleMeshLabelMapReader\n".encode())
        os._exit(1)
    Show(reader)
    Render()
    data = servermanager.Fetch(reader)
    shutil.rmtree(folder, ignore_errors=True)
    got = (data.GetDimensions(), data.GetSpacing(), data.GetOrigin(),
           sum(1 for i in range(data.GetNumberOfPoints()) if data.GetPointData().GetScalars().GetValue(i) == 3))
    expected = ((6, 5, 4), (0.5, 1.0, 2.0), (-10.0, 20.0, 30.0), len(range(0, 120, 7)))
    if got != expected:
        os.write(1, f"the GUI read {got}, expected {expected}\n".encode())
        os._exit(1)
    os.write(1, f"GUI opened {path} with OracleMeshLabelMapReader: {got}\n1 passed, 0 failed\n".encode())
    os._exit(0)
except Exception as e:  # any failure must end the GUI, not leave it hanging
    os.write(1, f"GUI test failed: {e!r}\n".encode())
    os._exit(1)
