"""The picture of docs/hair-simulation.md#display-resolution: one curly guide at rest in its
natural shape, drawn by Hair Simulation at 4 points per element (left) and at the default
16 (right), points marked.

  xvfb-run -a -s "-screen 0 1280x1024x24" pvpython Scripts/guide_resolution.py \
      build/lib/paraview-5.11/plugins/HairDynamics/HairDynamics.so docs/images/guide-resolution.png
"""
import os
import sys

from paraview.simple import (AssignViewToLayout, CreateLayout, LoadPlugin, PassArrays,
                             SaveScreenshot, Show, Text, servermanager)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundled  # noqa: E402

plugin, png = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())

body = bundled.body()
guides = HairStrands(Input=body, NumberOfStrands=1, NumberOfElements=10, StrandLength=0.3,  # noqa: F821
                     HairType="Curly (Caucasian 2)", Seed=3)
layout = CreateLayout("guide resolution")
layout.SplitHorizontal(0, 0.5)
for hint, per in ((1, 4), (2, 16)):
    sim = HairSimulation(Input=guides, Duration=0, PointsPerElement=per)  # noqa: F821
    sim.UpdatePipeline(0.0)
    strand = servermanager.Fetch(sim)
    b = strand.GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    view = bundled.white_view([centre[0] + 1.9 * size, centre[1] + 0.3 * size, centre[2] + 1.9 * size],
                              centre, size=[800, 900])
    AssignViewToLayout(view=view, layout=layout, hint=hint)
    line = Show(sim, view)
    line.ColorArrayName = [None, ""]
    line.DiffuseColor = [0.35, 0.2, 0.1]
    line.AmbientColor = [0.35, 0.2, 0.1]
    line.LineWidth = 2.5
    dots = Show(PassArrays(Input=sim), view)  # a second representation: the points
    dots.SetRepresentationType("Points")
    dots.ColorArrayName = [None, ""]
    dots.DiffuseColor = [0.85, 0.3, 0.1]
    dots.AmbientColor = [0.85, 0.3, 0.1]
    dots.PointSize = 5
    dots.RenderPointsAsSpheres = 1
    label = Text(Text=f"{per} points per element: {strand.GetNumberOfPoints()} points")
    shown = Show(label, view)
    shown.Color = [0, 0, 0]
    shown.FontSize = 14
    shown.WindowLocation = "Upper Center"
SaveScreenshot(png, layout, ImageResolution=[1600, 900])
print("wrote", png)
