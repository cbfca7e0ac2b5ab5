"""The bundled body in a ParaView pipeline, shared by the demo scripts: the mesh, its
collision tables as listed in Data/body_parts.txt, and a plain white render view."""
import os

from paraview.simple import CreateView, LegacyVTKReader

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
