"""pvpython: a state file with the Illuminated Volume representation reloads to the same image.

The CT phantom is shown as "Illuminated Volume" (filtered shadows, custom settings) with a
custom colour map and opacity, the light kit off and two Light Inspector lights. The
state is saved to a .pvsm, the session reset and the state loaded: the representation
type, the lights and the rendered image (mean absolute difference below 0.5 of 255) must
come back.
Usage: pvpython TestIlluminatedVolumeState.py PLUGIN OUTPUT_DIR
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import finish, illuminated_view, image_difference, scene_light

LoadPlugin(sys.argv[1], remote=False, ns=globals())
out = sys.argv[2]
state = os.path.join(out, "IlluminatedVolumeState.pvsm")
before = os.path.join(out, "IlluminatedVolumeStateSaved.png")
after = os.path.join(out, "IlluminatedVolumeStateLoaded.png")

phantom = IlluminationPhantom(Scene="CT Phantom", Dimensions=[64, 64, 64])
view, rep = illuminated_view(phantom, [300, 300])
rep.IlluminationMethod = "Filtered Shadows"
rep.ShadowFilterWidth = 5
rep.IlluminationAmbient = 0.2
GetColorTransferFunction("Density").ApplyPreset("Inferno (matplotlib)", True)
GetOpacityTransferFunction("Density").Points = [0.0, 0.0, 0.5, 0.0, 0.25, 0.08, 0.5, 0.0,
                                                1.0, 0.5, 0.5, 0.0]
view.ResetCamera()
GetActiveCamera().Elevation(25)
scene_light(view, [-40, 90, 90], [32, 32, 32], [1.0, 0.8, 0.5])
scene_light(view, [100, 10, -30], [32, 32, 32], [0.4, 0.6, 1.0], point=True)
Render(view)
SaveScreenshot(before, view)
SaveState(state)

ResetSession()
LoadState(state)
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [300, 300]
Render(view)
SaveScreenshot(after, view)

failures = []
rep = GetDisplayProperties(FindSource("IlluminationPhantom1"), view)
if rep.Representation != "Illuminated Volume":
    failures.append("representation came back as %s" % rep.Representation)
if rep.IlluminationMethod != "Filtered Shadows" or rep.ShadowFilterWidth != 5:
    failures.append("method/filter width came back as %s/%s" %
                    (rep.IlluminationMethod, rep.ShadowFilterWidth))
if len(view.AdditionalLights) != 2:
    failures.append("%d lights came back, expected 2" % len(view.AdditionalLights))
difference = image_difference(before, after)
print("mean absolute image difference after reloading: %.3f" % difference)
if difference > 0.5:
    failures.append("reloaded image differs by %.3f" % difference)
finish(failures)
