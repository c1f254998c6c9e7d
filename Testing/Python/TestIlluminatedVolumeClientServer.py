"""pvpython: the Illuminated Volume representation through pvserver gives the builtin image.

The CT phantom lit by two Light Inspector lights (light kit off) is rendered as
"Illuminated Volume" in a builtin session; then a pvserver is started on 127.0.0.1 (a free
port of this machine, stopped at the end), pvpython connects to it with the plugin loaded
on both sides, and the same scene is rendered with remote rendering (the server lights
and draws the volume) and with local rendering (the data delivered to the client). Both
images must match the builtin image (mean absolute difference below 0.5 of 255).
Usage: pvpython TestIlluminatedVolumeClientServer.py PLUGIN OUTPUT_DIR PVSERVER
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import (finish, illuminated_view, image_difference,
                                             pvserver_session, scene_light)

plugin, out, pvserver = sys.argv[1:4]


def scene(path, remote_render_threshold=None):
    phantom = IlluminationPhantom(Scene="CT Phantom", Dimensions=[48, 48, 48])
    view, rep = illuminated_view(phantom, [240, 240])
    if remote_render_threshold is not None:
        view.RemoteRenderThreshold = remote_render_threshold
    GetColorTransferFunction("Density").ApplyPreset("Viridis (matplotlib)", True)
    GetOpacityTransferFunction("Density").Points = [0.0, 0.0, 0.5, 0.0, 0.3, 0.05, 0.5, 0.0,
                                                    1.0, 0.5, 0.5, 0.0]
    view.ResetCamera()
    GetActiveCamera().Azimuth(35)
    scene_light(view, [-40, 70, 80], [24, 24, 24], [1.0, 0.7, 0.4])
    scene_light(view, [80, 10, 30], [24, 24, 24], [0.4, 0.6, 1.0], point=True)
    Render(view)
    SaveScreenshot(path, view)
    Delete(view)


LoadPlugin(plugin, remote=False, ns=globals())
builtin = os.path.join(out, "ClientServerBuiltin.png")
scene(builtin)

failures = []
with pvserver_session([pvserver], plugin, globals()) as port:
    if port is None:
        failures.append("pvserver did not listen")
    else:
        for label, threshold in (("remote rendering", 0), ("local rendering", 1e6)):
            path = os.path.join(out, "ClientServer%s.png" % label.split()[0].capitalize())
            scene(path, threshold)
            difference = image_difference(builtin, path)
            print("%s: mean absolute difference to the builtin image %.3f" % (label, difference))
            if difference > 0.5:
                failures.append("%s differs from the builtin image by %.3f" % (label, difference))
finish(failures)
