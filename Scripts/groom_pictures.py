"""The pictures of docs/study-groom.md: a groom of the bundled body (200 guides shaken 0.5 s,
that frame given back as guide curves) at t = 0 and after 10 s with the body still, made
sag-free and as grown, side by side, one picture per model. The strands come from the study's
curves file (Scripts/study_groom.py writes it), coloured by what became of them: held strands
brown, those no natural shape can hold (started in their closest stable shape) blue.

  /usr/bin/python3 Scripts/study_groom.py build/bin/groom_study Output/study_groom
  xvfb-run -a -s "-screen 0 1280x1024x24" pvpython Scripts/groom_pictures.py \
      Output/study_groom docs/images wavy
"""
import csv
import os
import sys

from paraview import servermanager
from paraview.simple import (AssignViewToLayout, ColorBy, CreateLayout, GetColorTransferFunction,
                             SaveScreenshot, Show, Text)
from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bundled  # noqa: E402

study, outdir, preset = sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else "wavy"
rows = list(csv.DictReader(open(os.path.join(study, "study_groom.csv"))))
status = {(r["model"], int(r["strand"])): int(r["rest_status"]) for r in rows if r["preset"] == preset}
curves = {}
for r in csv.DictReader(open(os.path.join(study, "study_groom_curves.csv"))):
    if r["preset"] != preset:
        continue
    key = (r["model"], r["frame"])
    curves.setdefault(key, {}).setdefault(int(r["strand"]), []).append(
        (float(r["x"]), float(r["y"]), float(r["z"])))


def polylines(model, frame):
    pts, lines, held = vtkPoints(), vtkCellArray(), vtkIntArray()
    held.SetName("held")
    for k, line in sorted(curves[(model, frame)].items()):
        ids = [pts.InsertNextPoint(p) for p in line]
        lines.InsertNextCell(len(ids), ids)
        held.InsertNextValue(1 if status.get((model, k)) == 1 else 0)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetLines(lines)
    pd.GetCellData().AddArray(held)
    source = servermanager.sources.TrivialProducer()
    source.GetClientSideObject().SetOutput(pd)
    return source


body = bundled.body()
for model in ("super-helix", "projective"):
    if (model, "groom") not in curves:
        continue
    layout = CreateLayout(f"groom {model}")
    layout.SplitHorizontal(0, 1 / 3)
    layout.SplitHorizontal(2, 0.5)
    n = len(curves[(model, "groom")])
    held = sum(1 for (m, _), s in status.items() if m == model and s == 1)
    for hint, frame, title in ((1, "groom", f"the groom, t = 0 ({n} guides)"),
                               (5, "sag_free_end", f"sag-free, 10 s ({held} held, brown)"),
                               (6, "as_grown_end", "as grown, 10 s")):
        view = bundled.white_view([0.62, 1.62, 0.85], [0, 1.48, 0.02], size=[600, 800])
        AssignViewToLayout(view=view, layout=layout, hint=hint)
        skin = Show(body, view)
        skin.DiffuseColor = [0.93, 0.85, 0.78]
        skin.AmbientColor = [0.93, 0.85, 0.78]
        strands = Show(polylines(model, frame), view)
        ColorBy(strands, ("CELLS", "held"))
        strands.SetScalarBarVisibility(view, False)
        lut = GetColorTransferFunction("held")
        lut.RGBPoints = [0, 0.2, 0.35, 0.75, 1, 0.45, 0.25, 0.1]
        lut.ColorSpace = "RGB"
        strands.LineWidth = 1.5
        label = Text(Text=title)
        shown = Show(label, view)
        shown.Color = [0, 0, 0]
        shown.FontSize = 14
        shown.WindowLocation = "Upper Center"
    png = os.path.join(outdir, f"groom-{model}.png")
    SaveScreenshot(png, layout, ImageResolution=[1800, 800])
    print("wrote", png)
