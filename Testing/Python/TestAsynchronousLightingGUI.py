"""Run inside the ParaView GUI (paraview --script=...): the GUI never waits on the lighting.

The engine CT resampled to 256^3 is shown as "Illuminated Volume" (Resolution Scale 0.5)
under the default light kit. The script records whether the GUI turned Asynchronous
Lighting on, the time of a still frame with nothing to light, and the time a synchronous
Render() blocks after a 40-degree camera turn (the light kit turns with the camera, so
everything is re-lit). With Asynchronous Lighting on, it renders once with nothing to
light and returns to the event loop for a second, then turns the camera again, renders once
and returns to the event loop until no lighting runs or waits to be drawn
(IlluminationStatus), without the script rendering again (pqIlluminationLightingBehavior
renders when the illumination is ready); then the representation must report
IlluminationPending 0. From before that Render() to the end it counts the lightings that a
render computed itself or waited for (IlluminationStatus's IlluminationWaits; also counted
around the synchronous turn, where it must see one) and the ticks
of a 20 ms timer of the view's interactor (a Qt timer) that found the lighting running.
It also records, as figures only, the largest delay between ticks, that delay less the time
the view spent rendering frames within it, and the longest frame, in both stretches.
Results go to OUTPUT_DIR/async_result.txt as "name value" lines; then the application ends
(os._exit).
Environment: VOLILLUM_PLUGIN, VOLILLUM_DATA (the folder of engine.vti), VOLILLUM_OUTPUT.
"""
import os
import time

from paraview.simple import *

# On PYTHONPATH: run_gui_script.
from IlluminatedVolumeTestUtilities import (illumination_status, illumination_waits, info,
                                             lighting_flags, write_lines_and_exit)

out = os.environ["VOLILLUM_OUTPUT"]
results = []


def finish():
    write_lines_and_exit(os.path.join(out, "async_result.txt"), results)


try:
    LoadPlugin(os.environ["VOLILLUM_PLUGIN"], remote=False, ns=globals())
    engine = XMLImageDataReader(FileName=[os.path.join(os.environ["VOLILLUM_DATA"], "engine.vti")])
    volume = ResampleToImage(Input=engine, SamplingDimensions=[256, 256, 256])
    view = GetActiveViewOrCreate("RenderView")
    rep = Show(volume, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, ("POINTS", "ImageFile"))
    rep.IlluminationResolutionScale = 0.5
    results.append("asynchronous_in_gui %d" % rep.AsynchronousLighting)
    view.ResetCamera()
    camera = GetActiveCamera()
    rep.AsynchronousLighting = 0
    Render(view)
    start = time.perf_counter()
    Render(view)
    results.append("still_frame_s %.3f" % (time.perf_counter() - start))
    status = illumination_status()
    waits = illumination_waits(status)
    camera.Azimuth(40)
    start = time.perf_counter()
    Render(view)
    results.append("synchronous_turn_s %.3f" % (time.perf_counter() - start))
    results.append("waits_in_synchronous_turn %d" % (illumination_waits(status) - waits))

    # The GUI around a frame with nothing to light: the script renders, then the event loop
    # runs for a second (Qt presents the frame) while the ticker measures its delays.
    rep.AsynchronousLighting = 1
    interactor = view.GetRenderWindow().GetInteractor()
    state = {"phase": "baseline", "last": None, "gap": 0.0, "blocked": 0.0, "frame": 0.0,
             "drawing": 0.0, "began": None, "busy_ticks": 0}
    Render(view)
    baseline_start = state["last"] = time.perf_counter()

    def frame_began(caller, event):
        state["began"] = time.perf_counter()

    def frame_ended(caller, event):
        if state["began"] is not None:
            seconds = time.perf_counter() - state["began"]
            state["drawing"] += seconds
            state["frame"] = max(state["frame"], seconds)
            state["began"] = None

    def turn():
        """The asynchronous turn: one render, then back to the event loop."""
        global start, waits
        results.append("baseline_timer_delay_s %.3f" % state["gap"])
        results.append("baseline_delay_outside_frames_s %.3f" % state["blocked"])
        waits = illumination_waits(status)
        camera.Azimuth(40)
        start = time.perf_counter()
        Render(view)
        results.append("asynchronous_turn_render_s %.3f" % (time.perf_counter() - start))
        results.append("pending_after_render %d" % info(rep, "IlluminationPending")[0])
        state.update(phase="lighting", gap=0.0, blocked=0.0, frame=0.0, drawing=0.0,
                     last=time.perf_counter())

    def tick(caller, event):
        now = time.perf_counter()
        state["gap"] = max(state["gap"], now - state["last"])
        state["blocked"] = max(state["blocked"], now - state["last"] - state["drawing"])
        state["drawing"] = 0.0
        state["last"] = now
        if state["phase"] == "baseline":
            if now - baseline_start > 1.0:
                turn()
            return
        busy, ready = lighting_flags(status)
        state["busy_ticks"] += busy
        if not (busy or ready):
            results.append("waits_in_renders %d" % (illumination_waits(status) - waits))
            results.append("ticks_while_lighting %d" % state["busy_ticks"])
            results.append("final_frame_s %.3f" % (now - start))
            results.append("largest_timer_delay_s %.3f" % state["gap"])
            results.append("largest_delay_outside_frames_s %.3f" % state["blocked"])
            results.append("longest_frame_s %.3f" % state["frame"])
            results.append("pending_at_the_end %d" % info(rep, "IlluminationPending")[0])
            finish()
        elif now - start > 120:
            results.append("error the lighting was still pending after 120 s")
            finish()

    view.SMProxy.AddObserver("StartEvent", frame_began)  # a render of the view, its update
    view.SMProxy.AddObserver("EndEvent", frame_ended)  # included
    interactor.AddObserver("TimerEvent", tick)
    interactor.CreateRepeatingTimer(20)
except Exception as error:  # report instead of leaving the GUI open
    results.append("error %s" % str(error).replace("\n", " "))
    finish()
