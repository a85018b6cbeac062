# SPDX-License-Identifier: GPL-3.0-or-later
"""ParaView readers for label maps (.mha .mhd .nii .nii.gz .nrrd .nhdr .inr .inr.gz), embedded in the
OracleMesh plugin (File > Open). They are the command line's readers (oraclemesh.readers.label_map_reader):
the same origin, spacing, direction and anatomical frame (Space: LPS, the default, or RAS), the
same checks of truncated or oversized files. The oraclemesh package is imported when a file is
read: from PYTHONPATH, else from the site-packages folder next to the plugin
(<lib>/python3.X/site-packages beside <lib>/paraview-plugins/OracleMesh), in the build tree and
installed alike.

The proxy (OracleMeshLabelMapReader: FileName, Space, the ReaderFactory hint with the extensions) is
written in OracleMesh.xml rather than with paraview.util.vtkAlgorithm's decorators: Debian 12's
ParaView 5.11 cannot import that module under Python 3.11 (it imports inspect.getargspec)."""
import os
import sys

from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase

SPACES = ("LPS", "RAS")  # the Space property's values 0 and 1


def _readers():
    """oraclemesh.readers, found on sys.path or next to the loaded plugin."""
    try:
        from oraclemesh import readers
        return readers
    except ImportError:
        pass
    from paraview.modules.vtkRemotingCore import vtkPVPluginTracker

    tracker = vtkPVPluginTracker.GetInstance()
    version = f"python{sys.version_info.major}.{sys.version_info.minor}"
    for i in range(tracker.GetNumberOfPlugins()):
        path = tracker.GetPluginFileName(i) or ""
        if tracker.GetPluginName(i) != "OracleMesh" or not path:
            continue
        lib = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(path))))
        site = os.path.join(lib, version, "site-packages")
        if os.path.isdir(os.path.join(site, "oraclemesh")) and site not in sys.path:
            sys.path.append(site)
    from oraclemesh import readers
    return readers


def _errors():
    """oraclemesh.errors (found as _readers() finds the package)."""
    _readers()
    from oraclemesh import errors
    return errors


class OracleMeshLabelMapReader(VTKPythonAlgorithmBase):
    """A label map placed as `oraclemesh mesh` places it: vtkImageData with origin, spacing and
    direction in the scene's frame (Space)."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1, outputType="vtkImageData")
        self._filename = None
        self._space = 0
        self._reader = None

    def SetFileName(self, name):
        if name != self._filename:
            self._filename = name
            self._reader = None
            self.Modified()

    def SetSpace(self, value):
        value = int(value)
        if value != self._space:
            self._space = value
            self._reader = None
            self.Modified()

    def _get_reader(self):
        if self._reader is None:
            if not self._filename:
                raise RuntimeError("no file name set")
            self._reader = _readers().label_map_reader(self._filename, SPACES[self._space])
        return self._reader

    def _fail(self, error):
        from vtkmodules.vtkCommonCore import vtkOutputWindow

        vtkOutputWindow.GetInstance().DisplayErrorText(f"OracleMesh Label Map Reader: {error}\n")
        return 0

    def RequestInformation(self, request, inInfo, outInfo):
        from vtkmodules.vtkCommonDataModel import vtkDataObject
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp

        try:
            reader = self._get_reader()
            # the reader's own first error, named (not VTK's "Failure when calling ProcessRequest")
            _errors().update_information(reader, warnings=[])
        except Exception as e:  # OracleMeshError names the file and the problem
            self._reader = None
            return self._fail(e)
        source, info = reader.GetOutputInformation(0), outInfo.GetInformationObject(0)
        for key in (sddp.WHOLE_EXTENT(), vtkDataObject.ORIGIN(), vtkDataObject.SPACING(),
                    vtkDataObject.DIRECTION()):
            if source.Has(key):
                info.CopyEntry(source, key)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        from vtkmodules.vtkCommonDataModel import vtkImageData

        try:
            image = _errors().update(self._get_reader(), warnings=[])
        except Exception as e:
            return self._fail(e)
        if image is None or image.GetNumberOfPoints() == 0:
            return self._fail(f"{self._filename}: no image read")
        vtkImageData.GetData(outInfo).ShallowCopy(image)
        return 1
