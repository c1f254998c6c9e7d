"""pvpython: the Illuminated Volume representation through pvserver gives the builtin image.

The CT phantom lit by two Light Inspector lights (light kit off) is rendered as
"Illuminated Volume" in a builtin session; then a pvserver is started on 127.0.0.1 (a free
port of this machine, stopped at the end), pvpython connects to it with the plugin loaded
on both sides, and the same scene is rendered with remote rendering (the server lights
and draws the volume) and with local rendering (the data delivered to the client), and with
remote rendering and Asynchronous Lighting on: the server lights in the background, its
IlluminationStatus (read by the client) shows it, and the client renders until the final
illumination. Every image must match the builtin image (mean absolute difference below 0.5
of 255).
Usage: pvpython TestIlluminatedVolumeClientServer.py PLUGIN OUTPUT_DIR PVSERVER
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import (finish, illuminated_view, image_difference,
                                             pvserver_session, render_final, scene_light)

plugin, out, pvserver = sys.argv[1:4]


def scene(path, remote_render_threshold=None, asynchronous=False):
    """Render the scene and save it; with asynchronous, with Asynchronous Lighting on (returns
    whether a lighting ran in the background, where the view renders)."""
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
    rep.AsynchronousLighting = 1 if asynchronous else 0
    waited = render_final(view)
    SaveScreenshot(path, view)
    Delete(view)
    return waited


LoadPlugin(plugin, remote=False, ns=globals())
builtin = os.path.join(out, "ClientServerBuiltin.png")
scene(builtin)

failures = []
with pvserver_session([pvserver], plugin, globals()) as port:
    if port is None:
        failures.append("pvserver did not listen")
    else:
        for label, threshold, asynchronous in (("remote rendering", 0, False),
                                               ("local rendering", 1e6, False),
                                               ("asynchronous remote rendering", 0, True)):
            path = os.path.join(out, "ClientServer%s.png" % "".join(
                word.capitalize() for word in label.split()[:-1]))
            waited = scene(path, threshold, asynchronous)
            if asynchronous and not waited:
                failures.append("%s: the server's IlluminationStatus never showed a background "
                                "lighting" % label)
            difference = image_difference(builtin, path)
            print("%s: mean absolute difference to the builtin image %.3f" % (label, difference))
            if difference > 0.5:
                failures.append("%s differs from the builtin image by %.3f" % (label, difference))
finish(failures)
