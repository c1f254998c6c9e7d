"""Checks the demo picture (volillum-render's side_by_side output: local shading on the
left, global illumination on the right, each half labelled): it is at least 1280 pixels
wide, and its lit half is no grainier than its local half (relative high-pass energy over
the pixels where the local half shows material, eroded by 3 pixels, the labels' strip at
the bottom left out). The figures are printed on every run.
Usage: pvpython check_demo_halves.py DEMO_PNG
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import Checks, finish
from PictureMeasures import erode, high_pass, luminance, rgb

# Just above what the demo reaches (measured on llvmpipe, 2026-12-06).
GRAIN_BOUND = 1.1

picture = rgb(sys.argv[1])
rows, columns, _ = picture.shape
check = Checks()
check(columns >= 1280, "the demo picture is %d pixels wide (at least 1280)" % columns)
local, lit = luminance(picture[:, :columns // 2]), luminance(picture[:, columns // 2:])
material = local > 20
material[int(rows * 0.9):, :] = False
material = erode(material, 3)
check(material.sum() > 5000, "the head covers %d pixels of a half (more than 5000)" % material.sum())
grain = [high_pass(local, material), high_pass(lit, material)]
print("high-pass energy over the head: local shading %.4f, global illumination %.4f (%.2fx)" %
      (grain[0], grain[1], grain[1] / grain[0]))
check(grain[1] <= GRAIN_BOUND * grain[0],
      "the lit half is no grainier than the local half: %.2fx (bound %.2f)" %
      (grain[1] / grain[0], GRAIN_BOUND))
finish(check.failures)
