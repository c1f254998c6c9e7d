"""pvpython: the plugin as `cmake --install` placed it, found the way the README says.

ParaView loads it by itself (no LoadPlugin) from PV_PLUGIN_PATH or PV_PLUGIN_CONFIG_FILE,
which the test sets; the plugin must come from the install prefix, its filters must give
the propagated illumination close to the ray-marched one, and the installed volillum-render
must write the same picture as the build tree's.
Usage: pvpython TestInstalledPlugin.py PREFIX INSTALLED_CLI BUILD_CLI OUTPUT_DIR
"""
import os
import subprocess
import sys

from paraview import servermanager
from paraview.simple import *

from IlluminatedVolumeTestUtilities import Checks, finish, pixels_apart, png_scalars, relative_rms

prefix, installed_cli, build_cli, output_dir = [os.path.realpath(a) for a in sys.argv[1:5]]
os.makedirs(output_dir, exist_ok=True)
check = Checks()

plugins = servermanager.vtkSMProxyManager.GetProxyManager().GetPluginManager().GetLocalInformation()
loaded = [plugins.GetPluginFileName(i) for i in range(plugins.GetNumberOfPlugins())
          if plugins.GetPluginName(i) == "VolumetricIllumination" and plugins.GetPluginLoaded(i)]
check(len(loaded) == 1 and os.path.realpath(loaded[0]).startswith(prefix + os.sep),
      "the plugin loaded by itself from the install prefix (%s)" % loaded)

if loaded:
    phantom = IlluminationPhantom(Scene="Three Spheres", Dimensions=[32, 32, 32])
    opacity = GetOpacityTransferFunction("Density")
    opacity.Points = [0.0, 0.0, 0.5, 0.0, 200.0, 0.3, 0.5, 0.0]
    lights = [1, -40, 16, 16, 16, 16, 16, 1, 1, 0, 1, 180, 1, 1,
              0, 0, 0, 1, 0.2, 0.1, 0, 0.3, 0.5, 1, 0.7, 30, 1, 1]
    values = []
    for filter in (MultiLightIlluminationVolume, RayMarchedIllumination):
        lit = filter(Input=phantom, OpacityFunction=opacity, Lights=lights)
        lit.UpdatePipeline()
        values.append(servermanager.Fetch(lit).GetPointData().GetArray("Illumination"))
    rms = relative_rms(values[0], values[1])
    check(rms < 0.1, "installed propagation against installed ray marching: RMS %.4f < 0.1" % rms)


def render(cli, name):
    path = os.path.join(output_dir, name)
    subprocess.run([cli, "--phantom", "spheres", "--dims", "32", "--size", "96", "96",
                    "--output", path], check=True)
    return path


installed, built = render(installed_cli, "installed.png"), render(build_cli, "build.png")
different = pixels_apart(installed, built, 1)
(colours,) = png_scalars(built)
lit = sum(1 for i in range(colours.GetNumberOfValues()) if colours.GetValue(i) > 0)
check(different == 0 and lit > 0,
      "the installed volillum-render's picture equals the build tree's (%d of %d pixels differ, "
      "%d values lit)" % (different, colours.GetNumberOfTuples(), lit))
finish(check.failures)
