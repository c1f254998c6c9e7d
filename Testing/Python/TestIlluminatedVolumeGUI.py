"""Run inside the ParaView GUI (paraview --script=...): the Illuminated Volume
representation in the real application, with a Light Inspector light toggled.

The CT phantom is shown as "Illuminated Volume" in the GUI's render view with the light
kit off and one orange Light Inspector light, then the light is switched off and on
again; then a filter is given a Lights list of 14 numbers a light. Screenshots of the view are saved at each step; the driver (run_gui_test.py)
checks them. Results go to OUTPUT_DIR/gui_result.txt as "name value" lines; then the
script ends the application (os._exit: the GUI has no exit-after-script option).
Environment: VOLILLUM_PLUGIN (the plugin), VOLILLUM_OUTPUT (OUTPUT_DIR).
"""
import os

from paraview.simple import *

from IlluminatedVolumeTestUtilities import (render_final,  # on PYTHONPATH: run_gui_script
                                             write_lines_and_exit)

out = os.environ["VOLILLUM_OUTPUT"]
results = []
try:
    LoadPlugin(os.environ["VOLILLUM_PLUGIN"], remote=False, ns=globals())
    phantom = IlluminationPhantom(Scene="CT Phantom", Dimensions=[64, 64, 64])
    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    view.UseLight = 0
    rep = Show(phantom, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, ("POINTS", "Density"))
    view.ResetCamera()
    light = AddLight(view=view)
    light.Coords = "Scene"
    light.Position = [-50, 80, 90]
    light.FocalPoint = [32, 32, 32]
    light.DiffuseColor = [1.0, 0.6, 0.3]
    for step, enable in (("on", 1), ("off", 0), ("on_again", 1)):
        light.Enable = enable
        render_final(view)
        SaveScreenshot(os.path.join(out, "gui_%s.png" % step), view, ImageResolution=[300, 300])
        rep.SMProxy.UpdatePropertyInformation()
        mean = rep.SMProxy.GetProperty("IlluminationMean")
        results.append("mean_%s %g" % (step, mean.GetElement(0)))
    results.append("representation %s" % str(rep.Representation).strip("'").replace(" ", "_"))
    # A filter created (or loaded from a state file) with a Lights list of 14 numbers a light
    # (written before the radius column) holds 15 a light in the GUI, as the lights table
    # shows them.
    old = MultiLightIlluminationVolume(Input=phantom,
                                       Lights=[0, 1, 2, 3, 4, 5, 6, 1, 1, 1, 1, 30, 1, 1] * 2)
    results.append("legacy_lights %s" % ",".join("%g" % v for v in old.Lights))
    Delete(old)
except Exception as error:  # reported to the driver, which fails the test
    results.append("error %s" % str(error).replace("\n", " "))
write_lines_and_exit(os.path.join(out, "gui_result.txt"), results)
