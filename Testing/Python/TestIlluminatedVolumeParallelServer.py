"""pvpython: the Illuminated Volume representation on `mpiexec -np 2 pvserver` gives the
builtin image.

The shipped CT head, read by ParaView's image reader (on the server each process reads and
renders its own piece), is drawn as "Illuminated Volume" with two Light Inspector lights
(light kit off): first in a builtin session, then on a pvserver of two MPI processes on
127.0.0.1 with remote rendering (ordered compositing of the two pieces). The images must
match (mean absolute difference below 0.5 of 255). The server's output must hold no error
but those of the port probe.
Usage: pvpython TestIlluminatedVolumeParallelServer.py PLUGIN OUTPUT_DIR PVSERVER MPIEXEC
       "MPI_FLAGS"
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import finish, image_difference, pvserver_session, scene_light

plugin, out, pvserver, mpiexec, flags = sys.argv[1:6]
HEAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data", "headsq.vti")


def scene(path):
    head = XMLImageDataReader(FileName=[HEAD])
    view = CreateView("RenderView")
    view.ViewSize = [240, 240]
    view.OrientationAxesVisibility = 0
    view.UseLight = 0
    view.RemoteRenderThreshold = 0
    rep = Show(head, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, ("POINTS", "scalars"))
    lut = GetColorTransferFunction("scalars")
    lut.RGBPoints = [0, 0.9, 0.8, 0.7, 1200, 1.0, 0.9, 0.8, 3000, 1.0, 1.0, 1.0]
    GetOpacityTransferFunction("scalars").Points = [0, 0, 0.5, 0, 500, 0, 0.5, 0,
                                                    1200, 0.3, 0.5, 0, 3000, 0.8, 0.5, 0]
    rep.IlluminationResolutionScale = 0.5
    view.ResetCamera()
    GetActiveCamera().Elevation(70)
    GetActiveCamera().Azimuth(30)
    scene_light(view, [-200, -150, 400], [100, 100, 70], [1.0, 0.7, 0.4])
    scene_light(view, [350, 120, 60], [100, 100, 70], [0.4, 0.6, 1.0], point=True)
    Render(view)
    SaveScreenshot(path, view)
    Delete(view)
    Delete(head)


if __name__ == "__main__":
    LoadPlugin(plugin, remote=False, ns=globals())
    builtin = os.path.join(out, "ParallelServerBuiltin.png")
    scene(builtin)

    failures = []
    log_path = os.path.join(out, "ParallelServer.log")
    with open(log_path, "w") as log, \
            pvserver_session([mpiexec] + flags.split() + ["-np", "2", pvserver], plugin,
                             globals(), log) as port:
        if port is None:
            failures.append("pvserver -np 2 did not listen")
        else:
            parallel = os.path.join(out, "ParallelServerTwoProcesses.png")
            scene(parallel)
            difference = image_difference(builtin, parallel)
            print("pvserver -np 2, remote rendering: mean absolute difference to the builtin "
                  "image %.3f" % difference)
            if difference > 0.5:
                failures.append("pvserver -np 2 differs from the builtin image by %.3f"
                                % difference)
    with open(log_path) as log:
        # The port probe (wait_for) connects without a handshake: the socket errors it causes
        # are expected.
        errors = [line for line in log if "ERR|" in line and "Socket" not in line and
                  "TCPNetwork" not in line]
    if errors:
        failures.append("the server reported errors:\n" + "".join(errors[:10]))
    finish(failures)
