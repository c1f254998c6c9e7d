#!/usr/bin/env python3
"""Makes the pictures of the README and of Documentation/ (this folder's PNGs).

Every picture but soft.png and ambient.png comes from the shipped CT head (Data/headsq.vti)
or a generated phantom, so any clone with a build can remake them; soft.png and ambient.png
need the engine of ../shared/data beside the clone:

  hero.png          the demo (`./setup.sh demo`): the head lit by a warm point light and a
                    blue directional light, beside local shading
  gui.png           ParaView with the head as Illuminated Volume, the Properties panel at
                    its Illumination group and the Light Inspector
  propagation.png   Multi-Light Propagation: three spheres under a yellow and a blue point
                    light and a red spot light (the scene of the selective-updates paper)
  filtered.png      Filtered Shadows: the chirp phantom's shadow with filter width 0 and 9
  soft.png          Filtered Shadows from a directional light 0, 5 and 15 degrees across
                    (Shadow Radius) on the engine
  ambient.png       the engine under one directional light, without and with ambient
                    occlusion (an ambient light through the local transmittance)
  unstructured.png  the two-level solver on a tetrahedral mesh made from the head

Usage, from anywhere (python3, no display needed):

    python3 Documentation/images/make_images.py [--build BUILD] [--only NAME ...]

It needs the build (volillum-render, the plugin), ParaView's `pvpython` and `paraview` on
PATH, `xvfb-run` and `Xvfb`, and for gui.png `xdotool` and ImageMagick (`import`,
`convert`): `apt-get install xvfb xdotool imagemagick`. gui.png is taken by clicking the
GUI at fixed places of a 1600x1000 screen; look at it after a ParaView upgrade.
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
HEAD = os.path.join(ROOT, "Data", "headsq.vti")
DEMO = os.path.join(ROOT, "Data", "demo.json")
HEAD_MAX = 3926  # the head's largest scalar (Data/README.md)
# The engine of ../shared/data (DATASETS.md), beside the clone as in CI.
ENGINE = os.path.join(os.path.dirname(ROOT), "shared", "data", "volumes", "engine.vti")


def run(*command, **kwargs):
    print("$ " + " ".join(command), flush=True)
    subprocess.run(command, check=True, **kwargs)


def render(cli, args, output):
    run("xvfb-run", "-a", cli, *args, "--output", output)


def write_json(path, settings):
    with open(path, "w") as f:
        json.dump(settings, f, indent=1)
    return path


def hero(cli, tmp):
    render(cli, [HEAD, "--config", DEMO], os.path.join(HERE, "hero.png"))


def propagation(cli, tmp):
    settings = json.load(open(os.path.join(ROOT, "Testing", "Data", "three_spheres.json")))
    settings.update(image_size=[480, 480], ambient=0.1,
                    camera={"azimuth": 20, "elevation": 40, "zoom": 1.3})
    settings["lights"].append({"type": "spot", "position": [0.5, 1.6, 1.2],
                               "focal_point": [0.5, 0.5, 0.5], "relative": True,
                               "color": [1.0, 0.3, 0.3], "intensity": 2.0, "cone_angle": 25})
    config = write_json(os.path.join(tmp, "propagation.json"), settings)
    render(cli, ["--phantom", "spheres", "--method", "propagation", "--config", config],
           os.path.join(HERE, "propagation.png"))


def labelled_row(cli, tmp, name, source, variants):
    """Renders source (volillum-render's input arguments) once per (label, settings), each
    labelled in its top left corner, side by side into name.png."""
    parts = []
    for i, (label, settings) in enumerate(variants):
        config = write_json(os.path.join(tmp, "%s%d.json" % (name, i)), settings)
        part = os.path.join(tmp, "%s%d.png" % (name, i))
        render(cli, source + ["--config", config], part)
        run("convert", part, "-font", "DejaVu-Sans", "-pointsize", "20", "-fill", "white",
            "-annotate", "+14+30", label, part)
        parts.append(part)
    run("convert", *parts, "+append", os.path.join(HERE, name + ".png"))


def filtered(cli, tmp):
    settings = json.load(open(os.path.join(ROOT, "Testing", "Data", "chirp.json")))
    settings["image_size"] = [400, 400]
    labelled_row(cli, tmp, "filtered", ["--phantom", "chirp", "--method", "filtered"],
                 [("Shadow Filter Width %d" % width, dict(settings, filter_width=width))
                  for width in (0, 9)])


def soft(cli, tmp):
    if not os.path.exists(ENGINE):
        print("make_images.py: soft.png left as it is: it needs the engine, %s" % ENGINE)
        return
    def settings(radius):
        return {"method": "filtered", "filter_width": 0, "image_size": [400, 400],
                "ambient": 0.08, "camera": {"azimuth": 20, "elevation": 30, "zoom": 1.1},
                "lights": [{"type": "directional", "position": [1.6, 0.9, 1.4],
                            "focal_point": [0.5, 0.5, 0.5], "relative": True,
                            "color": [1, 0.95, 0.85], "intensity": 1.2, "radius": radius}]}
    labelled_row(cli, tmp, "soft", [ENGINE],
                 [("Shadow Radius %d" % radius, settings(radius)) for radius in (0, 5, 15)])


def ambient(cli, tmp):
    if not os.path.exists(ENGINE):
        print("make_images.py: ambient.png left as it is: it needs the engine, %s" % ENGINE)
        return
    def settings(strength):
        return {"method": "filtered", "image_size": [400, 400], "ambient": 0.05,
                "ambient_occlusion": strength,
                "camera": {"azimuth": 20, "elevation": 30, "zoom": 1.1},
                "lights": [{"type": "directional", "position": [1.6, 0.9, 1.4],
                            "focal_point": [0.5, 0.5, 0.5], "relative": True,
                            "color": [1, 0.95, 0.85], "intensity": 0.8}]}
    labelled_row(cli, tmp, "ambient", [ENGINE],
                 [("No ambient occlusion", settings(0)),
                  ("Ambient Occlusion 0.8", settings(0.8))])


def unstructured(cli, tmp):
    mesh = os.path.join(tmp, "head_tets.vtu")
    script = os.path.join(tmp, "tetrahedralize.py")
    with open(script, "w") as f:
        f.write(f"""from paraview.simple import *
head = XMLImageDataReader(FileName=[{HEAD!r}])
small = ResampleToImage(Input=head, SamplingDimensions=[56, 56, 82], UseInputBounds=1)
material = Threshold(Input=small, Scalars=["POINTS", "scalars"])
material.LowerThreshold, material.UpperThreshold = {0.22 * HEAD_MAX}, {HEAD_MAX}
SaveData({mesh!r}, proxy=Tetrahedralize(Input=material), ChooseArraysToWrite=0)
""")
    run("pvpython", script)
    settings = json.load(open(DEMO))
    transfer = settings["transfer_function"]
    # Absolute scalars: the threshold changed the range a relative function spans.
    transfer["relative"] = False
    transfer["color"] = [[p[0] * HEAD_MAX] + p[1:] for p in transfer["color"]]
    transfer["opacity"] = [[p[0] * HEAD_MAX, p[1]] for p in transfer["opacity"]]
    settings.update(side_by_side=False, image_size=[480, 480], level0_resolution=96)
    settings["camera"]["zoom"] = 1.3
    config = write_json(os.path.join(tmp, "unstructured.json"), settings)
    render(cli, [mesh, "--config", config], os.path.join(HERE, "unstructured.png"))


GUI_SCRIPT = """import os
from paraview.simple import *
LoadPlugin({plugin!r}, remote=False, ns=globals())
head = XMLImageDataReader(registrationName="headsq.vti", FileName=[{head!r}])
head.UpdatePipeline()
view = GetActiveViewOrCreate("RenderView")
rep = Show(head, view)
rep.SetRepresentationType("Illuminated Volume")
ColorBy(rep, ("POINTS", "scalars"))
lo, hi = head.PointData["scalars"].GetRange()
s = lambda f: lo + f * (hi - lo)
# Data/demo.json's transfer function and lights.
GetColorTransferFunction("scalars").RGBPoints = [
    s(0), .9, .6, .45, s(.25), .9, .6, .45, s(.35), 1, .95, .9, s(1), 1, 1, 1]
GetOpacityTransferFunction("scalars").Points = [
    s(0), 0, .5, 0, s(.15), 0, .5, 0, s(.2), .02, .5, 0, s(.28), .02, .5, 0,
    s(.33), .6, .5, 0, s(1), .9, .5, 0]
rep.ScalarOpacityUnitDistance = 3.0
view.UseColorPaletteForBackground = 0
view.Background = [0.1, 0.1, 0.12]
view.OrientationAxesVisibility = 0
view.ResetCamera()
camera = view.GetActiveCamera()
camera.Azimuth(90)
camera.Elevation(-60)
camera.Roll(-90)
view.ResetCamera()
camera.Zoom(1.3)
# As in Data/demo.json: a warm point light from the viewer's left and a blue directional
# light from the right, placed in the camera's frame so that both show.
b = head.GetDataInformation().GetBounds()
center = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
eye, up = camera.GetPosition(), camera.GetViewUp()
back = [e - c for e, c in zip(eye, center)]
norm = sum(v * v for v in back) ** 0.5
back = [v / norm for v in back]
right = [up[1] * back[2] - up[2] * back[1], up[2] * back[0] - up[0] * back[2],
         up[0] * back[1] - up[1] * back[0]]
place = lambda r, u, f: [c + size * (r * x + u * y + f * z)
                         for c, x, y, z in zip(center, right, up, back)]
view.UseLight = 0
warm = AddLight(view=view)
warm.Coords, warm.Type, warm.ConeAngle = "Scene", "Positional", 180
warm.Position, warm.FocalPoint = place(-1.3, 0.3, 0.8), center
warm.DiffuseColor, warm.Intensity = [1, .75, .35], 1.4
blue = AddLight(view=view)
blue.Coords = "Scene"
blue.Position, blue.FocalPoint = place(1.5, 0.2, 0.4), center
blue.DiffuseColor, blue.Intensity = [.3, .55, 1], 1.0
SetActiveSource(head)
Render(view)
"""


def xdo(display, *args):
    subprocess.run(("xdotool",) + args, check=True, env=dict(os.environ, DISPLAY=display))


def drag(display, start, end, steps=14):
    """Drags slowly: Qt's splitters ignore a jump."""
    (x0, y0), (x1, y1) = start, end
    xdo(display, "mousemove", str(x0 - 3), str(y0))
    xdo(display, "mousemove", str(x0), str(y0))
    time.sleep(0.5)
    xdo(display, "mousedown", "1")
    for i in range(1, steps + 1):
        time.sleep(0.15)
        xdo(display, "mousemove", str(x0 + (x1 - x0) * i // steps), str(y0 + (y1 - y0) * i // steps))
    time.sleep(0.3)
    xdo(display, "mouseup", "1")
    time.sleep(1)


def click(display, x, y, wait=1.0):
    xdo(display, "mousemove", str(x), str(y), "click", "1")
    time.sleep(wait)


def gui(cli, tmp, plugin):
    home = os.path.join(tmp, "home")
    os.makedirs(os.path.join(home, ".config", "ParaView"))
    for version in ("5.11.0", "5.13.0", "5.13.1", "5.13.2", "5.13.3"):
        with open(os.path.join(home, ".config", "ParaView", "ParaView%s.ini" % version), "w") as f:
            f.write("[General]\nGeneralSettings.ShowWelcomeDialog=false\n")
    script = os.path.join(tmp, "gui.py")
    with open(script, "w") as f:
        f.write(GUI_SCRIPT.format(plugin=plugin, head=HEAD))
    read, write = os.pipe()
    xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1600x1000x24",
                             "-nolisten", "tcp"], pass_fds=[write])
    os.close(write)
    display = ":" + os.read(read, 16).decode().strip()
    os.close(read)
    env = dict(os.environ, DISPLAY=display, HOME=home, XDG_CONFIG_HOME=os.path.join(home, ".config"))
    paraview = subprocess.Popen(["paraview", "--script=" + script], env=env)
    try:
        window = ""
        for _ in range(120):
            time.sleep(1)
            found = subprocess.run(["xdotool", "search", "--name", "^ParaView [0-9]"], env=env,
                                   stdout=subprocess.PIPE, text=True).stdout.split()
            if found:
                window = found[0]
                break
        if not window:
            raise RuntimeError("ParaView opened no window on " + display)
        time.sleep(10)
        xdo(display, "windowsize", window, "1600", "1000")
        time.sleep(5)
        drag(display, (295, 700), (560, 700))  # widen the Properties panel
        drag(display, (300, 437), (300, 230))  # shorten the Pipeline Browser
        xdo(display, "mousemove", "250", "800")
        xdo(display, "click", "--repeat", "10", "--delay", "100", "5")  # to Illumination
        click(display, 100, 10)  # View
        click(display, 158, 211, wait=3)  # View > Light Inspector
        # Hide the lights' widgets: a positional light's 180-degree cone covers the view.
        click(display, 1430, 386)
        click(display, 1433, 715)
        drag(display, (1412, 900), (1262, 900), steps=20)  # widen the Light Inspector
        time.sleep(10)
        shot = os.path.join(tmp, "gui.png")
        run("import", "-display", display, "-window", "root", shot)
        run("convert", shot, "-resize", "1280x800", os.path.join(HERE, "gui.png"))
    finally:
        paraview.terminate()
        try:
            paraview.wait(timeout=20)
        except subprocess.TimeoutExpired:
            paraview.kill()
        xvfb.terminate()
        xvfb.wait()


PICTURES = {"hero": hero, "propagation": propagation, "filtered": filtered, "soft": soft,
            "ambient": ambient, "unstructured": unstructured, "gui": gui}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--only", nargs="+", choices=sorted(PICTURES), default=list(PICTURES))
    args = parser.parse_args()
    cli = os.path.join(os.path.abspath(args.build), "bin", "volillum-render")
    plugins = glob.glob(os.path.join(os.path.abspath(args.build), "lib", "paraview-*", "plugins",
                                     "VolumetricIllumination", "VolumetricIllumination.so"))
    if not os.path.exists(cli) or len(plugins) != 1:
        sys.exit("make_images.py: no build in %s (run ./setup.sh build)" % args.build)
    os.environ.setdefault("VTK_SMP_BACKEND_IN_USE", "STDThread")
    tmp = tempfile.mkdtemp(prefix="volillum-images-")
    try:
        for name in args.only:
            if name == "gui":
                gui(cli, tmp, plugins[0])
            else:
                PICTURES[name](cli, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for name in args.only:
        path = os.path.join(HERE, name + ".png")
        if os.path.exists(path):
            print("%s: %d KB" % (os.path.relpath(path, ROOT), os.path.getsize(path) // 1024))


if __name__ == "__main__":
    main()
