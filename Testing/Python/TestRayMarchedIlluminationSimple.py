"""pvpython: load the plugin and run RayMarchedIllumination through paraview.simple.

The slab phantom (value 1 for z indices 16..47, 0 elsewhere) is lit by one white
directional light shining down -z with grey attenuation. Below the slab the light has
crossed the linearly interpolated slab profile, whose integral is 32 voxels (31 between
the first and last slab points plus two half-voxel ramps), so the illumination must be
exp(-sigma * 32) with sigma = -ln(1 - 0.05); above
the slab it must be 1. A second light doubles it; a Lights list that is not whole lights
(17 numbers) gives an error and an empty output. FilteredVolumetricShadows takes the Lights
in both layouts (15 numbers a light with the radius, 14 without) and softens its shadows
with the radius. Usage: pvpython TestRayMarchedIlluminationSimple.py PLUGIN
"""
import math
import sys

from paraview.simple import *

LoadPlugin(sys.argv[1], remote=False, ns=globals())

slab = IlluminationPhantom(Scene="Slab", Dimensions=[32, 32, 64], SlabBegin=16, SlabEnd=47)
opacity = GetOpacityTransferFunction("Density")
opacity.Points = [0.0, 0.0, 0.5, 0.0, 1.0, 0.05, 0.5, 0.0]
illumination = RayMarchedIllumination(Input=slab)
illumination.OpacityFunction = opacity
illumination.ChromaticAttenuation = 0
illumination.Lights = [0, 16, 16, 100, 16, 16, 0, 1, 1, 1, 1, 30, 1, 1]
illumination.UpdatePipeline()

result = servermanager.Fetch(illumination)
values = result.GetPointData().GetArray("Illumination")
dims = result.GetDimensions()
assert dims == (32, 32, 64), dims
sigma = -math.log(1 - 0.05)
below = math.exp(-sigma * 32)
failures = []
for k, expected in ((0, below), (10, below), (50, 1.0), (63, 1.0)):
    got = values.GetComponent(5 + 32 * (7 + 32 * k), 0)
    if abs(got - expected) > 1e-3 * expected:
        failures.append("z=%d: %g, expected %g" % (k, got, expected))
field = result.GetFieldData()
if field.GetArray("UpdateMode").GetValue(0) != 0:
    failures.append("UpdateMode should be 0 (full)")
if field.GetArray("PropagationPasses").GetValue(0) != 1:
    failures.append("PropagationPasses should be 1")
if not field.GetArray("UpdateSeconds").GetValue(0) > 0:
    failures.append("UpdateSeconds should be positive")

# A second light doubles the light above the slab (linearity through the proxy API).
illumination.Lights = [0, 16, 16, 100, 16, 16, 0, 1, 1, 1, 1, 30, 1, 1] * 2
illumination.UpdatePipeline()
top = servermanager.Fetch(illumination).GetPointData().GetArray("Illumination").GetComponent(
    5 + 32 * (7 + 32 * 63), 0)
if abs(top - 2.0) > 1e-6:
    failures.append("two lights above the slab give %g, expected 2" % top)

# A list that is not whole lights (the server manager itself would drop an incomplete last
# row): an error and an empty output, until the list is whole again.
illumination.Lights = [0, 16, 16, 100, 16, 16, 0, 1, 1, 1, 1, 30, 1, 1, 0, 16, 16]
illumination.UpdatePipeline()
if servermanager.Fetch(illumination).GetNumberOfPoints() != 0:
    failures.append("17 numbers in Lights were accepted")
illumination.Lights = [0, 16, 16, 100, 16, 16, 0, 1, 1, 1, 1, 30, 1, 1]
illumination.UpdatePipeline()
if servermanager.Fetch(illumination).GetNumberOfPoints() != 32 * 32 * 64:
    failures.append("14 numbers in Lights after 17 were refused")

# The Lights layouts: 15 numbers a light (the last is the radius), or the 14 of lists
# written before the radius (radius 0). Filtered shadows of the slab from a light 20 degrees
# across equal a hard light's under its middle and differ at its sides, where the cone
# toward the light passes partly beside the slab.
filtered = FilteredVolumetricShadows(Input=slab, OpacityFunction=opacity, FilterWidth=0)
filtered.ChromaticAttenuation = 0
light = [0, 16, 16, 100, 16, 16, 0, 1, 1, 1, 1, 30, 1, 1]


def filtered_with(lights):
    filtered.Lights = lights
    filtered.UpdatePipeline()
    array = servermanager.Fetch(filtered).GetPointData().GetArray("Illumination")
    return [array.GetComponent(i, 0) for i in range(array.GetNumberOfTuples())]


legacy = filtered_with(light)
hard = filtered_with(light + [0])
soft = filtered_with(light + [20])
if legacy != hard:
    failures.append("14 numbers a light differ from 15 with radius 0")
centre = 16 + 32 * (16 + 32 * 8)  # below the slab, far from its sides
side = 0 + 32 * (16 + 32 * 8)
if abs(soft[centre] - hard[centre]) > 1e-6 * hard[centre]:
    failures.append("a 20-degree light changed the shadow under the slab's middle: %g, %g"
                    % (soft[centre], hard[centre]))
if not abs(soft[side] - hard[side]) > 1e-3:
    failures.append("a 20-degree light left the slab's side as a hard light does: %g, %g"
                    % (soft[side], hard[side]))

print("\n".join(failures) if failures else "RayMarchedIllumination through paraview.simple: ok")
sys.exit(1 if failures else 0)
