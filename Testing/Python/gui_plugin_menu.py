#!/usr/bin/env python3
"""The plugin in the ParaView GUI, under Xvfb: ParaView starts with the plugin on
PV_PLUGIN_PATH, its proxies are registered (checked from the GUI's own Python with
--script), and a screenshot of Filters > Hair is left in the test output; then the same
script builds a full head of rendered hair in the GUI (body, guides, a second of the shake,
Hair Interpolation) and a screenshot of the window is left too (gui_rendered_head.png).

Usage: gui_plugin_menu.py <HairDynamics.so> <output folder>
"""
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import start as start_xvfb, stop as stop_xvfb  # noqa: E402

plugin, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for tool in ("Xvfb", "paraview", "xdotool", "import"):
    if not shutil.which(tool):
        sys.exit(f"{tool} is missing: Scripts/install-deps.sh installs it")

tmp = tempfile.mkdtemp()
marker = os.path.join(tmp, "proxies.txt")
rendered = os.path.join(tmp, "rendered.txt")
body_file = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data", "body.vtk")
scripts = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Scripts"))
check = os.path.join(tmp, "check.py")
with open(check, "w") as f:
    f.write(f"""
from paraview import servermanager
pxm = servermanager.ProxyManager()
found = [name for group, name in (("filters", "CylindricalCollisionMap"), ("filters", "HairStrands"),
         ("filters", "HairSimulation"), ("filters", "HairAnalysis"), ("sources", "HairStateReader"),
         ("filters", "HairInterpolation"))
         if pxm.GetPrototypeProxy(group, name) is not None]
open({marker!r}, "w").write(" ".join(found))
from paraview.simple import (GetActiveViewOrCreate, GetAnimationScene, HairInterpolation, HairSimulation,
                             HairStrands, LegacyVTKReader, Render, Show)
import sys
sys.path.insert(0, {scripts!r})
import bundled
body = LegacyVTKReader(registrationName="body", FileNames=[{os.path.abspath(body_file)!r}])
guides = HairStrands(registrationName="guides", Input=body, NumberOfStrands=200, StrandLength=0.3,
                     HairType="Wavy (Caucasian 1)", Growth="Combed", CombDirection=[0, -1, -0.3],
                     CombWeight=0.35)
sim = HairSimulation(registrationName="simulation", Input=guides, Duration=1.0,
                     BodyMotion="Shake", MotionAmplitude=0.5)
hair = HairInterpolation(registrationName="rendered hair", Input=sim, Scalp=body, NumberOfStrands=30000)
view = GetActiveViewOrCreate("RenderView")
skin = Show(body, view)
skin.DiffuseColor = [0.87, 0.76, 0.68]
shown = Show(hair, view)
# The look of Scripts/demo_hair.py (Scripts/bundled.py's hair_look) on lit tubes: lines have no
# normals and are drawn unlit. Tubes coloured through a texture (scalars interpolated before
# mapping) are drawn behind the body in ParaView 5.11: colours are interpolated after.
shown.RenderLinesAsTubes = 1
shown.LineWidth = 2.0
shown.InterpolateScalarsBeforeMapping = 0
bundled.hair_look(view, shown, "ArcParameter")
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = 1.0
Render(view)
view.CameraPosition = bundled.HAIR_CAMERA
view.CameraFocalPoint = bundled.HAIR_FOCUS
view.CameraViewUp = [0, 1, 0]
Render(view)
data = hair.GetClientSideObject().GetOutputDataObject(0)
open({rendered!r}, "w").write(str(data.GetNumberOfLines()))
""")

xvfb, display = start_xvfb("1400x900x24")
env = dict(os.environ, DISPLAY=display, PV_PLUGIN_PATH=os.path.dirname(os.path.abspath(plugin)))
log = open(os.path.join(out, "paraview_gui.log"), "w")
gui = subprocess.Popen(["paraview", "--dr", f"--script={check}"], env=env, stdout=log, stderr=log)
failures = []
try:
    window = ""
    deadline = time.time() + 120
    while time.time() < deadline and not window:
        time.sleep(1)
        window = subprocess.run(["xdotool", "search", "--name", "^ParaView"], env=env,
                                capture_output=True, text=True).stdout.strip()
    if not window:
        failures.append("the ParaView window did not appear within 120 s")
    deadline = time.time() + 60
    while time.time() < deadline and not os.path.exists(marker):
        time.sleep(1)
    found = open(marker).read().split() if os.path.exists(marker) else []
    for name in ("CylindricalCollisionMap", "HairStrands", "HairSimulation", "HairAnalysis",
                 "HairStateReader", "HairInterpolation"):
        if name not in found:
            failures.append(f"proxy {name} is not registered in the GUI")
    # Filters > Hair: open the Filters menu, then hover its Hair entry (positions of this
    # ParaView build's menu at 1400 x 900); the screenshot is for people to look at.
    time.sleep(2)
    subprocess.run(["xdotool", "mousemove", "215", "10", "click", "1"], env=env)
    time.sleep(1)
    subprocess.run(["xdotool", "mousemove", "240", "280", "sleep", "0.3", "mousemove", "245", "286", "click", "1"], env=env)
    time.sleep(1.5)
    shot = os.path.join(out, "gui_filters_hair.png")
    subprocess.run(["import", "-window", "root", shot], env=env)
    if not os.path.exists(shot):
        failures.append("no screenshot")
    # Close the menus, wait for the rendered head, and take the window as it is.
    subprocess.run(["xdotool", "key", "Escape", "key", "Escape"], env=env)
    deadline = time.time() + 180
    while time.time() < deadline and not os.path.exists(rendered):
        time.sleep(1)
    lines = open(rendered).read().strip() if os.path.exists(rendered) else ""
    if lines != "30000":
        failures.append(f"the GUI's Hair Interpolation gave {lines or 'nothing'} instead of 30000 strands")
    time.sleep(3)
    head_shot = os.path.join(out, "gui_rendered_head.png")
    subprocess.run(["import", "-window", "root", head_shot], env=env)
finally:
    gui.kill()
    gui.wait()
    stop_xvfb(xvfb)
    log.close()
errors = [line for line in open(os.path.join(out, "paraview_gui.log")) if "HairDynamics" in line and "rror" in line]
if errors:
    failures.append("ParaView reported errors about the plugin: " + errors[0].strip())
for f in failures:
    print("FAIL " + f)
print(f"screenshots: {os.path.join(out, 'gui_filters_hair.png')}, {os.path.join(out, 'gui_rendered_head.png')}")
print(f"{6 - len([f for f in failures if 'proxy' in f])} of 6 proxies registered in the GUI")
sys.exit(1 if failures else 0)
