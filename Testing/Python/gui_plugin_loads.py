# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by the ParaView GUI (under Xvfb) with PV_PLUGIN_PATH pointing at the plugin: the plugin
must be auto-loaded and its proxies usable. The GUI swallows print() and does not exit by itself,
so this writes to fd 1 and ends with os._exit."""
import os

try:
    from paraview import servermanager
    from paraview.simple import *  # noqa: F401,F403

    pxm = servermanager.ProxyManager().SMProxyManager
    names = [("sources", "OracleMeshSphereDomain"), ("sources", "OracleMeshImplicitDomain"),
             ("filters", "OracleMeshSurfaceDomain"), ("filters", "OracleMeshLabelMapDomain"),
             ("filters", "OracleMeshHierarchicalOracle"), ("filters", "OracleMeshOracleSampler")]
    missing = [n for g, n in names if pxm.GetPrototypeProxy(g, n) is None]
    if missing:
        os.write(1, f"plugin proxies missing in the GUI: {missing}\n".encode())
        os._exit(1)
    sphere = SphereDomain()  # noqa: F405 - created from the plugin's XML label
    sphere.Radius = 3.0
    oracle = HierarchicalOracle(Input=[sphere])  # noqa: F405
    sampler = OracleSampler(Input=oracle)  # noqa: F405
    sampler.Dimensions = [16, 16, 16]
    Show(sampler)  # noqa: F405
    Render()  # noqa: F405
    data = servermanager.Fetch(sampler)
    inside = sum(1 for i in range(data.GetNumberOfPoints())
                 if data.GetPointData().GetArray("Material").GetValue(i) == 1)
    if inside == 0:
        os.write(1, b"sampling in the GUI found no material\n")
        os._exit(1)
    os.write(1, f"GUI loaded the plugin; {inside} samples inside the sphere\n1 passed, 0 failed\n".encode())
    os._exit(0)
except Exception as e:  # any failure must end the GUI, not leave it hanging
    os.write(1, f"GUI test failed: {e!r}\n".encode())
    os._exit(1)
