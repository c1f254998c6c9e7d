"""pvpython: MultiLightIlluminationVolume through paraview.simple.

Three lights light the three-spheres phantom. Editing one light's colour through the Lights
property must give a selective update (UpdateMode 1) whose result equals a fresh filter
computing the edited lights in full (the fixed-point accumulation cancels old states
exactly), and the propagated volume must stay close to RayMarchedIllumination.
Usage: pvpython TestMultiLightIlluminationVolumeSimple.py PLUGIN
"""
import sys

from paraview.simple import *

from IlluminatedVolumeTestUtilities import relative_rms

LoadPlugin(sys.argv[1], remote=False, ns=globals())

phantom = IlluminationPhantom(Scene="Three Spheres", Dimensions=[48, 48, 48])
opacity = GetOpacityTransferFunction("Density")
opacity.Points = [0.0, 0.0, 0.5, 0.0, 200.0, 0.3, 0.5, 0.0]
yellow = [1, -40, 24, 24, 24, 24, 24, 1, 1, 0, 1, 180, 1, 1]
blue = [1, 90, 24, 30, 24, 24, 24, 0, 0, 1, 1, 180, 1, 1]
top = [0, 0, 0, 1, 0.2, 0.1, 0, 1, 1, 1, 0.5, 30, 1, 1]
blue_edited = blue[:7] + [0, 1, 0.5] + blue[10:]


def illumination(proxy):
    proxy.UpdatePipeline()
    data = servermanager.Fetch(proxy)
    return data, data.GetPointData().GetArray("Illumination")


def max_relative(a, b):
    worst = largest = 0.0
    for i in range(a.GetNumberOfValues()):
        worst = max(worst, abs(a.GetValue(i) - b.GetValue(i)))
        largest = max(largest, abs(b.GetValue(i)))
    return worst / largest


failures = []
lit = MultiLightIlluminationVolume(Input=phantom, OpacityFunction=opacity)
lit.Lights = yellow + blue + top
data, _ = illumination(lit)
if data.GetFieldData().GetArray("UpdateMode").GetValue(0) != 0:
    failures.append("the first update should be full")
lit.Lights = yellow + blue_edited + top
data, edited = illumination(lit)
if data.GetFieldData().GetArray("UpdateMode").GetValue(0) != 1:
    failures.append("editing one of three lights should be a selective update")

fresh = MultiLightIlluminationVolume(Input=phantom, OpacityFunction=opacity)
fresh.Lights = yellow + blue_edited + top
_, full = illumination(fresh)
difference = max_relative(edited, full)
if difference > 1e-6:
    failures.append("selective differs from full by %g" % difference)

reference = RayMarchedIllumination(Input=phantom, OpacityFunction=opacity)
reference.Lights = yellow + blue_edited + top
_, exact = illumination(reference)
rms = relative_rms(full, exact)
print("RMS relative difference to RayMarchedIllumination: %g" % rms)
if rms > 0.1:
    failures.append("RMS relative difference to the reference %g exceeds 0.1" % rms)

print("\n".join(failures) if failures else "MultiLightIlluminationVolume through paraview.simple: ok")
sys.exit(1 if failures else 0)
