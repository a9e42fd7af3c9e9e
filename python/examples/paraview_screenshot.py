"""The ParaView picture of docs/output.md: the demo's last snapshot, floes
coloured by speed, walls grey, contacts as lines coloured by their normal
force, from the XDMF description `floe export --xdmf` writes. Run with
ParaView's Python (`make paraview`; under Xvfb without a display):

    floe run scenarios/demo.toml -o demo.h5 --xdmf
    xvfb-run -a pvpython python/examples/paraview_screenshot.py demo.xdmf docs/figures/paraview-demo.png
"""

import sys

from paraview.simple import (ColorBy, CreateView, ExtractBlock, GetColorTransferFunction,
                             GetScalarBar, ResetCamera, SaveScreenshot, Show, XDMFReader)

reader = XDMFReader(FileNames=[sys.argv[1]])
reader.UpdatePipelineInformation()
view = CreateView("RenderView")
view.ViewSize = [1200, 700]
view.Background = [1, 1, 1]
if hasattr(view, "UseColorPaletteForBackground"):
    view.UseColorPaletteForBackground = 0
view.OrientationAxesVisibility = 0
view.ViewTime = reader.TimestepValues[-1]
view.InteractionMode = "2D"


def block(name):
    b = ExtractBlock(Input=reader)
    b.Selectors = [f"/Root/{name}"]
    return Show(b, view)


def colour(display, array, preset, title, position=None):
    ColorBy(display, ("CELLS", array, "Magnitude") if array == "velocity" else ("CELLS", array))
    lut = GetColorTransferFunction(array)
    lut.ApplyPreset(preset, True)
    display.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = title, ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    if position:
        bar.WindowLocation, bar.Position = "Any Location", position


colour(block("floes"), "velocity", "Viridis (matplotlib)", "floe speed, m/s")
walls = block("walls")
walls.ColorArrayName = ["POINTS", ""]
walls.DiffuseColor = walls.AmbientColor = [0.6, 0.6, 0.6]
contacts = block("contacts")
contacts.LineWidth = 2.0
colour(contacts, "normal_force", "Reds", "contact normal force, N", [0.02, 0.1])
ResetCamera(view)
SaveScreenshot(sys.argv[2], view, ImageResolution=[1200, 700])
