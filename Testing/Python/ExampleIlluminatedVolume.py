"""Example: the CT phantom in an "Illuminated Volume" representation lit by two coloured
Light Inspector lights, saved as a PNG (the README's example; it runs as a test).
Usage: pvpython ExampleIlluminatedVolume.py PLUGIN OUTPUT.png
"""
import os
import sys

from paraview.simple import *

# ParaView 5.13 loads a plugin given by its absolute path only.
LoadPlugin(os.path.abspath(sys.argv[1]), remote=False, ns=globals())
phantom = IlluminationPhantom(Scene="CT Phantom", Dimensions=[96, 96, 96])
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [400, 400]
rep = Show(phantom, view)
rep.SetRepresentationType("Illuminated Volume")
ColorBy(rep, ("POINTS", "Density"))
view.UseLight = 0  # only the lights below

key = AddLight(view=view)
key.Coords, key.Position, key.FocalPoint = "Scene", [-50, 80, 90], [48, 48, 48]
key.DiffuseColor = [1, 0.6, 0.3]
fill = AddLight(view=view)
fill.Coords, fill.Type, fill.ConeAngle = "Scene", "Positional", 180
fill.Position, fill.FocalPoint = [150, 20, 60], [48, 48, 48]
fill.DiffuseColor, fill.Intensity = [0.3, 0.5, 1], 0.7

view.ResetCamera()
SaveScreenshot(sys.argv[2], view)
rep.SMProxy.UpdatePropertyInformation()  # the read-only report of the last update
print("update mode (0 full, 1 selective):",
      rep.SMProxy.GetProperty("IlluminationUpdateMode").GetElement(0))
print("update seconds:", rep.SMProxy.GetProperty("IlluminationUpdateSeconds").GetElement(0))

fill.Position = [150, 60, 20]  # a Light Inspector edit: only this light is re-propagated
Render(view)
rep.SMProxy.UpdatePropertyInformation()
print("after moving one light, update mode:",
      rep.SMProxy.GetProperty("IlluminationUpdateMode").GetElement(0))
