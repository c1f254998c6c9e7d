"""pvpython: Asynchronous Lighting of the Illuminated Volume representation.

Two views show the CT phantom (128^3) as "Illuminated Volume" with the same colour map,
opacity, camera and light kit: one lights synchronously (pvpython's default), the other
with Asynchronous Lighting on. Checks:
- pvpython leaves Asynchronous Lighting off;
- after a camera turn, the asynchronous Render() returns with IlluminationPending 1, the
  view renders the final illumination by itself once the worker is done (pending then 0),
  and that frame equals the synchronous view's within 0.5 of 255 (mean absolute);
- two opacity edits in a row, the second before the first is lit: the final frame equals
  the synchronous frame of the second edit (the first, superseded, never becomes final);
- the unstructured representation (a tetrahedralised phantom) likewise after a turn: pending
  after Render(), then the synchronous frame and mean illumination;
- a screenshot taken right after a turn (no render in between) equals the synchronous one:
  a screenshot's render waits for the lighting;
- Ray-Marched Reference cancelled while it runs (IlluminationStatus's CancelIllumination):
  the representation draws the illumination it had before (same mean illumination), and
  nothing stays pending. The time the cancellation took is printed.
Usage: pvpython TestAsynchronousLighting.py PLUGIN OUTPUT_DIR
"""
import os
import sys
import time

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import (Checks, finish, illumination_status, image_difference,
                                             info, lighting_flags, render_final)

LoadPlugin(sys.argv[1], remote=False, ns=globals())
out = sys.argv[2]
check = Checks()

phantom = IlluminationPhantom(Scene="CT Phantom", Dimensions=[128, 128, 128])
lut = GetColorTransferFunction("Density")
lut.ApplyPreset("Cool to Warm", True)
pwf = GetOpacityTransferFunction("Density")
pwf.Points = [0.0, 0.0, 0.5, 0.0, 0.3, 0.05, 0.5, 0.0, 1.0, 0.4, 0.5, 0.0]


def sync_and_async(source):
    """Two 300x300 views showing source as "Illuminated Volume" coloured by Density, lit
    synchronously and with Asynchronous Lighting on (after checking it is off by default)."""
    pair_views, pair_reps = [], []
    for asynchronous in (0, 1):
        view = CreateView("RenderView")
        view.ViewSize = [300, 300]
        view.OrientationAxesVisibility = 0
        rep = Show(source, view)
        rep.SetRepresentationType("Illuminated Volume")
        ColorBy(rep, ("POINTS", "Density"))
        if asynchronous:
            check(rep.AsynchronousLighting == 0, "pvpython leaves Asynchronous Lighting off (%s)"
                  % source.GetXMLLabel())
        rep.AsynchronousLighting = asynchronous
        view.ResetCamera()
        pair_views.append(view)
        pair_reps.append(rep)
    return pair_views, pair_reps


views, reps = sync_and_async(phantom)
for rep in reps:
    rep.IlluminationResolutionScale = 1.0
sync_view, async_view = views
sync_rep, async_rep = reps
status = illumination_status()


def turn(degrees, views=views):
    for view in views:
        SetActiveView(view)
        GetActiveCamera().Azimuth(degrees)
    SetActiveView(None)


def frames_agree(name, views=views, reps=reps):
    """Both views' final frames, saved and compared (mean absolute difference per channel)."""
    paths = []
    for view, rep, kind in zip(views, reps, ("sync", "async")):
        render_final(view)
        paths.append(os.path.join(out, "async_%s_%s.png" % (name, kind)))
        SaveScreenshot(paths[-1], view, ImageResolution=[300, 300])
    difference = image_difference(*paths)
    check(difference <= 0.5,
          "%s: the asynchronous frame equals the synchronous one (mean abs %.4f of 255, "
          "bound 0.5)" % (name, difference))


render_final(sync_view)
render_final(async_view)

# A camera turn: the light kit turns with the camera, so everything is re-lit.
turn(40)
start = time.perf_counter()
Render(sync_view)
synchronous = time.perf_counter() - start
start = time.perf_counter()
Render(async_view)
asynchronous = time.perf_counter() - start
check(info(async_rep, "IlluminationPending")[0] == 1,
      "the asynchronous Render() returned with the lighting pending (Render %.3f s, the "
      "synchronous one %.3f s)" % (asynchronous, synchronous))
render_final(async_view)
check(info(async_rep, "IlluminationPending")[0] == 0, "then the final illumination was drawn")
frames_agree("turn")

# Two opacity edits in a row: the second supersedes the first.
pwf.Points = [0.0, 0.0, 0.5, 0.0, 0.3, 0.2, 0.5, 0.0, 1.0, 0.6, 0.5, 0.0]
Render(async_view)
pwf.Points = [0.0, 0.0, 0.5, 0.0, 0.3, 0.02, 0.5, 0.0, 1.0, 0.3, 0.5, 0.0]
Render(async_view)
frames_agree("superseded_edit")

# A screenshot right after a turn waits for the final illumination.
turn(30)
shots = []
for view, kind in ((sync_view, "sync"), (async_view, "async")):
    shots.append(os.path.join(out, "async_screenshot_%s.png" % kind))
    SaveScreenshot(shots[-1], view, ImageResolution=[300, 300])
difference = image_difference(*shots)
check(difference <= 0.5, "a screenshot right after a turn shows the final illumination (mean abs "
      "%.4f of 255, bound 0.5)" % difference)

# Ray-Marched Reference, cancelled while it runs: the previous illumination stays.
before = info(async_rep, "IlluminationMean")
async_rep.IlluminationMethod = "Ray-Marched Reference"
Render(async_view)
running = lighting_flags(status)[0]
start = time.perf_counter()
status.InvokeCommand("CancelIllumination")
while True:
    if not lighting_flags(status)[0]:
        break
    time.sleep(0.005)
cancelled = time.perf_counter() - start
check(running, "the ray-marched lighting ran in the background (cancelled within %.3f s)"
      % cancelled)
render_final(async_view)
after = info(async_rep, "IlluminationMean")
check(after == before, "the cancelled update kept the previous illumination (mean %s, before %s)"
      % (after, before))

# The unstructured representation likewise: a tetrahedralised phantom turned under the light kit.
mesh = Tetrahedralize(Input=IlluminationPhantom(Scene="Three Spheres", Dimensions=[48, 48, 48]))
grid_views, grid_reps = sync_and_async(mesh)
for view, rep in zip(grid_views, grid_reps):
    render_final(view)
turn(40, grid_views)
Render(grid_views[1])
check(info(grid_reps[1], "IlluminationPending")[0] == 1,
      "unstructured: the asynchronous Render() returned with the lighting pending")
frames_agree("grid_turn", grid_views, grid_reps)
check(info(grid_reps[0], "IlluminationMean") == info(grid_reps[1], "IlluminationMean"),
      "unstructured: the same mean illumination (%s)" % info(grid_reps[1], "IlluminationMean"))
status.UnRegister(None)
finish(check.failures)
