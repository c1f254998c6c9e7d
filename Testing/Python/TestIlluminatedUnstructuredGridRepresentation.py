"""pvpython: the Illuminated Volume representation of an unstructured grid.

The three-spheres phantom, split into tetrahedra, is shown as "Illuminated Volume" and lit
by two Light Inspector lights. The representation's mean illumination must equal that of
Unstructured Grid Illumination run separately on the same grid with the same lights,
transfer functions, unit distance and level-0 resolution (1e-5 relative); moving one light
must recompute only that light (UpdateMode 1, one light propagated) and still agree; and
the picture must take the key light's colour (orange vs blue key); a grid coloured by a
cell array is lit like the filter lights that array; a grid coloured by a vector array is
lit by the magnitude or the component the colour map shows, like the filter lights the
one-component array the Calculator makes of it.
Usage: pvpython TestIlluminatedUnstructuredGridRepresentation.py PLUGIN OUTPUT_DIR
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import (Checks, finish, illuminated_view, info, light_parameters,
                                            mean_colours, scene_light,
                                            mean_illumination, relative_difference)

LoadPlugin(sys.argv[1], remote=False, ns=globals())
out = sys.argv[2]
check = Checks()


phantom = IlluminationPhantom(Scene="Three Spheres", Dimensions=[24, 24, 24])
mesh = Tetrahedralize(Input=phantom)
view, rep = illuminated_view(mesh, [300, 300])
rep.Level0Resolution = [32, 32, 32]
lut = GetColorTransferFunction("Density")
lut.ApplyPreset("Grayscale", True)
pwf = GetOpacityTransferFunction("Density")
view.ResetCamera()

key = scene_light(view, [0, 30, 40], [12, 12, 12], [1.0, 0.6, 0.2])
fill = scene_light(view, [-20, 12, 12], [12, 12, 12], [0.3, 0.5, 1.0], point=True)


def parameters():
    return sum([light_parameters(l, l.Position, l.FocalPoint) for l in (key, fill)], [])


def compare(label):
    Render(view)
    reference = UnstructuredGridIllumination(
        Input=mesh, Lights=parameters(), ColorTransferFunction=lut, OpacityFunction=pwf,
        ScalarOpacityUnitDistance=rep.ScalarOpacityUnitDistance, Level0Resolution=[32, 32, 32])
    got = info(rep, "IlluminationMean")
    want = mean_illumination(reference)
    Delete(reference)
    diff = relative_difference(got, want)
    check(diff < 1e-5, "%s: mean illumination %s vs filter %s (relative %.2g)" %
          (label, ["%.5f" % v for v in got], ["%.5f" % v for v in want], diff))


compare("two lights")
check(info(rep, "IlluminationUpdateMode")[0] == 0, "first update is full")
orange = os.path.join(out, "IlluminatedGridOrangeKey.png")
SaveScreenshot(orange, view)

fill.Position = [12, -20, 14]
compare("after moving one light")
mode = info(rep, "IlluminationUpdateMode")[0]
passes = info(rep, "IlluminationPropagationPasses")[0]
check(mode == 1 and passes == 1, "moving one light: mode %d, %d light(s) propagated" % (mode, passes))

key.DiffuseColor = [0.2, 0.6, 1.0]
fill.DiffuseColor = [0.2, 0.6, 1.0]
Render(view)
check(info(rep, "IlluminationPropagationPasses")[0] == 0, "a colour change propagates no light")
blue = os.path.join(out, "IlluminatedGridBlueKey.png")
SaveScreenshot(blue, view)
r_o, _, b_o = mean_colours(orange)
r_b, _, b_b = mean_colours(blue)
check((r_o - b_o) - (r_b - b_b) > 10, "image colours follow the lights (red - blue: %.1f vs %.1f)" %
      (r_o - b_o, r_b - b_b))

# A grid coloured by a cell array is lit like the filter lights that array.
cells = PointDatatoCellData(Input=mesh)
Hide(mesh, view)
cell_rep = Show(cells, view)
cell_rep.SetRepresentationType("Illuminated Volume")
ColorBy(cell_rep, ("CELLS", "Density"))
cell_rep.Level0Resolution = [32, 32, 32]
Render(view)
on_cells = UnstructuredGridIllumination(
    Input=cells, Scalars=["CELLS", "Density"], Lights=parameters(), ColorTransferFunction=lut,
    OpacityFunction=pwf, ScalarOpacityUnitDistance=cell_rep.ScalarOpacityUnitDistance,
    Level0Resolution=[32, 32, 32])
got = info(cell_rep, "IlluminationMean")
want = mean_illumination(on_cells)
check(max(got) > 0 and relative_difference(got, want) < 1e-5,
      "cell data: mean illumination %s vs filter on the cell array %s" %
      (["%.5f" % v for v in got], ["%.5f" % v for v in want]))
SaveScreenshot(os.path.join(out, "IlluminatedGridCellData.png"), view)

# A grid coloured by a vector array is lit by the magnitude or the component the colour map
# shows (switched on the colour map alone), like the filter lights the one-component array
# the Calculator makes of it.
gradient = Gradient(Input=mesh, ScalarArray=["POINTS", "Density"])
Hide(cells, view)
vector_rep = Show(gradient, view)
vector_rep.SetRepresentationType("Illuminated Volume")
vector_rep.Level0Resolution = [32, 32, 32]
glut = GetColorTransferFunction("Gradient")
gpwf = GetOpacityTransferFunction("Gradient")
glut.AutomaticRescaleRangeMode = "Never"
for component, function, lo, hi in (("Magnitude", "mag(Gradient)", 0.0, 170.0),
                                    ("X", "Gradient_X", -100.0, 100.0)):
    ColorBy(vector_rep, ("POINTS", "Gradient", component))
    glut.RescaleTransferFunction(lo, hi)
    gpwf.Points = [lo, 0.0, 0.5, 0.0, lo + 0.3 * (hi - lo), 0.0, 0.5, 0.0, hi, 1.0, 0.5, 0.0]
    Render(view)
    got = info(vector_rep, "IlluminationMean")
    SaveScreenshot(os.path.join(out, "IlluminatedGridVector%s.png" % component), view)
    single = Calculator(Input=gradient, ResultArrayType="Float", Function=function,
                        ResultArrayName="Single")
    reference = UnstructuredGridIllumination(
        Input=single, Scalars=["POINTS", "Single"], Lights=parameters(),
        ColorTransferFunction=glut, OpacityFunction=gpwf,
        ScalarOpacityUnitDistance=vector_rep.ScalarOpacityUnitDistance,
        Level0Resolution=[32, 32, 32])
    want = mean_illumination(reference)
    Delete(reference)
    Delete(single)
    check(max(got) > 0 and relative_difference(got, want) < 1e-5,
          "vector array by %s: mean illumination %s vs filter on the one-component array %s" %
          (component, ["%.5f" % v for v in got], ["%.5f" % v for v in want]))

finish(check.failures)
