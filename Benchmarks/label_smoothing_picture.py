#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The demo's tibia label map meshed with Trilinear and with Smooth interpolation, cut open, side by
side: the picture in docs/REFERENCE.md (label maps).

    PYTHONPATH=build/lib/python3.11/site-packages \\
        python3 Benchmarks/label_smoothing_picture.py --work build/label_picture --out docs/images/tibia_smooth.png

Meshes with the oraclemesh package (criteria fine enough to show the interfaces: facet size 1 mm,
facet distance 0.1 mm), renders each mesh cut open at y = 0 with pvbatch under xvfb-run, and joins
the two pictures (Trilinear left, Smooth right) with VTK's image filters.
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Data", "demo")

RENDER = r'''
import sys
from paraview import simple as pv
mesh, png, title = sys.argv[1:4]
reader = pv.XMLUnstructuredGridReader(FileName=[mesh])
cut = pv.Clip(Input=reader)
cut.ClipType = "Plane"
cut.ClipType.Origin = [0.0, 0.0, 0.0]
cut.ClipType.Normal = [0.0, -1.0, 0.0]
cut.Crinkleclip = 1
view = pv.CreateView("RenderView")
view.ViewSize = [640, 640]
view.Background = [1.0, 1.0, 1.0]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
display = pv.Show(cut, view)
display.SetRepresentationType("Surface With Edges")
display.EdgeColor = [0.25, 0.25, 0.25]
pv.ColorBy(display, ("CELLS", "Material"))
lut = pv.GetColorTransferFunction("Material")
lut.InterpretValuesAsCategories = 1
lut.Annotations = ["1", "cortical bone", "2", "cancellous bone"]
lut.IndexedColors = [0.89, 0.45, 0.2, 0.98, 0.85, 0.55]
text = pv.Text(Text=title)
t = pv.Show(text, view)
t.FontSize = 22
t.Color = [0, 0, 0]
t.WindowLocation = "Upper Center"
view.CameraPosition = [-10.0, -120.0, 30.0]
view.CameraFocalPoint = [-10.0, 0.0, 30.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.CameraParallelProjection = 1
view.CameraParallelScale = 22.0
pv.Render(view)
pv.SaveScreenshot(png, view, ImageResolution=[640, 640])
'''


def mesh(interpolation, work):
    scene = {
        "domains": [{"name": "tibia", "type": "labelmap", "file": os.path.abspath(os.path.join(DATA, "tibia_labels.vti")),
                     "array": "labels", "label_names": {"1": "cortical bone", "2": "cancellous bone"},
                     "interpolation": interpolation}],
        "mesh": {"criteria": {"facet_angle": 25, "cell_radius_edge_ratio": 2.0, "cell_size": 2.0, "facet_size": 1.0,
                              "facet_distance": 0.1}},
    }
    path = os.path.join(work, f"tibia_{interpolation}.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    out = os.path.join(work, f"tibia_{interpolation}.vtu")
    subprocess.run([sys.executable, "-m", "oraclemesh", "mesh", path, "-o", out], check=True,
                   stdout=subprocess.DEVNULL)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    script = os.path.join(args.work, "render_cut.py")
    with open(script, "w") as f:
        f.write(RENDER)
    pictures = []
    for interpolation, title in (("trilinear", "Trilinear (as CGAL 5.5)"), ("smooth", "Smooth (default)")):
        vtu = mesh(interpolation, args.work)
        png = os.path.join(args.work, f"tibia_{interpolation}.png")
        subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "pvbatch", script, vtu, png, title],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        pictures.append(png)
    from vtkmodules.vtkFiltersCore import vtkImageAppend
    from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
    append = vtkImageAppend()
    append.SetAppendAxis(0)
    for png in pictures:
        r = vtkPNGReader()
        r.SetFileName(png)
        r.Update()
        append.AddInputData(r.GetOutput())
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    w = vtkPNGWriter()
    w.SetFileName(args.out)
    w.SetInputConnection(append.GetOutputPort())
    w.Write()
    print("wrote", args.out)


if __name__ == "__main__":
    main()
