"""pvpython: the Illuminated Volume representation of image data.

The CT phantom is shown as "Illuminated Volume" with a custom colour map and opacity and
lit by the view's lights. Each check compares the representation with the illumination
filter run separately through paraview.simple on the same data, transfer functions and
lights (given as the flat 14-number list, camera lights converted to world coordinates
here from the camera's position, focal point and view-up): the mean illumination must
agree to 1e-5 (relative). Also: a Light Inspector edit with four lights is a selective
update (one light re-propagated, same result as a full recompute), and so are further moves
of that light (its recorded contribution subtracted); a colour map change
forces a full update; interactive renders keep the lighting and the next still render
updates it; the light kit counts only with Use Light Kit on; the rendered image takes
the lights' colours; a cell array is lit like the filter lights it; a vector array is
coloured and lit by its magnitude or the colour map's component; a suppressed render leaves
no lighting armed for a later render of the window; a light's Shadow Radius softens Filtered
Shadows as the filter's Radius column does.
Usage: pvpython TestIlluminatedVolumeRepresentation.py PLUGIN OUTPUT_DIR
"""
import os
import sys

from paraview.simple import *

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import (Checks, finish, camera_to_world, illuminated_view, info,
                                            image_difference,
                                            light_parameters, scene_light,
                                            mean_colours, mean_illumination,
                                            relative_difference)

LoadPlugin(sys.argv[1], remote=False, ns=globals())
out = sys.argv[2]
check = Checks()


phantom = IlluminationPhantom(Scene="CT Phantom", Dimensions=[64, 64, 64])
view, rep = illuminated_view(phantom, [300, 300])
lut = GetColorTransferFunction("Density")
lut.ApplyPreset("Cool to Warm", True)
pwf = GetOpacityTransferFunction("Density")
pwf.Points = [0.0, 0.0, 0.5, 0.0, 0.3, 0.05, 0.5, 0.0, 1.0, 0.4, 0.5, 0.0]
view.ResetCamera()
camera = GetActiveCamera()
camera.Azimuth(30)
camera.Elevation(20)

key = scene_light(view, [-60, 80, 100], [32, 32, 32], [1.0, 0.7, 0.3])
fill = scene_light(view, [110, 20, 40], [32, 32, 32], [0.3, 0.5, 1.0], point=True, intensity=0.8)


def scene_parameters(light):
    return light_parameters(light, light.Position, light.FocalPoint)


reference = MultiLightIlluminationVolume(Input=phantom, ColorTransferFunction=lut,
                                         OpacityFunction=pwf, ResolutionScale=0.5)


def reference_mean(lights):
    reference.ScalarOpacityUnitDistance = rep.ScalarOpacityUnitDistance
    reference.Lights = sum(lights, [])
    return mean_illumination(reference)


def compare(label, lights):
    Render(view)
    got = info(rep, "IlluminationMean")
    want = reference_mean(lights)
    diff = relative_difference(got, want)
    check(diff < 1e-5, "%s: mean illumination %s vs filter %s (relative %.2g)" %
          (label, ["%.5f" % v for v in got], ["%.5f" % v for v in want], diff))


compare("two scene lights", [scene_parameters(key), scene_parameters(fill)])
check(info(rep, "IlluminationUpdateMode")[0] == 0, "first update is full")
SaveScreenshot(os.path.join(out, "IlluminatedVolumeOrangeBlue.png"), view)

# A camera light: given in the camera's frame, it must be lit where the camera puts it.
side = AddLight(view=view)
side.Coords = "Camera"
side.Type = "Directional"
side.Position = [1, 0.5, 0.2]
side.FocalPoint = [0, 0, 0]
side.DiffuseColor = [0.6, 1.0, 0.6]
side.Intensity = 0.5


def camera_parameters(light):
    return light_parameters(light, camera_to_world(camera, light.Position),
                            camera_to_world(camera, light.FocalPoint))


compare("two scene lights and a camera light",
        [scene_parameters(key), scene_parameters(fill), camera_parameters(side)])

# Interactive renders keep the lighting while the camera (and so the camera light) moves.
before = info(rep, "IlluminationMean")
camera.Azimuth(40)
view.InteractiveRender()
check(relative_difference(info(rep, "IlluminationMean"), before) == 0,
      "an interactive render keeps the illumination")
compare("still render after the camera moved",
        [scene_parameters(key), scene_parameters(fill), camera_parameters(side)])

# Four lights; editing one in the Light Inspector re-propagates that light only.
rim = scene_light(view, [32, -80, -60], [32, 32, 32], [1.0, 1.0, 1.0], intensity=0.6)
lights = lambda: [scene_parameters(key), scene_parameters(fill), camera_parameters(side),
                  scene_parameters(rim)]
compare("four lights", lights())
fill.Position = [110, 60, -20]
compare("after moving one light", lights())
mode = info(rep, "IlluminationUpdateMode")[0]
passes = info(rep, "IlluminationPropagationPasses")[0]
full = MultiLightIlluminationVolume(Input=phantom, ColorTransferFunction=lut, OpacityFunction=pwf,
                                    ResolutionScale=0.5, Lights=sum(lights(), []))
full.UpdatePipeline()
full_passes = int(full.FieldData["PropagationPasses"].GetRange()[0])
check(mode == 1 and passes < full_passes,
      "moving one of four lights is selective (%d passes, a full update %d)" % (passes, full_passes))
Delete(full)
# Dragging it on: its old state now leaves by subtracting its recorded contribution.
for step in range(3):
    fill.Position = [105 - 5 * step, 64 + 4 * step, -17 + 3 * step]
    compare("after dragging that light, step %d" % step, lights())
    check(info(rep, "IlluminationUpdateMode")[0] == 1, "a drag step is selective")

# A colour map change recomputes everything, and the update reports progress (ParaView's
# progress bar listens to the representation).
progress = []
active = rep.GetClientSideObject().GetActiveRepresentation()
observer = active.AddObserver("ProgressEvent", lambda o, e: progress.append(o.GetProgress()))
pwf.Points = [0.0, 0.0, 0.5, 0.0, 0.3, 0.1, 0.5, 0.0, 1.0, 0.6, 0.5, 0.0]
compare("after an opacity change", lights())
check(info(rep, "IlluminationUpdateMode")[0] == 0, "an opacity change forces a full update")
active.RemoveObserver(observer)
check(len(progress) > 2 and max(progress) == 1.0,
      "the full update reported progress (%d events, last %s)" %
      (len(progress), progress[-1] if progress else None))

# The light kit counts only with Use Light Kit on.
for light in (side, rim):
    light.Enable = 0
fill.Enable = 0
view.UseLight = 1
rep.UseLightKit = 0
compare("light kit on in the view, Use Light Kit off", [scene_parameters(key)] +
        [p[:13] + [0] for p in (scene_parameters(fill), camera_parameters(side), scene_parameters(rim))])
rep.UseLightKit = 1
Render(view)
with_kit = info(rep, "IlluminationMean")
check(relative_difference(with_kit, reference_mean([scene_parameters(key)])) > 0.05,
      "Use Light Kit on adds the light kit's lights (mean %s)" % ["%.4f" % v for v in with_kit])
view.UseLight = 0
rep.UseLightKit = 1

# The picture takes the lights' colours: orange key only, then a blue key.
key.DiffuseColor = [1.0, 0.5, 0.1]
Render(view)
orange = os.path.join(out, "IlluminatedVolumeOrangeKey.png")
SaveScreenshot(orange, view)
key.DiffuseColor = [0.1, 0.5, 1.0]
Render(view)
blue = os.path.join(out, "IlluminatedVolumeBlueKey.png")
SaveScreenshot(blue, view)
r_o, _, b_o = mean_colours(orange)
r_b, _, b_b = mean_colours(blue)
check((r_o - b_o) - (r_b - b_b) > 10,
      "image colours follow the light (red - blue: orange key %.1f, blue key %.1f)" %
      (r_o - b_o, r_b - b_b))

# A render ParaView suppresses (SuppressRendering: the representations are updated, nothing
# is drawn) leaves no lighting armed: a later render of the window outside a view's render
# (in parallel, one process's alone, where a collective update would wait for ever) must not
# light; the next render of the view does, with the edited light.
key.DiffuseColor = [1.0, 0.5, 0.1]
view.SuppressRendering = 1
Render(view)
view.SuppressRendering = 0
blue_mean = info(rep, "IlluminationMean")
view.GetRenderWindow().Render()
check(info(rep, "IlluminationMean") == blue_mean,
      "a suppressed render leaves no lighting for the window's next render (mean %s, before %s)"
      % (["%.4f" % v for v in info(rep, "IlluminationMean")], ["%.4f" % v for v in blue_mean]))
Render(view)
check(info(rep, "IlluminationMean")[0] > blue_mean[0],
      "the next render of the view lights with the edited light (red %.4f, blue key %.4f)"
      % (info(rep, "IlluminationMean")[0], blue_mean[0]))

for method, label in ((1, "Filtered Shadows"), (2, "Ray-Marched Reference")):
    rep.IlluminationMethod = label
    Render(view)
    m = info(rep, "IlluminationMean")
    check(m[2] > 0, "%s renders with illumination (mean %s)" % (label, ["%.4f" % v for v in m]))

# A Light Inspector light's Shadow Radius (its size) softens Filtered Shadows as the
# filters' Radius column does: the representation's mean illumination equals
# FilteredVolumetricShadows given the same light at that radius, differs from the hard
# light's, and radius 0 gives the hard light's back.
rep.IlluminationMethod = "Filtered Shadows"
soft_reference = FilteredVolumetricShadows(Input=phantom, ColorTransferFunction=lut,
                                           OpacityFunction=pwf, ResolutionScale=0.5,
                                           FilterWidth=rep.ShadowFilterWidth)
soft_reference.ScalarOpacityUnitDistance = rep.ScalarOpacityUnitDistance


def filtered_mean(radius):
    soft_reference.Lights = scene_parameters(key) + [radius]
    return mean_illumination(soft_reference)


Render(view)
hard_mean = info(rep, "IlluminationMean")
key.ShadowRadius = 12
Render(view)
soft_mean = info(rep, "IlluminationMean")
check(relative_difference(soft_mean, filtered_mean(12)) < 1e-5,
      "Shadow Radius 12: mean illumination %s vs the filter at radius 12 %s"
      % (["%.5f" % v for v in soft_mean], ["%.5f" % v for v in filtered_mean(12)]))
check(relative_difference(soft_mean, hard_mean) > 1e-3,
      "Shadow Radius 12 softens the shadows (mean %s, hard %s)"
      % (["%.5f" % v for v in soft_mean], ["%.5f" % v for v in hard_mean]))
key.ShadowRadius = 0
Render(view)
check(info(rep, "IlluminationMean") == hard_mean,
      "Shadow Radius 0 gives the hard light's illumination back")

# Ambient Occlusion adds an ambient light through the local transmittance, as the filters'
# AmbientOcclusion does: the representation's mean equals the filter's with the same
# strength and radius, is brighter than the lights alone, and 0 gives them back.
rep.AmbientOcclusion = 0.5
rep.AmbientOcclusionRadius = 4
Render(view)
ambient_mean = info(rep, "IlluminationMean")
soft_reference.AmbientOcclusion = 0.5
soft_reference.AmbientOcclusionRadius = 4
filter_ambient = filtered_mean(0)
check(relative_difference(ambient_mean, filter_ambient) < 1e-5,
      "Ambient Occlusion 0.5: mean illumination %s vs the filter's %s"
      % (["%.5f" % v for v in ambient_mean], ["%.5f" % v for v in filter_ambient]))
check(all(a > h + 0.01 for a, h in zip(ambient_mean, hard_mean)),
      "the ambient light brightens the volume (mean %s, lights alone %s)"
      % (["%.5f" % v for v in ambient_mean], ["%.5f" % v for v in hard_mean]))
rep.AmbientOcclusion = 0
Render(view)
check(info(rep, "IlluminationMean") == hard_mean,
      "Ambient Occlusion 0 gives the lights' illumination back")
Delete(soft_reference)

# Gradient shading is compiled into the shader only while it is on. With the Phong factor
# held at 0.5 (ambient 0.5, no diffuse or specular term) the image must equal the unshaded
# one at half the Diffuse weight; the default factor must change it; switching it off
# again must give back the unshaded image.
rep.IlluminationMethod = "Multi-Light Propagation"


def screenshot(name, **properties):
    for key, value in properties.items():
        setattr(rep, key, value)
    path = os.path.join(out, name)
    SaveScreenshot(path, view)
    return path


half = screenshot("GradientShadingOff.png", GradientShading=0, IlluminationDiffuse=0.5)
constant = screenshot("GradientShadingConstant.png", GradientShading=1, IlluminationDiffuse=1.0,
                      PhongAmbient=0.5, PhongDiffuse=0.0, PhongSpecular=0.0)
shaded = screenshot("GradientShadingOn.png", PhongAmbient=0.3, PhongDiffuse=0.7,
                    PhongSpecular=0.2)
again = screenshot("GradientShadingOffAgain.png", GradientShading=0, IlluminationDiffuse=0.5)
rep.IlluminationDiffuse = 1.0
differences = [image_difference(half, constant), image_difference(constant, shaded),
               image_difference(half, again)]
check(differences[0] < 0.01 and differences[1] > 0.3 and differences[2] < 0.01,
      "gradient shading: constant factor 0.5 vs half the diffuse weight %.3f, default factor "
      "vs constant %.2f, off again vs off %.3f (mean levels)" % tuple(differences))

# An array on the cells (ParaView colours the volume by it as such) is lit too: through
# point values averaged from the cells, as the filter does when given the same array.
rep.IlluminationMethod = "Multi-Light Propagation"
cells = PointDatatoCellData(Input=phantom)
Hide(phantom, view)
cell_rep = Show(cells, view)
cell_rep.SetRepresentationType("Illuminated Volume")
ColorBy(cell_rep, ("CELLS", "Density"))
Render(view)
got = info(cell_rep, "IlluminationMean")
on_cells = MultiLightIlluminationVolume(Input=cells, Scalars=["CELLS", "Density"],
                                        ColorTransferFunction=lut, OpacityFunction=pwf,
                                        ResolutionScale=0.5,
                                        ScalarOpacityUnitDistance=cell_rep.ScalarOpacityUnitDistance,
                                        Lights=scene_parameters(key))
want = mean_illumination(on_cells)
check(max(got) > 0 and relative_difference(got, want) < 1e-5,
      "cell data: mean illumination %s vs filter on the cell array %s" %
      (["%.5f" % v for v in got], ["%.5f" % v for v in want]))
SaveScreenshot(os.path.join(out, "IlluminatedVolumeCellData.png"), view)

# A vector array is coloured (and lit) by its magnitude or by the component the colour map
# picks, as ParaView's Volume representation shows it: the same illumination and the same
# image as the one-component array computed by the Calculator, also after switching the
# component on the colour map alone.
gradient = Gradient(Input=phantom, ScalarArray=["POINTS", "Density"])
Hide(cells, view)
vector_rep = Show(gradient, view)
vector_rep.SetRepresentationType("Illuminated Volume")
glut = GetColorTransferFunction("Gradient")
gpwf = GetOpacityTransferFunction("Gradient")
glut.AutomaticRescaleRangeMode = "Never"
single = Calculator(Input=gradient, ResultArrayType="Float")
for component, function in (("Magnitude", "mag(Gradient)"), ("X", "Gradient_X"),
                            ("Y", "Gradient_Y")):
    lo = 0.0 if component == "Magnitude" else -350.0
    ColorBy(vector_rep, ("POINTS", "Gradient", component))
    glut.RescaleTransferFunction(lo, 350.0)
    gpwf.Points = [lo, 0.0, 0.5, 0.0, lo + 0.6 * (350.0 - lo), 0.0, 0.5, 0.0, 350.0, 0.5, 0.5, 0.0]
    Render(view)
    got = info(vector_rep, "IlluminationMean")
    vector_image = os.path.join(out, "IlluminatedVolumeVector%s.png" % component)
    SaveScreenshot(vector_image, view)
    single.Function = function
    single.ResultArrayName = "Gradient_" + component
    Hide(gradient, view)
    single_rep = Show(single, view)
    single_rep.SetRepresentationType("Illuminated Volume")
    ColorBy(single_rep, ("POINTS", "Gradient_" + component))
    single_rep.LookupTable = glut
    single_rep.ScalarOpacityFunction = gpwf
    Render(view)
    want = info(single_rep, "IlluminationMean")
    single_image = os.path.join(out, "IlluminatedVolumeSingle%s.png" % component)
    SaveScreenshot(single_image, view)
    Hide(single, view)
    Show(gradient, view)
    colours = [mean_colours(vector_image), mean_colours(single_image)]
    check(max(got) > 0 and relative_difference(got, want) < 1e-5 and
          max(abs(a - b) for a, b in zip(*colours)) < 0.5,
          "vector array by %s: mean illumination %s vs the one-component array %s, image "
          "colours %s vs %s" % (component, ["%.5f" % v for v in got], ["%.5f" % v for v in want],
                                ["%.1f" % v for v in colours[0]], ["%.1f" % v for v in colours[1]]))

finish(check.failures)
