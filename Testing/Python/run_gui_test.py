"""Driver of TestIlluminatedVolumeGUI.py: starts the real paraview GUI (it needs a display:
run under xvfb-run) with the test script, waits for it to exit, and checks what the script
recorded: the representation is Illuminated Volume, switching the only light off leaves
only ambient light (mean illumination 0 and a darker image), switching it on again
gives back the first image exactly, and a Lights list of 14 numbers a light becomes 15 a
light (radius 0) in the GUI.
Usage: python3 run_gui_test.py PARAVIEW PLUGIN OUTPUT_DIR
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import finish, image_difference, mean_colours, run_gui_script

paraview, plugin, out = sys.argv[1:4]
here = os.path.dirname(os.path.abspath(__file__))
results = run_gui_script(paraview, os.path.join(here, "TestIlluminatedVolumeGUI.py"),
                         dict(os.environ, VOLILLUM_PLUGIN=plugin, VOLILLUM_OUTPUT=out),
                         os.path.join(out, "gui_result.txt"))
print(results)
failures = []
if "error" in results:
    failures.append("the GUI script failed: " + results["error"])
else:
    if results.get("representation") != "Illuminated_Volume":
        failures.append("representation is %s" % results.get("representation"))
    if not float(results["mean_on"]) > 0.05:
        failures.append("light on: mean illumination %s" % results["mean_on"])
    if float(results["mean_off"]) != 0:
        failures.append("light off: mean illumination %s, expected 0" % results["mean_off"])
    if results["mean_on_again"] != results["mean_on"]:
        failures.append("light on again: mean %s, first %s" % (results["mean_on_again"], results["mean_on"]))
    on, off, again = (os.path.join(out, "gui_%s.png" % s) for s in ("on", "off", "on_again"))
    brightness = [sum(mean_colours(p)) for p in (on, off)]
    print("image brightness, light on %.1f, off %.1f" % tuple(brightness))
    if not brightness[0] > brightness[1] + 10:
        failures.append("switching the light off did not darken the image (%.1f vs %.1f)" %
                        tuple(brightness))
    light = [0, 1, 2, 3, 4, 5, 6, 1, 1, 1, 1, 30, 1, 1]
    padded = ",".join("%g" % v for v in (light + [0]) * 2)
    if results.get("legacy_lights") != padded:
        failures.append("a Lights list of 14 numbers a light reads back %s, expected %s"
                        % (results.get("legacy_lights"), padded))
    difference = image_difference(on, again)
    print("light on again vs first image: %.3f" % difference)
    if difference > 0.5:
        failures.append("light on again differs from the first image by %.3f" % difference)
finish(failures)
