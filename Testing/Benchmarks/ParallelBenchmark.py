"""Benchmark of the image filters under MPI (strong scaling), one run.

The engine resampled to 256^3 (../shared/data/volumes/engine.vti; --smoke: the CT phantom
at 64^3) is lit at scale 1 by 4 oblique directional lights with pvbatch on 1 process and
with `MPIEXEC -np 2 pvbatch`, each process single-threaded (Sequential SMP backend) so the
comparison is fair on a 2-core machine. Printed: full update and one-light edit times on
1 and 2 processes and their ratios (speed-up) of Multi-Light Illumination Volume (on 2
processes over bands of rows, DistributedSweeps, and with the input assembled: a second run,
so that each peak memory is its own; over bands also the largest band of the classification
process 0 held and the bytes it sent), the same for a full update of Filtered
Volumetric Shadows (with distributed tables: each process lights its own piece from its
block grown by a shadow's reach; and with the input assembled), its peak memory per process
on 1, 2 and 4 processes (separate runs; the grown block of process 0 and the bytes of
classification it sent), the same with the lights made point lights (spherical tables),
and of Ray-Marched
Illumination (scale 1/4, one light; each process classifies and marches through its block
of the input only: the points process 0 classified and the bytes of the products each
process sends are printed), the bytes each process
receives when the data changes (the gathered pieces; a light edit gathers nothing), the
bytes of the propagation's sums each process sends per update, the propagation's peak
memory per process (that of process 0, which runs the script), and
the propagation's peak memory per process also on 4 processes (oversubscribed: memory only),
the propagation with the lights made point lights (times on 1 and 2 processes, over wedges
and assembled; peak memory per process on 1, 2 and 4; the largest wedge process 0 held),
the Illuminated Volume representation's still render after a camera move (the light kit,
scale 1/2; propagation and filtered shadows) on 1 and 2 processes with process 0's peak
memory and whether the pieces were lit where they are, and the efficiency a sweep over bands
reaches at 8, 64, 204 and 512 processes for 1024^3 by the
model of Documentation/parallel.md with this run's compute cost per voxel and light.
Writes the figures as JSON with --json FILE.
Usage: pvpython ParallelBenchmark.py PLUGIN DATA_DIR OUT_DIR MPIEXEC "MPI_FLAGS"
       [--smoke] [--json FILE]
"""
import json
import math
import os
import shutil
import subprocess
import sys
import time

LIGHTS = 4


def lights(bounds, count, turn=0.0, kind=0):
    """`count` lights of `kind` (0 directional, 1 point) around and above the volume."""
    centre = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]
    rows = []
    for i in range(count):
        a = 0.7 + 1.3 * i + turn
        position = [centre[0] + 300 * math.cos(a), centre[1] + 300 * math.sin(a),
                    centre[2] + 200 + 40 * i]
        rows += [kind] + position + centre + [1, 0.9, 0.8, 1.0, 90, 1, 1]
    return rows


def worker(plugin, volume, modes):
    """Runs the modes given (comma-separated) in turn, each as `measure` describes."""
    from paraview.simple import LoadPlugin
    LoadPlugin(plugin, remote=False, ns=globals())
    for mode in modes.split(","):
        measure(volume, mode)


def measure(volume, mode):
    """Times a full update and a one-light edit of the propagation and (mode "all") a full
    update of filtered shadows and of the ray marcher; prints one JSON line. Mode "bands":
    the propagation only; "assembled": the propagation only, with DistributedSweeps off
    (each process assembles the input); "point" and "point_assembled": the same with the
    lights made point lights; "filtered" and "filtered_assembled": filtered shadows only,
    with DistributedTables on and off."""
    assembled = mode in ("assembled", "point_assembled")
    kind = 1 if mode.startswith("point") else 0
    from paraview.simple import (XMLImageDataReader, GetColorTransferFunction,
                                 GetOpacityTransferFunction)
    reader = XMLImageDataReader(FileName=[volume])
    reader.UpdatePipeline()
    array = reader.PointData.keys()[0]
    bounds = reader.GetDataInformation().GetBounds()
    pwf = GetOpacityTransferFunction(array)
    pwf.Points = [0, 0, 0.5, 0, 80, 0, 0.5, 0, 255, 0.5, 0.5, 0]

    def filter_with_lights(name):
        """The filter `name` at scale 1 with the benchmark's lights."""
        f = globals()[name](Input=reader, ColorTransferFunction=GetColorTransferFunction(array),
                            OpacityFunction=pwf, ResolutionScale=1.0)
        f.Scalars = ["POINTS", array]
        f.Lights = lights(bounds, LIGHTS, kind=kind)
        return f

    def seconds(f):
        start = time.perf_counter()
        f.UpdatePipeline()
        return time.perf_counter() - start

    import resource
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    if mode.startswith("render"):
        # The Illuminated Volume representation as ParaView renders it (the light kit,
        # resolution scale 1/2, 400 x 400): a still render after a camera move (the light kit
        # follows the camera: the illumination is updated), propagation ("render") or
        # filtered shadows ("render_shadows").
        from paraview.simple import ColorBy, CreateView, GetActiveCamera, Render, Show
        view = CreateView("RenderView")
        view.ViewSize = [400, 400]
        view.OrientationAxesVisibility = 0
        rep = Show(reader, view)
        rep.SetRepresentationType("Illuminated Volume")
        ColorBy(rep, ("POINTS", array))
        rep.IlluminationMethod = 1 if mode == "render_shadows" else 0
        rep.IlluminationResolutionScale = 0.5
        view.ResetCamera()
        Render(view)
        GetActiveCamera().Azimuth(60)
        start = time.perf_counter()
        Render(view)
        rendered = time.perf_counter() - start
        rep.SMProxy.UpdatePropertyInformation()
        print("RESULT " + json.dumps({
            "render_s": rendered,
            "peak_bytes": 1024 * (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before),
            "distributed": rep.SMProxy.GetProperty("IlluminationDistributed").GetElement(0),
            "points": reader.GetDataInformation().GetNumberOfPoints()}))
        return
    if mode.startswith("filtered"):
        # Filtered shadows alone, for their peak memory (with distributed tables, and with the
        # input assembled on every process); "filtered_point": the lights made point lights
        # (spherical tables).
        f = filter_with_lights("FilteredVolumetricShadows")
        f.DistributedTables = 0 if mode.endswith("_assembled") else 1
        if mode.startswith("filtered_point"):
            f.Lights = lights(bounds, LIGHTS, kind=1)
        filtered = seconds(f)
        peak = 1024 * (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)
        fields = f.GetClientSideObject().GetOutputDataObject(0).GetFieldData()
        grown, sent = fields.GetArray("GrownPoints"), fields.GetArray("SentBytes")
        print("RESULT " + json.dumps({"filtered_s": filtered, "peak_bytes": peak,
                                      "grown_points": int(grown.GetValue(0)) if grown else 0,
                                      "sent_bytes": int(sent.GetValue(0)) if sent else 0,
                                      "points": reader.GetDataInformation().GetNumberOfPoints()}))
        return
    f = filter_with_lights("MultiLightIlluminationVolume")
    f.DistributedSweeps = 0 if assembled else 1
    full = seconds(f)

    def field(name):
        array = f.GetClientSideObject().GetOutputDataObject(0).GetFieldData().GetArray(name)
        return int(array.GetValue(0)) if array else 0
    band, full_sent = field("BandPoints"), field("SentBytes")
    edited = lights(bounds, LIGHTS, kind=kind)
    edited[1:4] = lights(bounds, 1, turn=0.4)[1:4]
    f.Lights = edited
    edit = seconds(f)
    # The process's peak resident memory during the propagation above what it held before.
    peak = 1024 * (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)
    info = reader.GetDataInformation()
    if mode != "all":
        print("RESULT " + json.dumps({"full_s": full, "edit_s": edit, "peak_bytes": peak,
                                      "band_points": band,
                                      "points": info.GetNumberOfPoints()}))
        return
    edit_sent = field("SentBytes")
    # Filtered shadows light points independently: each process lights its own piece.
    filtered = seconds(filter_with_lights("FilteredVolumetricShadows"))
    assembling = filter_with_lights("FilteredVolumetricShadows")
    assembling.DistributedTables = 0
    filtered_assembled = seconds(assembling)
    # Ray-marched illumination marches through each process's block (no input gathered), at
    # scale 1/4 with one light (the brute-force reference costs a march per point and light).
    marched = filter_with_lights("RayMarchedIllumination")
    marched.ResolutionScale = 0.25
    marched.Lights = lights(bounds, 1)
    marched_s = seconds(marched)
    extent = marched.GetDataInformation().GetExtent()
    classified = marched.GetClientSideObject().GetOutputDataObject(0).GetFieldData().GetArray(
        "ClassifiedPoints")
    from vtkmodules.vtkCommonCore import vtkDataArray
    lit = info.GetPointDataInformation().GetArrayInformation(array)
    value = vtkDataArray.CreateDataArray(lit.GetDataType())
    print("RESULT " + json.dumps({"full_s": full, "edit_s": edit, "filtered_s": filtered,
                                  "filtered_assembled_s": filtered_assembled,
                                  "marched_s": marched_s,
                                  "marched_classified": int(classified.GetValue(0)),
                                  "marched_points": math.prod(
                                      extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)),
                                  "peak_bytes": peak,
                                  "band_points": band, "full_sent_bytes": full_sent,
                                  "edit_sent_bytes": edit_sent,
                                  "points": info.GetNumberOfPoints(),
                                  "bytes": info.GetNumberOfPoints() *
                                  lit.GetNumberOfComponents() * value.GetDataTypeSize()}))


def run(command, plugin, volume, modes):
    """The worker's results for each mode (a list), all run by one process."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
    from IlluminatedVolumeTestUtilities import environment_for_mpiexec
    environment = environment_for_mpiexec()
    environment["VTK_SMP_BACKEND_IN_USE"] = "Sequential"
    result = subprocess.run(command + [os.path.abspath(__file__), "--worker", plugin, volume,
                                       ",".join(modes)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=environment, timeout=3000)
    # pvbatch runs the script on the first process (the others serve it): its times and its
    # peak memory.
    results = [json.loads(line[len("RESULT "):]) for line in result.stdout.splitlines()
               if line.startswith("RESULT ")]
    if len(results) != len(modes):
        raise RuntimeError("the run failed:\n" + result.stdout[-3000:])
    return results


def prepare(data_dir, out, smoke):
    from paraview.simple import ResampleToImage, SaveData, XMLImageDataReader
    engine = os.path.join(data_dir, "volumes", "engine.vti")
    path = os.path.join(out, "parallel-benchmark-volume.vti")
    if smoke or not os.path.exists(engine):
        phantom = globals()["IlluminationPhantom"](Scene="CT Phantom", Dimensions=[64, 64, 64])
        SaveData(path, proxy=phantom)
        return path, "CT phantom 64^3 (smoke)"
    resampled = ResampleToImage(Input=XMLImageDataReader(FileName=[engine]),
                                SamplingDimensions=[256, 256, 256])
    SaveData(path, proxy=resampled)
    return path, "engine resampled to 256^3"


def model(compute_per_voxel_light, halo=5):
    """Efficiency of one sweep of a 1024^3 volume over bands of rows on P processes
    (Documentation/parallel.md): per slice each of the S = min(P, n) processes that sweep (a
    band holds at least a row; the others wait) computes its n^2 / S points and exchanges
    `halo` lattice rows (4 bytes a ray, one light) either side with the bands that hold them:
    up to D = ceil(halo / (n / S)) bands away, in two steps of a message each way per
    distance. The efficiency is the serial slice time over P times the parallel one."""
    rows = []
    n, latency, bandwidth = 1024, 2e-6, 10e9
    for p in (8, 64, n // halo, 512, n):
        sweeping = min(p, n)
        distances = -(-halo // (n // sweeping))
        compute = n * n / sweeping * compute_per_voxel_light
        exchange = 4 * distances * latency + 4 * halo * (n + 1) * 4 / bandwidth
        rows.append({"processes": p, "sweeping": sweeping, "distances": distances,
                     "efficiency": n * n * compute_per_voxel_light / (p * (compute + exchange)),
                     "slice_s": compute, "exchange_s": exchange})
    return rows


def model_tiles(compute_per_voxel_light, halo=5):
    """The same sweep over tiles (the plan in Documentation/parallel.md): the slices' rows and
    columns shared out in a grid of P = p_rows x p_columns tiles, as square as P allows, each
    process sweeping all slices of its tile. Per slice a tile computes its n^2 / P points and
    gets `halo` rows of the lattice either side from the tiles beside it, first across the rows
    and then, with those rows, across the columns (corners included): D = ceil(halo / tile
    width) tiles away per axis, 4 D messages a slice per axis as for the bands."""
    rows = []
    n, latency, bandwidth = 1024, 2e-6, 10e9
    for p in (8, 64, 512, 1024, 4096):
        p_rows = 1 << (p.bit_length() - 1) // 2  # the larger power of two below sqrt(p)
        p_columns = p // p_rows
        tile = (n // p_rows, n // p_columns)
        distances = [-(-halo // width) for width in tile]
        compute = n * n / p * compute_per_voxel_light
        rays = 2 * halo * (tile[1] + 2 * halo) + 2 * halo * (tile[0] + 2 * halo)
        exchange = 4 * sum(distances) * latency + rays * 4 / bandwidth
        rows.append({"processes": p, "tiles": [p_rows, p_columns], "distances": distances,
                     "efficiency": n * n * compute_per_voxel_light / (p * (compute + exchange)),
                     "slice_s": compute, "exchange_s": exchange})
    return rows


def main():
    from paraview.simple import LoadPlugin
    plugin, data_dir, out, mpiexec, flags = sys.argv[1:6]
    plugin = os.path.abspath(plugin)  # ParaView 5.13 loads a plugin by its absolute path only
    smoke = "--smoke" in sys.argv
    json_path = sys.argv[sys.argv.index("--json") + 1] if "--json" in sys.argv else None
    LoadPlugin(plugin, remote=False, ns=globals())
    os.makedirs(out, exist_ok=True)
    volume, name = prepare(data_dir, out, smoke)
    pvbatch = shutil.which("pvbatch")
    # The worker's modes on each number of processes. Memory on 4 processes (oversubscribed on
    # 2 cores: their times mean nothing). The propagation with the lights made point lights
    # ("point": each swept over wedges of its rays, one a process; "point_assembled"), filtered
    # shadows alone for their peak memory (directional and point lights, with distributed
    # tables and assembled), and the representation as ParaView renders it.
    plan = {1: ["all", "point", "filtered", "filtered_point", "render", "render_shadows"],
            2: ["all", "assembled", "point", "point_assembled", "filtered", "filtered_assembled",
                "filtered_point", "filtered_point_assembled", "render", "render_shadows"],
            4: ["bands", "assembled", "filtered", "filtered_assembled", "filtered_point",
                "filtered_point_assembled", "point", "point_assembled"]}
    measured = {}
    for n, modes in plan.items():
        command = [pvbatch] if n == 1 else [mpiexec] + flags.split() + ["-np", str(n), pvbatch]
        # Each mode in a process of its own, so that each peak memory is its own; the smoke
        # run (tiny sizes: only whether it runs) starts one process per count.
        runs = [modes] if smoke else [[mode] for mode in modes]
        for group in runs:
            measured.update(((n, mode), r) for mode, r in zip(group, run(command, plugin, volume,
                                                                          group)))
    one, two, two_assembled = measured[1, "all"], measured[2, "all"], measured[2, "assembled"]
    four = {mode: measured[4, mode] for mode in plan[4]}
    point_lights = {"1": measured[1, "point"], "2": measured[2, "point"],
                    "2_assembled": measured[2, "point_assembled"], "4": measured[4, "point"],
                    "4_assembled": measured[4, "point_assembled"]}
    shadows = {"1": measured[1, "filtered"], "1_point": measured[1, "filtered_point"]}
    for mode in ("filtered", "filtered_assembled", "filtered_point", "filtered_point_assembled"):
        shadows["2" + mode[len("filtered"):]] = measured[2, mode]
    rendering = {mode: {"1": measured[1, mode], "2": measured[2, mode]}
                 for mode in ("render", "render_shadows")}
    # Each process receives the other pieces of the lit array: (N - 1) / N of it.
    received = two["bytes"] / 2
    # Assembled: each process sends the fixed-point units (3 x 4 bytes a point) of the other
    # pieces, (N - 1) / N of the grid (scale 1: one point per data point).
    summed = 12 * one["points"] / 2

    def shadow_peaks(lights_kind):
        """Filtered shadows' peak bytes a point per process (lights_kind "" or "_point")."""
        return {"1": shadows["1" + lights_kind]["peak_bytes"] / one["points"],
                "2": shadows["2" + lights_kind]["peak_bytes"] / two["points"],
                "2 assembled": shadows["2" + lights_kind + "_assembled"]["peak_bytes"] /
                two["points"],
                "4": four["filtered" + lights_kind]["peak_bytes"] / two["points"],
                "4 assembled": four["filtered" + lights_kind + "_assembled"]["peak_bytes"] /
                two["points"]}

    # Directional lights travel in two groups each: light sweeps of one full update.
    per_voxel_light = one["full_s"] / (one["points"] * 2 * LIGHTS)
    results = {"volume": name, "lights": LIGHTS,
               "full_update_s": {"1": one["full_s"], "2": two["full_s"]},
               "one_light_edit_s": {"1": one["edit_s"], "2": two["edit_s"]},
               "full_update_assembled_s": {"2": two_assembled["full_s"]},
               "one_light_edit_assembled_s": {"2": two_assembled["edit_s"]},
               "band_points_of_process_0": {"2": two["band_points"]},
               "speedup_full": one["full_s"] / two["full_s"],
               "speedup_edit": one["edit_s"] / two["edit_s"],
               "filtered_shadows_s": {"1": one["filtered_s"], "2": two["filtered_s"]},
               "speedup_filtered_shadows": one["filtered_s"] / two["filtered_s"],
               "filtered_shadows_assembled_s": {"1": one["filtered_assembled_s"],
                                                "2": two["filtered_assembled_s"]},
               "filtered_shadows_peak_bytes_per_point_per_process": shadow_peaks(""),
               "filtered_shadows_point_lights_s": {
                   "1": shadows["1_point"]["filtered_s"], "2": shadows["2_point"]["filtered_s"],
                   "2 assembled": shadows["2_point_assembled"]["filtered_s"]},
               "filtered_shadows_point_lights_peak_bytes_per_point_per_process":
                   shadow_peaks("_point"),
               "filtered_shadows_point_lights_grown_points_of_process_0": {
                   "2": shadows["2_point"]["grown_points"]},
               "filtered_shadows_grown_points_of_process_0": {
                   "2": shadows["2"]["grown_points"], "4": four["filtered"]["grown_points"]},
               "filtered_shadows_bytes_sent_by_process_0": {
                   "2": shadows["2"]["sent_bytes"], "4": four["filtered"]["sent_bytes"]},
               "ray_marched_s": {"1": one["marched_s"], "2": two["marched_s"]},
               "speedup_ray_marched": one["marched_s"] / two["marched_s"],
               "ray_marched_points_classified_by_process_0": {
                   "1": one["marched_classified"], "2": two["marched_classified"]},
               # Every process sends 3 doubles a point of the illumination grid and light.
               "ray_marched_product_bytes_sent_per_process_per_update":
                   24 * one["marched_points"],
               "bytes_received_per_process_on_data_change": received,
               "propagation_sum_bytes_sent_per_process_per_update": {
                   "assembled (computed)": summed,
                   "bands, full update (measured, process 0)": two["full_sent_bytes"],
                   "bands, one-light edit (measured, process 0)": two["edit_sent_bytes"]},
               "point_lights_propagation_s": {
                   n: {"full": r["full_s"], "edit": r["edit_s"]} for n, r in point_lights.items()},
               "point_lights_propagation_peak_bytes_per_point_per_process": {
                   n: r["peak_bytes"] / r["points"] for n, r in point_lights.items()},
               "point_lights_band_points_of_process_0": {
                   n: point_lights[n]["band_points"] for n in ("2", "4")},
               "propagation_peak_bytes_per_point_per_process": {
                   "1": one["peak_bytes"] / one["points"], "2": two["peak_bytes"] / two["points"],
                   "2 assembled": two_assembled["peak_bytes"] / two["points"],
                   "4": four["bands"]["peak_bytes"] / two["points"],
                   "4 assembled": four["assembled"]["peak_bytes"] / two["points"]},
               "representation_render_after_camera_move_s": {
                   mode: {n: r["render_s"] for n, r in runs.items()}
                   for mode, runs in rendering.items()},
               "representation_peak_bytes_per_point_of_process_0": {
                   mode: {n: r["peak_bytes"] / r["points"] for n, r in runs.items()}
                   for mode, runs in rendering.items()},
               "representation_lit_where_the_pieces_are": {
                   mode: runs["2"]["distributed"] for mode, runs in rendering.items()},
               "compute_s_per_voxel_light_sweep": per_voxel_light,
               "model_1024_cubed": model(per_voxel_light),
               "model_1024_cubed_tiles": model_tiles(per_voxel_light)}
    print("Multi-Light Illumination Volume (propagation) and Filtered Volumetric Shadows, %s, "
          "%d lights, one thread per process" % (name, LIGHTS))
    print("%-22s %10s %10s %8s" % ("", "1 process", "2", "speed-up"))
    print("%-22s %10.2f %10.2f %8.2f" % ("full update (s)", one["full_s"], two["full_s"],
                                         results["speedup_full"]))
    print("%-22s %10.2f %10.2f %8.2f" % ("one-light edit (s)", one["edit_s"], two["edit_s"],
                                         results["speedup_edit"]))
    print("%-22s %10s %10.2f %8.2f" % ("  assembled: full (s)", "", two_assembled["full_s"],
                                       one["full_s"] / two_assembled["full_s"]))
    print("%-22s %10s %10.2f %8.2f" % ("  assembled: edit (s)", "", two_assembled["edit_s"],
                                       one["edit_s"] / two_assembled["edit_s"]))
    print("%-22s %10.2f %10.2f %8.2f" % ("filtered shadows (s)", one["filtered_s"],
                                         two["filtered_s"], results["speedup_filtered_shadows"]))
    print("%-22s %10.2f %10.2f %8.2f" % ("  assembled input (s)", one["filtered_assembled_s"],
                                         two["filtered_assembled_s"],
                                         one["filtered_assembled_s"] /
                                         two["filtered_assembled_s"]))
    print("filtered shadows' peak memory per process above the input, bytes a point: %.1f on "
          "1 process, %.1f on 2, %.1f on 2 assembled, %.1f on 4, %.1f on 4 assembled; grown "
          "block of process 0: %d points on 2 processes, %d on 4, of %d; classification it sent: "
          "%.1f MB on 2, %.1f MB on 4"
          % tuple(list(results["filtered_shadows_peak_bytes_per_point_per_process"].values()) +
                  [shadows["2"]["grown_points"], four["filtered"]["grown_points"],
                   one["points"], shadows["2"]["sent_bytes"] / 1e6,
                   four["filtered"]["sent_bytes"] / 1e6]))
    point = results["filtered_shadows_point_lights_s"]
    point_peak = results["filtered_shadows_point_lights_peak_bytes_per_point_per_process"]
    print("filtered shadows, the lights made point lights: %.2f s on 1 process, %.2f s on 2 "
          "(%.2fx), %.2f s on 2 assembled; peak memory per process above the input, bytes a "
          "point: %.1f on 1, %.1f on 2, %.1f on 2 assembled, %.1f on 4, %.1f on 4 assembled; "
          "grown block of process 0: %d points on 2 processes"
          % (point["1"], point["2"], point["1"] / point["2"], point["2 assembled"],
             point_peak["1"], point_peak["2"], point_peak["2 assembled"], point_peak["4"],
             point_peak["4 assembled"], shadows["2_point"]["grown_points"]))
    print("%-22s %10.2f %10.2f %8.2f" % ("ray marched (s)", one["marched_s"],
                                         two["marched_s"], results["speedup_ray_marched"]))
    print("ray marched: input points process 0 classified: %d on 1 process, %d on 2; "
          "products each process sends per update: %.1f MB"
          % (one["marched_classified"], two["marched_classified"],
             results["ray_marched_product_bytes_sent_per_process_per_update"] / 1e6))
    print("bytes each process receives when the data changes: %.1f MB (light edits: none)"
          % (received / 1e6))
    print("bytes of the propagation process 0 sends over bands: %.1f MB a full update, %.1f MB "
          "an edit (measured); assembled: %.1f MB an update (sums, computed)"
          % (two["full_sent_bytes"] / 1e6, two["edit_sent_bytes"] / 1e6, summed / 1e6))
    print("propagation over bands: largest band of process 0 %d of %d points"
          % (two["band_points"], one["points"]))
    print("propagation's peak memory per process above the input, bytes a point: "
          "%.1f on 1 process, %.1f on 2 over bands, %.1f on 2 assembled, %.1f on 4 over bands, "
          "%.1f on 4 assembled"
          % (one["peak_bytes"] / one["points"], two["peak_bytes"] / two["points"],
             two_assembled["peak_bytes"] / two["points"],
             four["bands"]["peak_bytes"] / two["points"],
             four["assembled"]["peak_bytes"] / two["points"]))
    print("propagation, the lights made point lights: full update %.2f s on 1 process, %.2f s "
          "on 2 over wedges (%.2fx), %.2f s on 2 assembled; one-light edit %.2f, %.2f and %.2f s; "
          "peak memory per process above the input, bytes a point: %.1f on 1, %.1f on 2 over "
          "wedges, %.1f on 2 assembled, %.1f on 4 over wedges, %.1f on 4 assembled; largest "
          "wedge of process 0: %d points on 2 processes, %d on 4"
          % (point_lights["1"]["full_s"], point_lights["2"]["full_s"], point_lights["1"]["full_s"] / point_lights["2"]["full_s"],
             point_lights["2_assembled"]["full_s"], point_lights["1"]["edit_s"], point_lights["2"]["edit_s"],
             point_lights["2_assembled"]["edit_s"],
             *results["point_lights_propagation_peak_bytes_per_point_per_process"].values(),
             point_lights["2"]["band_points"], point_lights["4"]["band_points"]))
    for mode, label in (("render", "propagation"), ("render_shadows", "filtered shadows")):
        runs = rendering[mode]
        print("Illuminated Volume representation, %s: a still render after a camera move "
              "%.2f s on 1 process, %.2f s on 2 (%.2fx); peak memory of process 0 above the "
              "input %.1f and %.1f bytes a point; lit where the pieces are on 2: %s"
              % (label, runs["1"]["render_s"], runs["2"]["render_s"],
                 runs["1"]["render_s"] / runs["2"]["render_s"],
                 runs["1"]["peak_bytes"] / runs["1"]["points"],
                 runs["2"]["peak_bytes"] / runs["2"]["points"],
                 "yes" if runs["2"]["distributed"] else "no"))
    print("model of a sweep over bands, 1024^3 (%.0f ns per voxel and light sweep, halo of 5 "
          "rows):" % (per_voxel_light * 1e9))
    for row in results["model_1024_cubed"]:
        print("  %4d processes (%d sweeping, exchanges up to %d bands away): efficiency %.1f %% "
              "(slice %.3f ms, exchange %.0f us)"
              % (row["processes"], row["sweeping"], row["distances"], 100 * row["efficiency"],
                 1e3 * row["slice_s"], 1e6 * row["exchange_s"]))
    if json_path:
        with open(json_path, "w") as f:
            json.dump(results, f, indent=2)


if __name__ == "__main__":
    if sys.argv[1] == "--worker":
        worker(sys.argv[2], sys.argv[3], sys.argv[4])
    else:
        main()
    sys.stdout.flush()
    os._exit(0)
