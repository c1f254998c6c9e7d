"""Run inside the ParaView GUI (paraview --script=...): the picture a user sees.

The engine CT (engine.vti, coloured by ImageFile with the default colour map and opacity)
is shown as plain "Volume", then as "Illuminated Volume", with the default light kit and
the default camera (looking straight at the engine's cut face), then at an oblique camera;
then Illuminated Volume's Resolution Scale is changed and the frame after the change is
grabbed twice. Each frame is grabbed once the lighting is final (the GUI lights in the
background: render_final). Every picture is the frame on the screen (vtkWindowToImageFilter without a
new render: SaveScreenshot renders a fresh frame, which can hide what the view shows),
saved as OUTPUT_DIR/picture_<name>.png for the driver (run_picture_test.py) to measure.
Results go to OUTPUT_DIR/picture_result.txt as "name value" lines; then the script ends the
application (os._exit: the GUI has no exit-after-script option).
Environment: VOLILLUM_PLUGIN (the plugin), VOLILLUM_DATA (the folder of engine.vti),
VOLILLUM_OUTPUT (OUTPUT_DIR).
"""
import os

from paraview.simple import *

from IlluminatedVolumeTestUtilities import (render_final,  # on PYTHONPATH: run_gui_script
                                             write_lines_and_exit)
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

out = os.environ["VOLILLUM_OUTPUT"]
results = []


def grab(view, name):
    """The frame on the screen as it is, without rendering again."""
    grabber = vtkWindowToImageFilter()
    grabber.SetInput(view.GetRenderWindow())
    grabber.ShouldRerenderOff()
    grabber.ReadFrontBufferOff()
    grabber.Update()
    writer = vtkPNGWriter()
    writer.SetInputData(grabber.GetOutput())
    writer.SetFileName(os.path.join(out, "picture_%s.png" % name))
    writer.Write()


try:
    LoadPlugin(os.environ["VOLILLUM_PLUGIN"], remote=False, ns=globals())
    engine = XMLImageDataReader(FileName=[os.path.join(os.environ["VOLILLUM_DATA"], "engine.vti")])
    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    rep = Show(engine, view)
    ColorBy(rep, ("POINTS", "ImageFile"))
    view.ResetCamera()
    camera = GetActiveCamera()
    straight = (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp())
    for representation in ("Volume", "Illuminated Volume"):
        rep.SetRepresentationType(representation)
        camera.SetPosition(straight[0])
        camera.SetFocalPoint(straight[1])
        camera.SetViewUp(straight[2])
        render_final(view)
        name = representation.split()[0].lower()
        grab(view, name + "_straight")
        camera.Azimuth(35)
        camera.Elevation(25)
        render_final(view)
        grab(view, name + "_oblique")
    # A Resolution Scale change: the first frame after it and the next one.
    rep.IlluminationResolutionScale = 0.25
    render_final(view)
    grab(view, "scale_first")
    render_final(view)
    grab(view, "scale_next")
    results.append("representation %s" % str(rep.Representation).strip("'").replace(" ", "_"))
except Exception as error:  # reported to the driver, which fails the test
    results.append("error %s" % str(error).replace("\n", " "))
write_lines_and_exit(os.path.join(out, "picture_result.txt"), results)
