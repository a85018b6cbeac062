# SPDX-License-Identifier: GPL-3.0-or-later
"""Renders a sampled oracle image (point array Material) to a PNG, cut open at y = -14 (the demo screw) so the
layers show. Runs under ParaView's pvbatch (needs an X display: use xvfb-run):

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch render.py oracle.vti|mesh.vtu picture.png [names.json]
"""
import json
import sys

try:
    from . import fieldkeys
except ImportError:  # run as a script by pvbatch: the package folder is on sys.path
    import fieldkeys


def render(data_file, png_file, names=None, size=(1200, 900)):
    """Renders a sampled oracle (.vti, point data Material) or a tetrahedral mesh (.vtu, cell data
    Material, drawn with its edges)."""
    from paraview import simple as pv

    mesh = data_file.lower().endswith(".vtu")
    if mesh:
        solid = pv.XMLUnstructuredGridReader(FileName=[data_file])
        association = "CELLS"
    else:
        reader = pv.XMLImageDataReader(FileName=[data_file])
        solid = pv.Threshold(Input=reader)
        solid.Scalars = ["POINTS", fieldkeys.MATERIAL]
        solid.LowerThreshold = 0
        solid.UpperThreshold = 1.0e9
        association = "POINTS"
    cut = pv.Clip(Input=solid)
    cut.ClipType = "Plane"
    cut.ClipType.Origin = [0.0, -14.0, 0.0]  # through the demo screw
    cut.ClipType.Normal = [0.0, -1.0, 0.0]
    cut.Crinkleclip = 1  # whole voxels: the labels stay crisp

    view = pv.CreateView("RenderView")
    view.ViewSize = list(size)
    view.Background = [1.0, 1.0, 1.0]
    view.OrientationAxesVisibility = 1
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = pv.Show(cut, view)
    if mesh:
        display.SetRepresentationType("Surface With Edges")
        display.EdgeColor = [0.2, 0.2, 0.2]
    pv.ColorBy(display, (association, fieldkeys.MATERIAL))
    lut = pv.GetColorTransferFunction(fieldkeys.MATERIAL)
    lut.InterpretValuesAsCategories = 1
    ids = sorted(int(k) for k in (names or {}))
    if ids:
        lut.Annotations = [x for m in ids for x in (str(m), f"{m}: {names[str(m)]}")]
    lut.ApplyPreset("Brewer Qualitative Set1", True)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = fieldkeys.MATERIAL
    bar.TitleColor = [0, 0, 0]
    bar.LabelColor = [0, 0, 0]
    view.CameraPosition = [-160.0, -260.0, 140.0]
    view.CameraFocalPoint = [0.0, 0.0, 50.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    pv.Render(view)
    pv.SaveScreenshot(png_file, view, ImageResolution=list(size))


if __name__ == "__main__":
    names = None
    if len(sys.argv) > 3:
        with open(sys.argv[3]) as f:
            names = json.load(f)
    render(sys.argv[1], sys.argv[2], names)
