"""pvpython: the Illuminated Volume representations on `mpiexec -np 2 pvserver` and
`mpiexec -np 2 pvbatch` give the builtin images.

The shipped CT head, read by ParaView's image reader (on the server each process reads and
renders its own piece), and a tetrahedral grid (redistributed by the view for ordered
compositing) are drawn as "Illuminated Volume" with two Light Inspector lights (light kit
off): first in a builtin session, then on a pvserver of two MPI processes on 127.0.0.1 with
remote rendering (ordered compositing of the pieces). A third scene lights the CT head with
the light kit alone (camera lights) and moves the camera just before the screenshot, so
that the screenshot's render is the first with that camera: the servers (and, in pvbatch,
every process but the first) get the camera only as that render starts, and must light with
it. That scene is also rendered by `mpiexec -np 2 pvbatch` running this script, with
Asynchronous Lighting on (synchronous under MPI: the same image). A fourth
scene adds two bright lights to the light kit: lit samples brighter than the displayable
range on rays that cross both pieces (a piece's image brighter than its opacity made the
compositing wrap channels around: saturated blue turned dark). Then a small
image (9 x 5 x 5, lit at resolution scale 1/4 by 3 pvbatch processes, one of which holds an
illumination piece that is the whole grid) is rendered twice in a row, before and after a
camera move, and so is a cube of 5 tetrahedra (processes without cells; the first process,
which holds them, must have lit them): the processes must agree whether to light, or wait
on each other for ever. The
images must match (mean absolute difference below 0.5 of 255, no pixel with a channel 128
or more apart). The server's output must hold no
error but those of the port probe.
Usage: pvpython TestIlluminatedVolumeParallelServer.py PLUGIN OUTPUT_DIR PVSERVER MPIEXEC
       "MPI_FLAGS" GRID PVBATCH
       pvbatch TestIlluminatedVolumeParallelServer.py --batch PLUGIN IMAGE (the third scene)
       pvbatch TestIlluminatedVolumeParallelServer.py --small PLUGIN SMALL_VTI
"""
import os
import subprocess
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import (environment_for_mpiexec, finish, image_difference,
                                             info, pixels_apart, pvserver_session, scene_light,
                                             write_image)

HEAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data", "headsq.vti")


def render_scene(path, source, array, setup, light_kit=False, moved=None):
    """Show source as "Illuminated Volume" coloured by array in a 240 x 240 view rendered on
    the server (the light kit on or off), let setup(view, rep) set the colour map, camera and
    lights, render, let moved() move the camera, and save the image."""
    view = CreateView("RenderView")
    view.ViewSize = [240, 240]
    view.OrientationAxesVisibility = 0
    view.UseLight = 1 if light_kit else 0
    view.RemoteRenderThreshold = 0
    rep = Show(source, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, array)
    view.ResetCamera()
    setup(view, rep)
    Render(view)
    if moved:
        moved()
    SaveScreenshot(path, view)
    # Whether the image was lit where its pieces are (image data; the value of this process:
    # the client's in a client-server session, the first process's in pvbatch).
    distributed = None
    if rep.SMProxy.GetProperty("IlluminationDistributed") is not None:
        distributed = info(rep, "IlluminationDistributed")[0]
    Delete(view)
    Delete(source)
    return distributed


def head_colours(rep):
    """The CT head's colour map and opacity, lit at resolution scale 0.5."""
    GetColorTransferFunction("scalars").RGBPoints = [0, 0.9, 0.8, 0.7, 1200, 1.0, 0.9, 0.8,
                                                     3000, 1.0, 1.0, 1.0]
    GetOpacityTransferFunction("scalars").Points = [0, 0, 0.5, 0, 500, 0, 0.5, 0,
                                                    1200, 0.3, 0.5, 0, 3000, 0.8, 0.5, 0]
    rep.IlluminationResolutionScale = 0.5


def image_scene(path):
    """The CT head at resolution scale 0.5, lit by two lights."""
    def setup(view, rep):
        head_colours(rep)
        GetActiveCamera().Elevation(70)
        GetActiveCamera().Azimuth(30)
        scene_light(view, [-200, -150, 400], [100, 100, 70], [1.0, 0.7, 0.4])
        scene_light(view, [350, 120, 60], [100, 100, 70], [0.4, 0.6, 1.0], point=True)
    return render_scene(path, XMLImageDataReader(FileName=[HEAD]), ("POINTS", "scalars"), setup)


def light_kit_scene(path, asynchronous=False):
    """The CT head lit by the light kit (lights that follow the camera), the camera turned
    just before the screenshot. With asynchronous, Asynchronous Lighting is on (pvbatch:
    under MPI the processes still light together as each render starts)."""
    def moved():
        GetActiveCamera().Azimuth(150)
        GetActiveCamera().Elevation(40)

    def setup(view, rep):
        head_colours(rep)
        rep.AsynchronousLighting = 1 if asynchronous else 0
    return render_scene(path, XMLImageDataReader(FileName=[HEAD]), ("POINTS", "scalars"),
                        setup, light_kit=True, moved=moved)


def grid_scene(path):
    """The tetrahedral grid GRID, lit by two lights."""
    grid = XMLUnstructuredGridReader(FileName=[GRID])
    association = "POINTS" if grid.PointData.keys() else "CELLS"
    name = (grid.PointData if association == "POINTS" else grid.CellData).keys()[0]

    def setup(view, rep):
        rep.RescaleTransferFunctionToDataRange(True)
        GetActiveCamera().Azimuth(30)
        bounds = grid.GetDataInformation().GetBounds()
        centre = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]
        size = max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))
        scene_light(view, [centre[0] - size, centre[1] + size, centre[2] + 2 * size], centre,
                    [1.0, 0.7, 0.4])
        scene_light(view, [centre[0] + size, centre[1], centre[2]], centre, [0.4, 0.6, 1.0],
                    point=True)
    return render_scene(path, grid, (association, name), setup)


def bright_scene(path):
    """The CT head lit by the light kit and two bright lights: lit samples brighter than the
    displayable range, on rays that cross from one process's piece into the other's (each
    piece's image must stay within its opacity, or compositing wraps its channels around)."""
    def setup(view, rep):
        head_colours(rep)
        GetActiveCamera().Elevation(50)
        GetActiveCamera().Azimuth(120)
        scene_light(view, [100, -300, 300], [100, 100, 70], [1.0, 0.8, 0.3], intensity=2.5)
        scene_light(view, [100, 100, 300], [100, 100, 70], [0.3, 1.0, 0.4], point=True,
                    intensity=2.5)
    return render_scene(path, XMLImageDataReader(FileName=[HEAD]), ("POINTS", "scalars"), setup,
                        light_kit=True)


SCENES = {"Image": image_scene, "Grid": grid_scene, "LightKit": light_kit_scene,
          "Bright": bright_scene}


def write_small_image(path):
    """A 9 x 5 x 5 image: lit at resolution scale 1/4 by 3 processes, the illumination grid
    (3 x 2 x 2 points) over the middle block (x 2 to 5) is the whole grid, those over the
    others are not."""
    write_image(path, (9, 5, 5), [(i * 37) % 101 for i in range(9 * 5 * 5)])


def small_renders(path):
    """Renders of the small image, and of a cube of 5 tetrahedra (processes without cells
    to render), with nothing changed in between and after a camera move: every process must
    light (or keep its lighting) together."""
    for source, array in ((XMLImageDataReader(FileName=[path]), "scalars"),
                          (Tetrahedralize(Input=Wavelet(WholeExtent=[0, 1, 0, 1, 0, 1])),
                           "RTData")):
        view = CreateView("RenderView")
        view.ViewSize = [120, 120]
        rep = Show(source, view)
        rep.SetRepresentationType("Illuminated Volume")
        ColorBy(rep, ("POINTS", array))
        if array == "scalars":
            rep.IlluminationResolutionScale = 0.25
        view.ResetCamera()
        for _ in range(2):
            Render(view)
            Render(view)
            GetActiveCamera().Azimuth(60)
        if array == "RTData":
            # The first process holds the cube's cells: it lit them (with the others).
            print("small grid lit: %s" % (max(info(rep, "IlluminationMean")) > 0), flush=True)
        Delete(view)
    print("small image rendered", flush=True)


if __name__ == "__main__" and sys.argv[1] == "--batch":
    LoadPlugin(sys.argv[2], remote=False, ns=globals())
    print("IlluminationDistributed %s" % light_kit_scene(sys.argv[3], asynchronous=True))
elif __name__ == "__main__" and sys.argv[1] == "--small":
    LoadPlugin(sys.argv[2], remote=False, ns=globals())
    small_renders(sys.argv[3])
elif __name__ == "__main__":
    plugin, out, pvserver, mpiexec, flags, GRID, pvbatch = sys.argv[1:8]
    LoadPlugin(plugin, remote=False, ns=globals())
    for name, scene in SCENES.items():
        scene(os.path.join(out, "ParallelServer%sBuiltin.png" % name))

    failures = []

    def compare(name, run, path):
        """The image of scene `name` saved by `run` at path against the builtin one."""
        if not os.path.exists(path):
            failures.append("%s: %s saved no image" % (name, run))
            return
        difference = image_difference(os.path.join(out, "ParallelServer%sBuiltin.png" % name),
                                      path)
        wrapped = pixels_apart(os.path.join(out, "ParallelServer%sBuiltin.png" % name), path,
                               128)
        print("%s, %s: mean absolute difference to the builtin image %.3f, pixels with a "
              "channel 128 or more apart %d" % (name, run, difference, wrapped))
        if difference > 0.5 or wrapped > 0:
            failures.append("%s: %s differs from the builtin image by %.3f (%d pixels 128 or "
                            "more apart)" % (name, run, difference, wrapped))

    def batch(processes, *arguments):
        """This script run by `mpiexec -np processes pvbatch` with arguments: its output, or
        None when it did not end within 5 minutes."""
        try:
            return subprocess.run([mpiexec] + flags.split() + ["-np", str(processes), pvbatch,
                                   os.path.abspath(__file__)] + list(arguments),
                                  env=environment_for_mpiexec(), timeout=300,
                                  capture_output=True, text=True)
        except subprocess.TimeoutExpired:
            return None

    log_path = os.path.join(out, "ParallelServer.log")
    with open(log_path, "w") as log, \
            pvserver_session([mpiexec] + flags.split() + ["-np", "2", pvserver], plugin,
                             globals(), log) as port:
        if port is None:
            failures.append("pvserver -np 2 did not listen")
        else:
            for name, scene in SCENES.items():
                parallel = os.path.join(out, "ParallelServer%sTwoProcesses.png" % name)
                scene(parallel)
                compare(name, "pvserver -np 2, remote rendering", parallel)
    lit = os.path.join(out, "ParallelServerLightKitPvbatch.png")
    run = batch(2, "--batch", plugin, lit)
    if run is None or "IlluminationDistributed 1" not in run.stdout:
        failures.append("pvbatch -np 2 assembled the whole image:\n" +
                        (run.stdout[-2000:] + run.stderr[-2000:] if run else "(no end)"))
    compare("LightKit", "pvbatch -np 2", lit)
    small = os.path.join(out, "ParallelServerSmall.vti")
    write_small_image(small)
    run = batch(3, "--small", plugin, small)
    if run is None:
        failures.append("pvbatch -np 3, small image: the renders did not end (the processes "
                        "wait on each other)")
    elif "small image rendered" not in run.stdout:
        failures.append("pvbatch -np 3, small image: no renders\n" + run.stderr[-2000:])
    elif "small grid lit: True" not in run.stdout:
        failures.append("pvbatch -np 3, small grid: not lit\n" + run.stdout[-2000:])
    with open(log_path) as log:
        # The port probe (wait_for) connects without a handshake: the socket errors it causes
        # are expected.
        errors = [line for line in log if "ERR|" in line and "Socket" not in line and
                  "TCPNetwork" not in line]
    if errors:
        failures.append("the server reported errors:\n" + "".join(errors[:10]))
    finish(failures)
