"""Run inside the ParaView GUI: how long the GUI freezes after what users do, lighting
synchronously (as before Asynchronous Lighting) and in the background.

  PYTHONPATH=Testing/Python xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" paraview --dr \
      --script=Testing/Benchmarks/GuiFreezeBenchmark.py
  (environment: VOLILLUM_PLUGIN the plugin, VOLILLUM_VOLUME a volume file ParaView reads,
   VOLILLUM_OUTPUT a file for the results)

The volume is shown as "Illuminated Volume" (default settings, light kit on, the GUI's
view). For each action (a 40-degree camera turn, an opacity edit, a Light Inspector light
made positional, Method changed to Filtered Shadows, Resolution Scale changed to 1) and each
mode, the script performs the action, renders, and returns to the Qt event loop; a 20 ms
timer of the view's interactor records the largest delay between ticks until the final
illumination is drawn (IlluminationStatus neither busy nor holding a result: the plugin's GUI
behaviour renders it). The
freeze is the longest of Render() and that delay; the final time runs from the action to
the final frame. One run; a line "volume_still_frame s" (a still frame of the plain Volume
representation, the drawing part of any freeze) and lines "mode action render_s freeze_s final_s" are written to
VOLILLUM_OUTPUT, then the application ends.
"""
import os
import time

from paraview.simple import *

from IlluminatedVolumeTestUtilities import (illumination_status, lighting_pending,  # PYTHONPATH
                                             write_lines_and_exit)

lines = []


try:
    LoadPlugin(os.environ["VOLILLUM_PLUGIN"], remote=False, ns=globals())
    source = OpenDataFile(os.environ["VOLILLUM_VOLUME"])
    source.UpdatePipeline()
    array = source.PointData.keys()[0]
    view = GetActiveViewOrCreate("RenderView")
    rep = Show(source, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, ("POINTS", array))
    rep.RescaleTransferFunctionToDataRange(True)
    view.ResetCamera()
    camera = GetActiveCamera()
    opacity = GetOpacityTransferFunction(array)
    base_opacity = list(opacity.Points)
    state = {"light": None, "turn": 0}

    def turn():
        camera.Azimuth(40)

    def edit_opacity():
        state["turn"] += 1
        factor = 1.2 if state["turn"] % 2 else 1.0
        opacity.Points = [v * factor if i % 4 == 1 else v for i, v in enumerate(base_opacity)]

    def positional():
        state["light"].Type = "Positional"

    def method():
        rep.IlluminationMethod = "Filtered Shadows"

    def scale():
        rep.IlluminationResolutionScale = 1.0

    def reset():
        """Back to the defaults, lit, before each mode."""
        rep.IlluminationMethod = "Multi-Light Propagation"
        rep.IlluminationResolutionScale = 0.5
        if state["light"] is not None:
            RemoveLight(state["light"])
        state["light"] = AddLight(view=view)
        state["light"].Coords = "Scene"
        bounds = source.GetDataInformation().GetBounds()
        state["light"].Position = [bounds[1] * 2, bounds[3] * 2, bounds[5] * 2]
        state["light"].FocalPoint = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]

    actions = [("camera_turn", turn), ("opacity_edit", edit_opacity),
               ("light_positional", positional), ("method", method), ("resolution_scale", scale)]
    plan = [(mode, name, action) for mode in (0, 1) for name, action in actions]
    interactor = view.GetRenderWindow().GetInteractor()
    status = illumination_status()
    run = {"index": -1}

    def start_next():
        run["index"] += 1
        if run["index"] >= len(plan):
            write_lines_and_exit(os.environ["VOLILLUM_OUTPUT"], lines)
        mode, name, action = plan[run["index"]]
        if name == actions[0][0]:
            rep.AsynchronousLighting = 0
            reset()
            Render(view)
            rep.AsynchronousLighting = mode
        action()
        run["start"] = time.perf_counter()
        Render(view)
        run["render"] = time.perf_counter() - run["start"]
        run["last"] = time.perf_counter()
        run["gap"] = 0.0

    def tick(caller, event):
        now = time.perf_counter()
        run["gap"] = max(run["gap"], now - run["last"])
        run["last"] = now
        if lighting_pending(status) and now - run["start"] < 300:
            return
        mode, name, _ = plan[run["index"]]
        lines.append("%s %s %.3f %.3f %.3f" % ("async" if mode else "sync", name, run["render"],
                                               max(run["render"], run["gap"]),
                                               now - run["start"]))
        start_next()
        run["last"] = time.perf_counter()

    # What a still frame of the plain Volume representation costs after a small turn: the
    # part of any freeze that is drawing, not lighting.
    reset()
    rep.SetRepresentationType("Volume")
    Render(view)
    camera.Azimuth(1)
    start = time.perf_counter()
    Render(view)
    lines.append("volume_still_frame %.3f" % (time.perf_counter() - start))
    rep.SetRepresentationType("Illuminated Volume")
    start_next()
    interactor.AddObserver("TimerEvent", tick)
    interactor.CreateRepeatingTimer(20)
except Exception as error:
    lines.append("error %s" % str(error).replace("\n", " "))
    write_lines_and_exit(os.environ["VOLILLUM_OUTPUT"], lines)
