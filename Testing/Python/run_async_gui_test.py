"""Driver of TestAsynchronousLightingGUI.py: starts the real paraview GUI (it needs a display:
run under xvfb-run) and checks what it measured while the engine at 256^3 was re-lit after
a camera turn with Asynchronous Lighting on:
- the GUI turned Asynchronous Lighting on (pvpython leaves it off);
- Render() after the turn took no more than a still frame with nothing to light + 0.25 s;
- the Qt event loop kept running: its timer's largest delay, less the frames the view drew
  within it, stayed within its delay around a frame with nothing to light + 0.25 s (frames
  block the event loop, and so does Qt presenting them, more with Qt 6; the lighting must
  not; two frames can follow each other without a tick between), and no frame drawn
  meanwhile took more than a still frame + 0.25 s;
- the final illumination was drawn without the script rendering again.
Prints every figure, with the synchronous turn's blocking time beside them.
Usage: pvpython run_async_gui_test.py PARAVIEW PLUGIN DATA_DIR OUTPUT_DIR
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from IlluminatedVolumeTestUtilities import Checks, finish, run_gui_script

FREEZE_BOUND = 0.25  # seconds the lighting may add to what a frame costs anyway

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
check(float(results["asynchronous_turn_render_s"]) <= frame + FREEZE_BOUND,
      "Render() after the turn took %s s (bound: a still frame + %.2f = %.3f s)" %
      (results["asynchronous_turn_render_s"], FREEZE_BOUND, frame + FREEZE_BOUND))
check(float(results["largest_delay_outside_frames_s"]) <= baseline + FREEZE_BOUND,
      "the event loop's largest delay outside the frames it drew was %s s (bound: its delay "
      "around a frame with nothing to light + %.2f = %.3f s)" %
      (results["largest_delay_outside_frames_s"], FREEZE_BOUND, baseline + FREEZE_BOUND))
check(float(results["longest_frame_s"]) <= frame + FREEZE_BOUND,
      "the longest frame drawn meanwhile took %s s (bound: a still frame + %.2f = %.3f s)" %
      (results["longest_frame_s"], FREEZE_BOUND, frame + FREEZE_BOUND))
finish(check.failures)
