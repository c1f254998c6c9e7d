"""pvpython: UnstructuredGridIllumination through paraview.simple.

The three-spheres phantom, split into tetrahedra by ParaView's Tetrahedralize, is lit by
two lights. Moving one light through the Lights property must recompute that light only
(UpdateMode 1, PropagationPasses 1) and give what a fresh filter computes in full (1e-5);
a colour change must propagate no light at all; LitColors must be the transfer-function
colour times the Illumination; and ParaView's own volume representation, coloured by
LitColors with Map Scalars off, must show the lights' colours (orange key light: red
exceeds blue; switched to blue: the other way round).
Usage: pvpython TestUnstructuredGridIlluminationSimple.py PLUGIN
"""
import sys

from paraview.simple import *

LoadPlugin(sys.argv[1], remote=False, ns=globals())

phantom = IlluminationPhantom(Scene="Three Spheres", Dimensions=[24, 24, 24])
mesh = Tetrahedralize(Input=phantom)
key = [0, 0, 0, 0, 0.2, 0.1, -1, 1, 0.9, 0.6, 1, 30, 1, 1]
fill = [1, -20, 12, 12, 12, 12, 12, 0.3, 0.5, 1, 1, 180, 1, 1]
fill_moved = [1, 12, -20, 14] + fill[4:]


def fetch(proxy):
    proxy.UpdatePipeline()
    data = servermanager.Fetch(proxy)
    fields = data.GetFieldData()
    return (data, data.GetPointData().GetArray("Illumination"),
            int(fields.GetArray("UpdateMode").GetValue(0)),
            int(fields.GetArray("PropagationPasses").GetValue(0)))


def make(lights):
    return UnstructuredGridIllumination(Input=mesh, Lights=lights, Level0Resolution=[32, 32, 32],
                                        ScatteringStrength=[0.2, 0.2, 0.2])


failures = []
lit = make(key + fill)
_, first, mode, passes = fetch(lit)
if (mode, passes) != (0, 2):
    failures.append("first update: mode %d passes %d, expected full with 2" % (mode, passes))
lit.Lights = key + fill_moved
data, moved, mode, passes = fetch(lit)
if (mode, passes) != (1, 1):
    failures.append("moving one light: mode %d passes %d, expected selective with 1" % (mode, passes))
_, full, _, _ = fetch(make(key + fill_moved))
worst = max(abs(moved.GetValue(i) - full.GetValue(i)) for i in range(full.GetNumberOfValues()))
print("selective vs full: %g" % worst)
if worst > 1e-5:
    failures.append("selective update differs from a full recompute by %g" % worst)
lit.Lights = key[:7] + [0.2, 1, 0.2] + key[10:] + fill_moved
_, _, _, passes = fetch(lit)
if passes != 0:
    failures.append("a colour change propagated %d lights" % passes)

# LitColors = grey ramp colour x Illumination (no transfer function given).
scalars = data.GetPointData().GetScalars()
lo, hi = scalars.GetRange()
colors = data.GetPointData().GetArray("LitColors")
for i in range(0, data.GetNumberOfPoints(), 97):
    grey = (scalars.GetValue(i) - lo) / (hi - lo)
    want = round(255 * min(1.0, grey * moved.GetComponent(i, 0)))
    if abs(colors.GetComponent(i, 0) - want) > 1:
        failures.append("LitColors red at %d is %g, expected %g" % (i, colors.GetComponent(i, 0), want))
        break



def mean_red_blue(path):
    from vtkmodules.vtkIOImage import vtkPNGReader
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    pixels = reader.GetOutput().GetPointData().GetScalars()
    red = blue = 0.0
    for i in range(pixels.GetNumberOfTuples()):
        red += pixels.GetComponent(i, 0)
        blue += pixels.GetComponent(i, 2)
    return red, blue


view = CreateRenderView()
view.ViewSize = [160, 160]
view.UseColorPaletteForBackground = 0
view.Background = [0, 0, 0]
view.OrientationAxesVisibility = 0
shown = UnstructuredGridIllumination(Input=mesh, Level0Resolution=[32, 32, 32])
display = Show(shown, view)
display.SetRepresentationType("Volume")
ColorBy(display, ("POINTS", "LitColors"))
display.MapScalars = 0
display.MultiComponentsMapping = 1
view.ResetCamera()
balance = []
for colour in ([1, 0.5, 0.1], [0.1, 0.5, 1]):
    shown.Lights = [0, 0, 0, 0, 0.2, 0.1, -1] + colour + [1, 30, 1, 1]
    Render(view)
    path = "volillum-ugrid-%d.png" % len(balance)
    SaveScreenshot(path, view)
    balance.append(mean_red_blue(path))
print("rendered red/blue sums: orange light %s, blue light %s" % (balance[0], balance[1]))
if not (balance[0][0] > 1.5 * balance[0][1] and balance[1][1] > 1.5 * balance[1][0]):
    failures.append("the volume rendering does not show the lights' colours: %s" % balance)

# Release the render window before the interpreter exits (otherwise the GLX context is
# torn down after the X connection and the process dies with an X error).
Delete(view)
del view

for f in failures:
    print("FAIL: " + f)
sys.exit(1 if failures else 0)
