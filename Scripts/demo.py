"""Part of the main job: collision tables of the bundled head and trunk, and a picture.

Run through Scripts/demo.sh, or:
  xvfb-run -a pvpython Scripts/demo.py build/lib/paraview-5.11/plugins/HairDynamics/HairDynamics.so Output
Writes Output/collision_tables.png and prints a summary.
"""
import os
import sys
import time

from paraview.simple import (AssignViewToLayout, ColorBy, CreateLayout, GetColorTransferFunction,
                             GetScalarBar, LoadPlugin, SaveScreenshot, Show, UpdatePipeline,
                             servermanager)

import bundled

plugin, outdir = sys.argv[1], sys.argv[2]
os.makedirs(outdir, exist_ok=True)
LoadPlugin(plugin, remote=False, ns=globals())

mesh = bundled.body()
overlay = bundled.white_view([1.0, 1.7, 1.2], [0.0, 1.28, 0.0])
tables_only = bundled.white_view([1.0, 1.7, 1.2], [0.0, 1.28, 0.0])

# Left: the body with the tables' sample grids over it (where the grid leaves the skin, the
# table departs from the mesh). Right: the surfaces the tables represent, by radius.
layout = CreateLayout("collision tables")
layout.SplitHorizontal(0, 0.5)
AssignViewToLayout(view=overlay, layout=layout, hint=1)
AssignViewToLayout(view=tables_only, layout=layout, hint=2)
skin = Show(mesh, overlay)
skin.DiffuseColor = [0.87, 0.76, 0.68]
lut = GetColorTransferFunction("Radius")
lut.ApplyPreset("Cool to Warm", True)
lut.RescaleTransferFunction(0.0, 0.3)
lut.AutomaticRescaleRangeMode = "Never"

print(f"{'part':<8}{'projection':<13}{'table':>9}{'rays hit':>10}{'radius range (m)':>20}{'time (s)':>10}")
parts = {p["name"]: p for p in bundled.body_parts()}
for name, table in bundled.tables(mesh, CylindricalCollisionMap).items():  # noqa: F821
    part = parts[name]
    start = time.time()
    UpdatePipeline(proxy=table)
    elapsed = time.time() - start
    image = servermanager.Fetch(table, None, None, 0)
    hit = image.GetPointData().GetArray("Hit")
    radius = image.GetPointData().GetArray("Radius")
    n = hit.GetNumberOfTuples()
    hits = sum(hit.GetValue(i) for i in range(n))
    radii = [radius.GetValue(i) for i in range(n) if hit.GetValue(i)]
    print(f"{part['name']:<8}{part['projection'].lower():<13}{'%dx%d' % tuple(part['resolution']):>9}"
          f"{hits:>6}/{n:<4}{min(radii):>9.3f} - {max(radii):.3f}{elapsed:>10.2f}")
    grid = Show(servermanager.OutputPort(table, 1), overlay)
    grid.SetRepresentationType("Wireframe")
    ColorBy(grid, ("POINTS", "Radius"))
    surface = Show(servermanager.OutputPort(table, 1), tables_only)
    ColorBy(surface, ("POINTS", "Radius"))

bar = GetScalarBar(lut, tables_only)
bar.Title = "table radius (m)"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.TitleFontSize = 10
bar.LabelFontSize = 9
bar.ScalarBarLength = 0.4
bar.WindowLocation = "Any Location"
bar.Orientation = "Horizontal"
bar.Position = [0.35, 0.04]
bar.RangeLabelFormat = "%.2f"
bar.Visibility = 1
png = os.path.join(outdir, "collision_tables.png")
SaveScreenshot(png, layout, ImageResolution=[1600, 900])
print(f"picture: {png}")
