"""Driver of TestAsynchronousLightingGUI.py: starts the real paraview GUI (it needs a display:
run under xvfb-run) and checks what happened while the engine at 256^3 was re-lit after a
camera turn with Asynchronous Lighting on:
- the GUI turned Asynchronous Lighting on (pvpython leaves it off);
- the Render() after the turn returned with the lighting pending, and neither it nor any frame
  drawn up to and including the final one ran the lighting inline or waited for it
  (IlluminationWaits, which sees the synchronous turn's lighting);
- the Qt event loop ran while the lighting was computed (its timer ticked more than once with
  the lighting running);
- the final illumination was drawn without the script rendering again.
No check is timed (a shared 2-core machine slows frames when the lighting takes both cores);
the times are printed as figures: a still frame, the synchronous turn's blocking Render(), the
asynchronous one, the final frame, the event loop's largest delay (and that less the frames
drawn within it, beside the same around a frame with nothing to light), the longest frame.
Usage: pvpython run_async_gui_test.py PARAVIEW PLUGIN DATA_DIR OUTPUT_DIR
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import Checks, finish, run_gui_script

paraview, plugin, data, out = sys.argv[1:5]
here = os.path.dirname(os.path.abspath(__file__))
results = run_gui_script(
    paraview, os.path.join(here, "TestAsynchronousLightingGUI.py"),
    dict(os.environ, VOLILLUM_PLUGIN=plugin, VOLILLUM_DATA=data, VOLILLUM_OUTPUT=out),
    os.path.join(out, "async_result.txt"))
if "error" in results:
    finish(["the GUI script failed: " + results["error"]])
check = Checks()
frame = float(results["still_frame_s"])
baseline = float(results["baseline_delay_outside_frames_s"])
print("still frame %.3f s; after a 40-degree turn: synchronous Render() %.3f s, asynchronous "
      "Render() %.3f s, final frame after %.3f s, largest event-loop delay %.3f s, of it outside "
      "frames %.3f s (around a frame with nothing to light: %.3f s, %.3f s), longest frame %.3f s" %
      (frame, float(results["synchronous_turn_s"]), float(results["asynchronous_turn_render_s"]),
       float(results["final_frame_s"]), float(results["largest_timer_delay_s"]),
       float(results["largest_delay_outside_frames_s"]), float(results["baseline_timer_delay_s"]),
       baseline, float(results["longest_frame_s"])))
check(results["asynchronous_in_gui"] == "1", "the GUI turned Asynchronous Lighting on")
check(results["pending_after_render"] == "1", "the lighting was pending after Render()")
check(results["pending_at_the_end"] == "0",
      "the GUI drew the final illumination (IlluminationPending 0) without the script rendering")
check(int(results["waits_in_synchronous_turn"]) >= 1,
      "the synchronous turn's Render() computed the lighting (%s lightings computed or waited "
      "for)" % results["waits_in_synchronous_turn"])
check(int(results["waits_in_renders"]) == 0,
      "no render computed the lighting or waited for it (%s lightings computed or waited for)"
      % results["waits_in_renders"])
check(int(results["ticks_while_lighting"]) >= 2,
      "the event loop ran while the lighting was computed (%s ticks of its 20 ms timer found it "
      "running)" % results["ticks_while_lighting"])
finish(check.failures)
