# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by pvpython (Testing/Python/test_paraview_readers.py): loads the plugin, asks ParaView's reader
factory which readers File > Open offers for each file, opens each through the plugin's
OracleMeshLabelMapReader and writes what it read as JSON.
    pvpython pvpython_readers.py <OracleMesh.so> <out.json> <file>[:<space>]...
The environment may lack oraclemesh on PYTHONPATH: the reader then finds the package next to the plugin."""
import json
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin

plugin, out, files = sys.argv[1], sys.argv[2], sys.argv[3:]
LoadPlugin(plugin, remote=False, ns=globals())
factory = servermanager.vtkSMProxyManager.GetProxyManager().GetReaderFactory()
session = servermanager.ActiveConnection.Session
results = {}
for item in files:
    path, _, space = item.partition(":")
    offered = factory.GetReaders(path, session)  # by extension: the choice File > Open offers
    readers = [offered.GetString(i + 1) for i in range(0, offered.GetNumberOfStrings(), 3)]
    default = factory.GetReaderName() if factory.CanReadFile(path, session) else None
    reader = OracleMeshLabelMapReader(FileName=path)  # noqa: F821 - defined by LoadPlugin
    if space:
        reader.Space = space
    image = servermanager.Fetch(reader)
    scalars = image.GetPointData().GetScalars()
    results[item] = {
        "offered": readers,
        "default": default,
        "dimensions": list(image.GetDimensions()),
        "spacing": list(image.GetSpacing()),
        "origin": list(image.GetOrigin()),
        "direction": [image.GetDirectionMatrix().GetElement(i, j) for i in range(3) for j in range(3)],
        "array": scalars.GetName() if scalars else None,
        "labels": [scalars.GetTuple1(i) for i in range(scalars.GetNumberOfTuples())] if scalars else None,
    }
with open(out, "w") as f:
    json.dump(results, f)
print(f"read {len(results)} files through OracleMeshLabelMapReader")
