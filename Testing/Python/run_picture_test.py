"""Driver of TestIlluminatedPictureGUI.py: starts the real paraview GUI (it needs a display:
run under xvfb-run) with the engine CT as plain Volume and as Illuminated Volume under the
default light kit, and measures the on-screen frames it grabbed:
- grain: relative high-pass energy (mean |luminance - its 3x3 median| / mean luminance)
  over the engine's cut face, seen straight on (the pixels plain Volume shows red, eroded
  by 3 pixels), Illuminated Volume against Volume;
- brightness: the cut face's mean luminance, Illuminated Volume against Volume;
- the first frame after a Resolution Scale change equals the next one.
Every figure is printed on every run, with its bound.
Usage: pvpython run_picture_test.py PARAVIEW PLUGIN DATA_DIR OUTPUT_DIR
"""
import os
import sys

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import Checks, finish, run_gui_script
from PictureMeasures import erode, high_pass, luminance, rgb

# Just above what the representation reaches (measured on llvmpipe, 2026-12-06).
GRAIN_BOUND = 0.6
BRIGHTNESS_RANGE = (0.85, 1.15)

paraview, plugin, data, out = sys.argv[1:5]
here = os.path.dirname(os.path.abspath(__file__))
results = run_gui_script(
    paraview, os.path.join(here, "TestIlluminatedPictureGUI.py"),
    dict(os.environ, VOLILLUM_PLUGIN=plugin, VOLILLUM_DATA=data, VOLILLUM_OUTPUT=out),
    os.path.join(out, "picture_result.txt"))
check = Checks()
if "error" in results:
    finish(["the GUI script failed: " + results["error"]])


def frame(name):
    return rgb(os.path.join(out, "picture_%s.png" % name))


check(results.get("representation") == "Illuminated_Volume",
      "the representation is Illuminated Volume (%s)" % results.get("representation"))
plain, lit = frame("volume_straight"), frame("illuminated_straight")
# The cut face: what plain Volume shows red (the top of the default colour map).
red = (plain[:, :, 0] > 60) & (plain[:, :, 0] > 1.6 * plain[:, :, 1]) & \
    (plain[:, :, 0] > 1.6 * plain[:, :, 2])
face = erode(red, 3)
check(face.sum() > 2000, "the cut face covers %d pixels (more than 2000)" % face.sum())
plain_l, lit_l = luminance(plain), luminance(lit)
grain = [high_pass(plain_l, face), high_pass(lit_l, face)]
print("cut face high-pass energy: Volume %.4f, Illuminated Volume %.4f (%.2fx)" %
      (grain[0], grain[1], grain[1] / grain[0]))
check(grain[1] <= GRAIN_BOUND * grain[0],
      "Illuminated Volume is no grainier than Volume: %.2fx (bound %.2f)" %
      (grain[1] / grain[0], GRAIN_BOUND))
brightness = lit_l[face].mean() / plain_l[face].mean()
print("cut face luminance: Volume %.1f, Illuminated Volume %.1f (%.2fx)" %
      (plain_l[face].mean(), lit_l[face].mean(), brightness))
check(BRIGHTNESS_RANGE[0] <= brightness <= BRIGHTNESS_RANGE[1],
      "the lit cut face is as bright as Volume's: %.2fx (bounds %.2f-%.2f)" %
      (brightness, BRIGHTNESS_RANGE[0], BRIGHTNESS_RANGE[1]))
first, after = frame("scale_first"), frame("scale_next")
difference = numpy.abs(first - after).mean()
print("first frame after a Resolution Scale change against the next: mean %.3f, means %.1f / %.1f" %
      (difference, luminance(first).mean(), luminance(after).mean()))
check(difference <= 0.5 and luminance(first).mean() > 0,
      "the first frame after a Resolution Scale change equals the next (%.3f)" % difference)
finish(check.failures)
