"""pvpython: the Illuminated Volume representations on `mpiexec -np 2 pvserver` give the
builtin images.

The shipped CT head, read by ParaView's image reader (on the server each process reads and
renders its own piece), and a tetrahedral grid (redistributed by the view for ordered
compositing) are drawn as "Illuminated Volume" with two Light Inspector lights (light kit
off): first in a builtin session, then on a pvserver of two MPI processes on 127.0.0.1 with
remote rendering (ordered compositing of the pieces). The images must match (mean absolute
difference below 0.5 of 255). The server's output must hold no error but those of the port
probe.
Usage: pvpython TestIlluminatedVolumeParallelServer.py PLUGIN OUTPUT_DIR PVSERVER MPIEXEC
       "MPI_FLAGS" GRID
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import finish, image_difference, pvserver_session, scene_light

plugin, out, pvserver, mpiexec, flags, GRID = sys.argv[1:7]
HEAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data", "headsq.vti")


def render_scene(path, source, array, setup):
    """Show source as "Illuminated Volume" coloured by array in a 240 x 240 view rendered on
    the server (light kit off), let setup(view, rep) set the colour map, camera and lights,
    and save the image."""
    view = CreateView("RenderView")
    view.ViewSize = [240, 240]
    view.OrientationAxesVisibility = 0
    view.UseLight = 0
    view.RemoteRenderThreshold = 0
    rep = Show(source, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, array)
    view.ResetCamera()
    setup(view, rep)
    Render(view)
    SaveScreenshot(path, view)
    Delete(view)
    Delete(source)


def image_scene(path):
    """The CT head at resolution scale 0.5, lit by two lights."""
    def setup(view, rep):
        GetColorTransferFunction("scalars").RGBPoints = [0, 0.9, 0.8, 0.7, 1200, 1.0, 0.9, 0.8,
                                                         3000, 1.0, 1.0, 1.0]
        GetOpacityTransferFunction("scalars").Points = [0, 0, 0.5, 0, 500, 0, 0.5, 0,
                                                        1200, 0.3, 0.5, 0, 3000, 0.8, 0.5, 0]
        rep.IlluminationResolutionScale = 0.5
        GetActiveCamera().Elevation(70)
        GetActiveCamera().Azimuth(30)
        scene_light(view, [-200, -150, 400], [100, 100, 70], [1.0, 0.7, 0.4])
        scene_light(view, [350, 120, 60], [100, 100, 70], [0.4, 0.6, 1.0], point=True)
    render_scene(path, XMLImageDataReader(FileName=[HEAD]), ("POINTS", "scalars"), setup)


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
    render_scene(path, grid, (association, name), setup)


SCENES = {"Image": image_scene, "Grid": grid_scene}


if __name__ == "__main__":
    LoadPlugin(plugin, remote=False, ns=globals())
    for name, scene in SCENES.items():
        scene(os.path.join(out, "ParallelServer%sBuiltin.png" % name))

    failures = []
    log_path = os.path.join(out, "ParallelServer.log")
    with open(log_path, "w") as log, \
            pvserver_session([mpiexec] + flags.split() + ["-np", "2", pvserver], plugin,
                             globals(), log) as port:
        if port is None:
            failures.append("pvserver -np 2 did not listen")
        else:
            for name, scene in SCENES.items():
                builtin = os.path.join(out, "ParallelServer%sBuiltin.png" % name)
                parallel = os.path.join(out, "ParallelServer%sTwoProcesses.png" % name)
                scene(parallel)
                difference = image_difference(builtin, parallel)
                print("%s, pvserver -np 2, remote rendering: mean absolute difference to the "
                      "builtin image %.3f" % (name, difference))
                if difference > 0.5:
                    failures.append("%s: pvserver -np 2 differs from the builtin image by %.3f"
                                    % (name, difference))
    with open(log_path) as log:
        # The port probe (wait_for) connects without a handshake: the socket errors it causes
        # are expected.
        errors = [line for line in log if "ERR|" in line and "Socket" not in line and
                  "TCPNetwork" not in line]
    if errors:
        failures.append("the server reported errors:\n" + "".join(errors[:10]))
    finish(failures)
