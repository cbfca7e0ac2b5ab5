"""The bundled body in a ParaView pipeline, shared by the demo scripts: the mesh, its
collision tables as listed in Data/body_parts.txt, a plain white render view, the
demo's view of a run, and a ParaView state that opens in the GUI as the demo's pictures look."""
import os

from paraview.simple import (AddCameraLink, ColorBy, CreateLayout, CreateView, GetAnimationScene,
                             GetColorTransferFunction, GetScalarBar, LegacyVTKReader, OutputPort, SaveState,
                             SetActiveView, Show)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def body_parts(path=os.path.join(ROOT, "Data", "body_parts.txt")):
    """Data/body_parts.txt: name projection origin(3) axis(3) reference(3) nθ ns hmin hmax maxR."""
    parts = []
    for line in open(path):
        line = line.split("#")[0].split()
        if not line:
            continue
        v = line[2:]
        parts.append(dict(name=line[0], projection=line[1].capitalize(),
                          origin=[float(x) for x in v[0:3]], axis=[float(x) for x in v[3:6]],
                          reference=[float(x) for x in v[6:9]], resolution=[int(v[9]), int(v[10])],
                          heights=[float(v[11]), float(v[12])],
                          max_radius=0.0 if v[13] == "inf" else float(v[13])))
    return parts


def body():
    return LegacyVTKReader(registrationName="body.vtk", FileNames=[os.path.join(ROOT, "Data", "body.vtk")])


def tables(mesh, collision_map):
    """One Cylindrical Collision Map per body part; the head's follows the head's motion.
    `collision_map` is the plugin's proxy constructor (CylindricalCollisionMap)."""
    out = {}
    for part in body_parts():
        out[part["name"]] = collision_map(
            registrationName=f"{part['name']} table", Input=mesh, Projection=part["projection"],
            AutomaticFrame=0, Origin=part["origin"], Axis=part["axis"],
            ReferenceDirection=part["reference"], Resolution=part["resolution"],
            HeightRange=part["heights"], MaximumRadius=part["max_radius"],
            BodyPartName=part["name"], MovesWithHead=1 if part["name"] == "head" else 0)
    return out


# The demo's camera on a full head of hair: behind the left shoulder (+x), a little above the
# head; during the shake the face turns this way, so it is seen in profile and the hair from
# the side and back.
HAIR_CAMERA, HAIR_FOCUS = [0.95, 1.68, -0.45], [0.0, 1.45, 0.0]


def hair_look(view, display, array):
    """The demo's look of rendered hair (Scripts/demo_hair.py, the GUI test's screenshot), on a
    display whose strands are lit (lines given normals, or tubes) and coloured by `array` in
    [0, 1] from root to tip: a warm highlight, dark brown roots to light brown tips, and
    screen-space ambient occlusion over 1 cm in `view`, which darkens the hair between locks
    and curls and under the outer layers. (ParaView's default ambient-occlusion presets scale
    the radius with the whole scene, the body: a grain on the skin and the hair darkened all
    over.)"""
    ColorBy(display, ("POINTS", array))
    display.SetScalarBarVisibility(view, False)
    display.Ambient = 0.15
    display.Diffuse = 0.85
    display.Specular = 0.5
    display.SpecularPower = 20.0
    display.SpecularColor = [1.0, 0.9, 0.75]
    lut = GetColorTransferFunction(array)
    lut.RGBPoints = [0.0, 0.16, 0.10, 0.06, 0.45, 0.42, 0.27, 0.14, 1.0, 0.72, 0.54, 0.34]
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, 1.0)
    view.UseFXAA = 1
    view.UseAmbientOcclusion = 1
    view.UseSSAODefaultPresets = 0
    view.Radius = 0.01
    view.Bias = 0.001
    view.KernelSize = 32
    view.Blur = 1


def white_view(position, focal_point, size=None):
    v = CreateView("RenderView")
    if size:
        v.ViewSize = size
    v.Background = [1, 1, 1]
    try:
        v.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    v.OrientationAxesVisibility = 0
    v.CameraPosition = position
    v.CameraFocalPoint = focal_point
    v.CameraViewUp = [0, 1, 0]
    v.CameraViewAngle = 30
    return v


def hair_view(mesh, sim):
    """The demo's view of a run: the body in skin colour, the guides coloured by speed on a
    fixed 0–1 m/s scale with its bar, seen from behind the left shoulder (500 x 600; the body
    faces +z, so its left is +x)."""
    view = white_view([0.75, 1.75, -0.75], [0.0, 1.45, 0.0], size=[500, 600])
    skin = Show(mesh, view)
    skin.DiffuseColor = [0.87, 0.76, 0.68]
    hair = Show(sim, view)
    hair.LineWidth = 2.0
    ColorBy(hair, ("POINTS", "Speed"))
    lut = GetColorTransferFunction("Speed")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    # The same fixed range for every run (ColorBy may rescale to the data it sees first).
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, 1.0)
    hair.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.Title = "speed (m/s)"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
    return view


# Line colours of the energy chart, one per run (matplotlib's first two).
CHART_COLORS = (["0.12", "0.47", "0.71"], ["0.84", "0.15", "0.16"])


def save_state(path, runs, time):
    """Save a ParaView state that opens in the GUI as the pvpython views look.

    `runs`: (label, render view, Hair Simulation) for one or two runs. pvpython makes views
    but puts them in no layout, and the GUI shows only the views of a layout: a state saved
    as it was opened to an empty tab with nothing drawn (issue 36). Here the runs' views go
    side by side on top of one layout, their cameras linked, and a line chart of their
    kinetic energy (the simulation's Energy output) below; the animation scene steps through
    the runs' frames ('Snap To TimeSteps': the GUI's default is 10 even steps over [0, 1],
    between the frames) and the state opens at `time`."""
    chart = CreateView("XYChartView")
    chart.ChartTitle = "kinetic energy of the guides"
    chart.LeftAxisTitle = "energy (J)"
    chart.BottomAxisTitle = "time (s)"
    for (label, _, sim), color in zip(runs, CHART_COLORS):
        curve = Show(OutputPort(sim, 1), chart, "XYChartRepresentation")
        curve.UseIndexForXAxis = 0
        curve.XArrayName = "Time"
        curve.SeriesVisibility = ["kinetic"]
        curve.SeriesLabel = ["kinetic", f"{label}: kinetic"]
        curve.SeriesColor = ["kinetic"] + color
    views = [view for _, view, _ in runs]
    layout = CreateLayout("Hair")
    layout.SplitVertical(0, 0.62)          # cell 1 on top (the runs), cell 2 below (the chart)
    if len(views) == 1:
        layout.AssignView(1, views[0])
    else:
        layout.SplitHorizontal(1, 0.5)     # cells 3 and 4, left and right
        layout.AssignView(3, views[0])
        layout.AssignView(4, views[1])
        AddCameraLink(views[0], views[1], "cameras of the runs")
    layout.AssignView(2, chart)
    layout.SetSize(1280, 900)
    SetActiveView(views[0])
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.PlayMode = "Snap To TimeSteps"
    scene.AnimationTime = time
    SaveState(path)
    return layout
