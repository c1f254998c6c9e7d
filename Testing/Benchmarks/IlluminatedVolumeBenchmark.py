"""Benchmark of the Illuminated Volume representation through paraview.simple, as users run it.

On the engine volume (../shared/data/volumes/engine.vti) at 512x512, one run:
1. Frame cost with the illumination already computed: Illuminated Volume vs a plain Volume
   frame, a Volume frame with Shade on and ParaView's built-in volumetric shadows with the
   default light kit (Shade on, GlobalIlluminationReach 0.5, VolumetricScatteringBlending 1).
2. Time from a Light Inspector light edit to the updated frame (ResolutionScale 0.5), with 2
   and 8 scene lights: one light moved (selective update), the same light moved again as
   while it is dragged (its record is subtracted), and every light moved (full update).
3. Asynchronous Lighting: on the engine resampled to 256^3 (Resolution Scale 0.5 and 1, the
   light kit on, 512x512), the time Render() blocks and the time to the final frame after a
   40-degree camera turn (every light kit light moves), a Light Inspector light edit and an
   opacity edit, synchronous against asynchronous. The asynchronous final frame is taken as
   the GUI takes it: a render when a finished illumination is ready (IlluminationStatus).
Prints the ratios and writes them as JSON (--json FILE). --smoke: the CT phantom at 64^3,
128x128, one frame each (a check that the benchmark runs, not a measurement).
Usage: pvpython IlluminatedVolumeBenchmark.py PLUGIN DATA_DIR [--smoke] [--json FILE]
"""
import json
import math
import os
import sys
import time

from paraview.simple import *

plugin, data_dir = sys.argv[1:3]
plugin = os.path.abspath(plugin)  # ParaView 5.13 loads a plugin by its absolute path only
smoke = "--smoke" in sys.argv
json_path = sys.argv[sys.argv.index("--json") + 1] if "--json" in sys.argv else None
LoadPlugin(plugin, remote=False, ns=globals())

engine = os.path.join(data_dir, "volumes", "engine.vti")
if smoke or not os.path.exists(engine):
    source = IlluminationPhantom(Scene="CT Phantom", Dimensions=[64, 64, 64])
    name, size, frames = "CT phantom 64^3 (smoke)", [128, 128], 1
else:
    source = XMLImageDataReader(FileName=[engine])
    name, size, frames = "engine", [512, 512], 3
source.UpdatePipeline()
array = source.PointData.keys()[0]
bounds = source.GetDataInformation().GetBounds()
centre = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]
extent = max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))

view = CreateView("RenderView")
view.ViewSize = size
view.OrientationAxesVisibility = 0
rep = Show(source, view)
rep.SetRepresentationType("Volume")
ColorBy(rep, ("POINTS", array))
rep.RescaleTransferFunctionToDataRange(True)
view.ResetCamera()
camera = GetActiveCamera()
camera.Elevation(20)


def frame_seconds(count):
    """Mean still-render time over count frames, the camera turning 2 degrees a frame."""
    Render(view)  # warm up: shader compilation, uploads, any illumination update
    start = time.perf_counter()
    for _ in range(count):
        camera.Azimuth(2)
        Render(view)
    return (time.perf_counter() - start) / count


results = {"volume": name, "size": size}
times = {}
times["volume"] = frame_seconds(frames)
rep.Shade = 1
times["volume_shade"] = frame_seconds(frames)
rep.GlobalIlluminationReach = 0.5
rep.VolumetricScatteringBlending = 1.0
times["builtin_shadows"] = frame_seconds(1)
rep.GlobalIlluminationReach = 0.0
rep.VolumetricScatteringBlending = 0.0
rep.Shade = 0

# Illuminated Volume lit by scene lights (the light kit off: camera turns keep the lighting).
view.UseLight = 0
lights = []


def place(light, index, turn):
    angle = 2 * math.pi * index / 8 + turn
    light.Coords = "Scene"
    light.Position = [centre[0] + 2 * extent * math.cos(angle),
                      centre[1] + 2 * extent * math.sin(angle), centre[2] + extent]
    light.FocalPoint = centre


for i in range(2):
    light = AddLight(view=view)
    place(light, i, 0.0)
    light.DiffuseColor = [1.0, 0.8, 0.6] if i % 2 == 0 else [0.6, 0.8, 1.0]
    lights.append(light)
rep.SetRepresentationType("Illuminated Volume")
rep.IlluminationResolutionScale = 0.5
times["illuminated"] = frame_seconds(frames)


def edit_seconds(moved):
    """Time from moving the given lights to the updated frame, and the update mode."""
    start = time.perf_counter()
    for i in moved:
        place(lights[i], i, 0.3 * (1 + edit_seconds.calls))
    Render(view)
    elapsed = time.perf_counter() - start
    edit_seconds.calls += 1
    rep.SMProxy.UpdatePropertyInformation()
    return (elapsed, int(rep.SMProxy.GetProperty("IlluminationUpdateMode").GetElement(0)),
            rep.SMProxy.GetProperty("IlluminationUpdateSeconds").GetElement(0))


edit_seconds.calls = 0
edits = {}
for count in (2, 8):
    while len(lights) < count:
        light = AddLight(view=view)
        place(light, len(lights), 0.0)
        light.Intensity = 0.5
        lights.append(light)
    Render(view)
    one, one_mode, one_update = edit_seconds([0])
    # The same light moved again, as while it is dragged (median of 4 moves).
    drag = sorted(edit_seconds([0]) for _ in range(4))[1:3]
    full, full_mode, full_update = edit_seconds(range(count))
    edits[count] = {"one_light_s": one, "one_light_mode": one_mode, "all_lights_s": full,
                    "all_lights_mode": full_mode, "speedup": full / one,
                    "one_light_update_s": one_update, "all_lights_update_s": full_update,
                    "update_speedup": full_update / one_update,
                    "drag_s": (drag[0][0] + drag[1][0]) / 2,
                    "drag_update_s": (drag[0][2] + drag[1][2]) / 2}

# 3. Asynchronous Lighting against synchronous, as the GUI sees it.
Delete(rep)
for light in lights:
    RemoveLight(light)
view.UseLight = 1
if smoke:
    large = IlluminationPhantom(Scene="CT Phantom", Dimensions=[64, 64, 64])
else:
    large = ResampleToImage(Input=source, SamplingDimensions=[256, 256, 256])
large.UpdatePipeline()
big = Show(large, view)
big.SetRepresentationType("Illuminated Volume")
ColorBy(big, ("POINTS", array))
big.RescaleTransferFunctionToDataRange(True)
opacity = GetOpacityTransferFunction(array)
inspector = AddLight(view=view)
place(inspector, 0, 0.0)
status = servermanager.ProxyManager().SMProxyManager.NewProxy("misc", "IlluminationStatus")
status.UpdateVTKObjects()


def status_flag(name):
    status.UpdatePropertyInformation()
    return status.GetProperty(name).GetElement(0) != 0


def until_final():
    """Render as the GUI does (when a finished illumination is ready) until nothing is pending."""
    while True:
        big.SMProxy.UpdatePropertyInformation()
        if not big.SMProxy.GetProperty("IlluminationPending").GetElement(0):
            return
        if status_flag("IlluminationReady"):
            Render(view)
        else:
            time.sleep(0.01)


def action_seconds(action):
    """Render() blocking time and time to the final frame after action()."""
    action()
    start = time.perf_counter()
    Render(view)
    blocked = time.perf_counter() - start
    until_final()
    return blocked, time.perf_counter() - start


def edit_light():
    place(inspector, 0, 0.3 * (1 + action_seconds.turn))


def edit_opacity():
    """Every point's opacity scaled by 1.1 or back, turn by turn."""
    factor = 1.1 if action_seconds.turn % 2 else 1.0
    opacity.Points = [v * factor if i % 4 == 1 else v for i, v in enumerate(base_opacity)]


base_opacity = list(opacity.Points)
actions = {"camera_turn": lambda: camera.Azimuth(40), "light_edit": edit_light,
           "opacity_edit": edit_opacity}
action_seconds.turn = 0
background = {}
for scale in ((0.5,) if smoke else (0.5, 1.0)):
    big.IlluminationResolutionScale = scale
    for mode in (0, 1):
        big.AsynchronousLighting = mode
        Render(view)
        until_final()
        for name, action in actions.items():
            # The second of two runs: the first warms the coarse stage up.
            for _ in range(2):
                action_seconds.turn += 1
                blocked, final = action_seconds(action)
            background["%s scale %g %s" % (name, scale, "async" if mode else "sync")] = {
                "render_s": blocked, "final_frame_s": final}
status.UnRegister(None)

ratios = {
    "builtin_shadows_over_volume": times["builtin_shadows"] / times["volume"],
    "shade_over_volume": times["volume_shade"] / times["volume"],
    "illuminated_over_volume": times["illuminated"] / times["volume"],
    "builtin_shadows_over_illuminated": times["builtin_shadows"] / times["illuminated"],
}
print("Illuminated Volume benchmark (%s, %dx%d, one run)" % (name, size[0], size[1]))
print("  frame cost relative to a plain Volume frame (%.3f s):" % times["volume"])
print("    Volume, Shade on                      %7.2fx" % ratios["shade_over_volume"])
print("    Illuminated Volume                    %7.2fx" % ratios["illuminated_over_volume"])
print("    built-in volumetric shadows           %7.2fx" % ratios["builtin_shadows_over_volume"])
print("  built-in shadows frame / Illuminated Volume frame: %.1fx (target >= 30)" %
      ratios["builtin_shadows_over_illuminated"])
print("  light edit to updated frame (ResolutionScale 0.5):")
for count, e in edits.items():
    print("    %d lights: one light moved (mode %d) vs all moved (mode %d): edit to frame %.2fx "
          "faster, illumination update alone %.2fx" %
          (count, e["one_light_mode"], e["all_lights_mode"], e["speedup"], e["update_speedup"]))
print("  target: one-light edit with 8 lights >= 3x faster than a full update")
for count, e in edits.items():
    print("    %d lights, one light moved: edit to frame %.3f s (update %.3f s); moved again "
          "(dragged): %.3f s (update %.3f s)" % (count, e["one_light_s"], e["one_light_update_s"],
                                                e["drag_s"], e["drag_update_s"]))
latency = edits[8]["drag_s"]
print("  8 lights, one dragged: edit to frame %.3f s; target <= a plain frame + 0.1 s = %.3f s"
      % (latency, times["volume"] + 0.1))
ratios["drag_edit_to_frame_over_plain_frame_plus_0.1s"] = latency / (times["volume"] + 0.1)
print("  Asynchronous Lighting (%s, light kit on): Render() blocks / final frame after, s" %
      ("CT phantom 64^3" if smoke else "engine 256^3"))
for key in sorted(k for k in background if k.endswith(" sync")):
    sync, asyn = background[key], background[key[:-5] + " async"]
    print("    %-28s synchronous %6.3f / %6.3f   asynchronous %6.3f / %6.3f   (final %.2fx)" %
          (key[:-5], sync["render_s"], sync["final_frame_s"], asyn["render_s"],
           asyn["final_frame_s"], asyn["final_frame_s"] / sync["final_frame_s"]))
results.update({"asynchronous_lighting": background})
results.update({"frame_seconds": times, "ratios": ratios, "light_edits": {str(k): v for k, v in edits.items()}})
if json_path:
    with open(json_path, "w") as f:
        json.dump(results, f, indent=2)
sys.stdout.flush()
os._exit(0)  # see IlluminatedVolumeTestUtilities.finish: ParaView's teardown under Xvfb
