# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython door of test_doors.py: a scene built from the plugin's proxies by
Data/make_demo_state.build_pipeline (only the keys the scene gives are set), meshed on the server,
fetched and written as .vtu; or, with --expect-error, the update's error printed.
    pvpython pvpython_doors.py <plugin .so> <Data folder> <scene.json> <out.vtu>"""
import os
import sys

from paraview import servermanager
from paraview import simple as pv

plugin, data, scene_file, out = sys.argv[1:5]
pv.LoadPlugin(plugin, remote=False)
sys.path.insert(0, os.path.abspath(data))
import make_demo_state  # noqa: E402

proxies, scene = make_demo_state.build_pipeline(scene_file)
grid = servermanager.Fetch(proxies["Tetrahedralizer"])
if grid is None or grid.GetNumberOfCells() == 0:
    print("no mesh")
    sys.exit(1)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter  # noqa: E402

writer = vtkXMLUnstructuredGridWriter()
writer.SetInputData(grid)
writer.SetFileName(out)
writer.SetDataModeToBinary()
sys.exit(0 if writer.Write() else 1)
