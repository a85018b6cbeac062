# SPDX-License-Identifier: GPL-3.0-or-later
"""Client/server: starts a pvserver on a free port, connects pvpython to it, loads the plugin on
the server (LoadPlugin(..., remote=True)), meshes a two-material scene there and fetches the
mesh to the client. The server is always stopped, and every wait has a time limit.
    pvpython pvpython_client_server.py <pvserver executable> <plugin .so>"""
import re
import subprocess
import sys
import threading
import time

pvserver, plugin = sys.argv[1], sys.argv[2]
failures = []


def check(condition, message):
    print(("ok: " if condition else "FAILED: ") + message, flush=True)
    if not condition:
        failures.append(message)


# Port 0: the server picks a free port and prints it ("Accepting connection(s): host:port").
server = subprocess.Popen([pvserver, "--server-port=0", "--hostname=127.0.0.1", "--timeout=5"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
lines, found = [], threading.Event()
port = []


def read_server_output():
    for line in server.stdout:
        lines.append(line.rstrip())
        m = re.search(r"Accepting connection\(s\): .*:(\d+)", line)
        if m and not port:
            port.append(int(m.group(1)))
            found.set()


threading.Thread(target=read_server_output, daemon=True).start()
try:
    if not found.wait(60):
        print("pvserver did not report its port within 60 s:\n" + "\n".join(lines))
        sys.exit(1)
    from paraview import servermanager
    from paraview import simple as pv

    connection = pv.Connect("127.0.0.1", port[0])
    check(connection is not None and servermanager.ActiveConnection.IsRemote(),
          f"connected to pvserver on port {port[0]}")
    pv.LoadPlugin(plugin, remote=True)  # on the server; the proxies come to the client
    inner = pv.SphereDomain(Radius=0.5, MaterialId=2, MaterialName="core")
    outer = pv.SphereDomain(Radius=1.0, MaterialId=1, MaterialName="shell")
    mesher = pv.FeaturePreservingTetrahedralizer(Input=pv.HierarchicalOracle(Input=[inner, outer]))
    mesher.FeatureStrategy = "None"
    mesher.CellSize = mesher.FacetSize = 0.3
    mesher.FacetDistance = 0.02
    mesher.MaterialCriteria = [2, -1, -1, -1, 0.15, -1, -1]
    grid = servermanager.Fetch(mesher)
    check(grid is not None and grid.GetNumberOfCells() > 100,
          f"fetched a mesh of {grid.GetNumberOfCells() if grid else 0} tetrahedra from the server")
    names = grid.GetFieldData().GetAbstractArray("StatisticNames")
    values = grid.GetFieldData().GetArray("StatisticValues")
    stats = {names.GetValue(i): values.GetValue(i) for i in range(names.GetNumberOfValues())}
    import math

    for m, exact in ((2, 4 / 3 * math.pi * 0.5 ** 3), (1, 4 / 3 * math.pi * (1 - 0.5 ** 3))):
        volume = stats.get(f"volume.material_{m}", 0.0)
        # inscribed interface triangles: the volumes come out a little small
        check(abs(volume - exact) < 0.08 * exact, f"material {m}: volume {volume:.4f}, exact {exact:.4f}")
    info = mesher.GetDataInformation()
    check(info.GetNumberOfCells() == grid.GetNumberOfCells(), "the server's data information agrees with the fetched mesh")
    del grid, info
    for proxy in list(pv.GetSources().values()):
        pv.Delete(proxy)
    pv.Disconnect()
finally:
    if server.poll() is None:
        server.terminate()
        try:
            server.wait(10)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait(10)
print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
