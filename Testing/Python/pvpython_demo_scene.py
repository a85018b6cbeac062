# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: the demo scene clicked together from the plugin's proxies (as in the GUI), sampled on
the server and fetched; the counts must equal the C++ pipeline's.
    pvpython pvpython_demo_scene.py <plugin .so> <Data folder>"""
import os
import sys

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from demo_counts import SAMPLES, counts_of, reference_counts  # noqa: E402

plugin, data = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
demo = os.path.join(data, "demo")

implant_file = XMLPolyDataReader(FileName=[os.path.join(demo, "implant.vtp")])
implant = SurfaceDomain(Input=implant_file)
implant.MaterialId = 3
implant.MaterialName = "implant"

screw = ImplicitDomain()
screw.Shape = "Cylinder"
screw.Shape.Center = [-15.0, -14.0, 66.0]
screw.Shape.Axis = [0.1, 0.05, 1.0]
screw.Shape.Radius = 2.5
screw.Height = 34.0
screw.Cut = 0
screw.MaterialId = 4
screw.MaterialName = "screw"

resection = ImplicitDomain()
resection.Shape = "Plane"
resection.Shape.Origin = [0.0, 0.0, 80.0]
resection.Shape.Normal = [0.0, 0.0, -1.0]
resection.Cut = 1
resection.MaterialName = "resection"

tibia_file = XMLImageDataReader(FileName=[os.path.join(demo, "tibia_labels.vti")])
tibia = LabelMapDomain(Input=tibia_file)
tibia.LabelArray = ["POINTS", "labels"]
tibia.LabelNames = ["1", "cortical bone", "2", "cancellous bone"]

oracle = HierarchicalOracle(Input=[implant, screw, resection, tibia])
sampler = OracleSampler(Input=oracle)
sampler.Dimensions = [SAMPLES, SAMPLES, SAMPLES]
image = servermanager.Fetch(sampler)
counts = counts_of(image.GetPointData().GetArray("Material"))
expected = reference_counts()
print("pvpython counts:", counts)
if counts != expected:
    print("MISMATCH with the C++ pipeline:", expected)
    sys.exit(1)

# The tetrahedralizer proxy meshes a small oracle on the server.
ball = SphereDomain()
ball.Radius = 1.0
mesher = FeaturePreservingTetrahedralizer(Input=HierarchicalOracle(Input=[ball]))
mesher.FeatureStrategy = "None"
mesher.CellSize = 0.3
grid = servermanager.Fetch(mesher)
if grid.GetNumberOfCells() < 100 or grid.GetCellData().GetArray("Material") is None:
    print("the tetrahedralizer proxy produced no mesh")
    sys.exit(1)

# Oracle Feature Lines shows the rim where the resection plane cuts a ball (issue 13), and the
# tetrahedralizer's Features property keeps it.
rim_cut = ImplicitDomain()
rim_cut.Shape = "Plane"
rim_cut.Shape.Origin = [0.0, 0.0, 0.5]
rim_cut.Shape.Normal = [0.0, 0.0, -1.0]
rim_cut.Cut = 1
rim_oracle = HierarchicalOracle(Input=[rim_cut, ball])
lines = servermanager.Fetch(OracleFeatureLines(Input=rim_oracle))
if lines.GetNumberOfLines() != 1 or any(abs(lines.GetPoint(i)[2] - 0.5) > 1e-6 for i in range(lines.GetNumberOfPoints())):
    print("Oracle Feature Lines did not give the rim at z = 0.5:", lines.GetNumberOfLines(), "lines")
    sys.exit(1)
kept = FeaturePreservingTetrahedralizer(Input=rim_oracle)
kept.Features = "Automatic"
kept.CellSize = 0.3
kept.FacetSize = 0.3
segments = servermanager.Fetch(kept, idx=2)
if segments.GetNumberOfCells() < 10:
    print("Features = Automatic kept no rim:", segments.GetNumberOfCells(), "segments")
    sys.exit(1)
print("3 passed, 0 failed")
