"""pvpython worker of run_fuzz.py: reads fuzz inputs and runs the plugin's filters on them.

    pvpython fuzz_filters.py PLUGIN JOBS.json

JOBS.json is a list of jobs written by run_fuzz.py:

    {"case": "grid__nan_vertex.vtu", "file": "/abs/path/grid__nan_vertex.vtu",
     "filters": ["UnstructuredGridIllumination"],
     "properties": {filter: {property: value}},   # optional, set before the first update
     "then": {filter: {property: value}},         # optional, set after it, then update again
     "prepare": {"scalar_tuples": N, "spacing": [...], "origin": [...]}}   # optional

For each job the worker loads the file with the reader matching its extension (as the
CLI does; the reader a ParaView user would pick for that file); with "prepare" a
Programmable Filter then changes the data in memory, as a user's script could, in ways
no file can carry because the readers check them: the active point scalars get N more
tuples than the data set has points (N < 0: fewer), or the image gets a NaN or
infinite spacing or origin.
It then runs every listed filter (paraview.simple names) on that output, one at a time,
with small settings so that each finishes quickly. Every step is framed by two marker lines on
stdout, flushed before the step starts, so that the runner can tell which step crashed,
hung or printed a sanitizer report even though VTK writes its messages to stderr
(the runner merges both streams):

    @@FUZZ BEGIN <case> <step>
    ... whatever VTK, the plugin or Python print ...
    @@FUZZ END <case> <step> {"points": N, "cells": M, "type": "...", "exception": null}

(fields separated by tabs). <step> is "reader", a filter name, or "close" (deleting the
job's proxies). The last line is "@@FUZZ DONE". The worker itself never judges an
outcome: run_fuzz.py classifies each step from its exit status and messages.
"""
import json
import math
import os
import sys
import traceback

MARK = "@@FUZZ"

# Readers by file ending, and the property that takes the file name.
READERS = {
    ".vti": ("XMLImageDataReader", "FileName"),
    ".vtu": ("XMLUnstructuredGridReader", "FileName"),
    ".vtp": ("XMLPolyDataReader", "FileName"),
    ".mha": ("MetaFileSeriesReader", "FileNames"),
    ".mhd": ("MetaFileSeriesReader", "FileNames"),
    ".nrrd": ("NrrdReader", "FileName"),
    ".nhdr": ("NrrdReader", "FileName"),
    ".vtk": ("LegacyVTKReader", "FileNames"),
}

# The server-manager XML names of the filters, for cases that use them.
ALIASES = {"TetrahedralizeSurface": "TetrahedralizeSurfaceTetGen",
           "AdaptiveTetrahedralMesh": "AdaptiveTetrahedralMeshCGAL"}

# Programmable Filter script for "prepare" (run in pvpython's __main__; the JSON text of
# the prepare object is substituted for PREPARE). Non-finite numbers come as the strings
# NaN / Infinity / -Infinity, which float() reads.
PREPARE_SCRIPT = """
import json as _json
prep = _json.loads(PREPARE)
data = self.GetInputDataObject(0, 0)
out = self.GetOutputDataObject(0)
out.ShallowCopy(data)
if "spacing" in prep:
    out.SetSpacing(*[float(v) for v in prep["spacing"]])
    print("spacing set to %s" % (out.GetSpacing(),))
if "origin" in prep:
    out.SetOrigin(*[float(v) for v in prep["origin"]])
    print("origin set to %s" % (out.GetOrigin(),))
if "scalar_tuples" in prep:
    old = data.GetPointData().GetScalars()
    if old is None and data.GetPointData().GetNumberOfArrays() > 0:
        old = data.GetPointData().GetArray(0)
    if old is not None:
        new = old.NewInstance()
        new.DeepCopy(old)
        count = old.GetNumberOfTuples() + int(prep["scalar_tuples"])
        if count < 0:
            count = 0
        new.Resize(count)
        new.SetNumberOfTuples(count)
        for i in range(old.GetNumberOfTuples(), count):
            for c in range(new.GetNumberOfComponents()):
                new.SetComponent(i, c, 0.5)
        out.GetPointData().RemoveArray(old.GetName())
        out.GetPointData().AddArray(new)
        out.GetPointData().SetActiveScalars(new.GetName())
        print("scalars resized to %d tuples for %d points" % (count, data.GetNumberOfPoints()))
"""

IMAGE_LIGHT_FILTERS = ("RayMarchedIllumination", "MultiLightIlluminationVolume",
                       "FilteredVolumetricShadows")


def emit(*fields):
    sys.stderr.flush()
    sys.stdout.write(MARK + " " + "\t".join(str(f) for f in fields) + "\n")
    sys.stdout.flush()


def finite(value):
    """Strings NaN / Infinity / -Infinity (strict JSON in cases.json) back to floats."""
    if isinstance(value, list):
        return [finite(v) for v in value]
    if value in ("NaN", "Infinity", "-Infinity"):
        return float(value.replace("Infinity", "inf"))
    return value


def describe(proxy):
    """Points, cells and type of a proxy's output (from the data information, so the
    data is not copied)."""
    info = proxy.GetDataInformation()
    return {"points": int(info.GetNumberOfPoints()), "cells": int(info.GetNumberOfCells()),
            "type": info.GetDataSetTypeAsString()}


def outside_point_light(bounds):
    """A white point light beside the data (14 numbers), or [] when the bounds are not
    finite or overflow."""
    if len(bounds) != 6 or not all(math.isfinite(b) for b in bounds) or bounds[0] > bounds[1]:
        return []
    centre = [(bounds[2 * a] + bounds[2 * a + 1]) / 2.0 for a in range(3)]
    size = max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))
    position = [centre[0] - 1.5 * size, centre[1] + 0.5 * size, centre[2] + 1.5 * size]
    row = [1] + position + centre + [1.0, 0.9, 0.8, 1.0, 180.0, 1.0, 1.0]
    return row if all(math.isfinite(v) for v in row) else []


def configure(name, proxy, bounds):
    """Small, fast settings per filter."""
    if name in IMAGE_LIGHT_FILTERS:
        # The default directional light down z plus a point light beside the data.
        proxy.Lights = [0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 30, 1, 1] + outside_point_light(bounds)
    elif name == "UnstructuredGridIllumination":
        proxy.Level0Resolution = [16, 16, 16]
        proxy.Lights = [0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 30, 1, 1] + outside_point_light(bounds)


def apply(proxy, settings):
    for key, value in (settings or {}).items():
        setattr(proxy, key, finite(value))


# This module's namespace once the plugin is loaded. A Programmable Filter runs its script
# in __main__ (this module) and imports numpy_interface.algorithms there, whose max, all
# and others would then replace the builtins; each step ends by restoring the namespace.
PRISTINE = {}


def restore_namespace():
    space = globals()
    for key in [k for k in space if k not in PRISTINE]:
        del space[key]
    space.update(PRISTINE)


def run_step(case, step, action):
    """Runs action() between the markers; action returns the info dict."""
    emit("BEGIN", case, step)
    info = {"exception": None}
    try:
        info.update(action() or {})
    except Exception as error:  # a Python-level failure is a clean error, not a crash
        traceback.print_exc()
        info["exception"] = "%s: %s" % (type(error).__name__, error)
    finally:
        restore_namespace()
    emit("END", case, step, json.dumps(info))


def run_job(job, ns):
    simple = ns["__simple"]
    case, path = job["case"], job["file"]
    state = {"reader": None, "source": None, "bounds": []}

    def load():
        ext = os.path.splitext(path)[1].lower()
        if ext in READERS:
            name, prop = READERS[ext]
            reader = ns[name](**{prop: [path] if prop == "FileNames" else path})
        else:
            reader = simple.OpenDataFile(path)
        state["reader"] = reader
        reader.UpdatePipeline()
        info = describe(reader)
        state["bounds"] = list(reader.GetDataInformation().GetBounds())
        info["arrays"] = list(reader.PointData.keys())
        prepare = job.get("prepare")
        if prepare:
            script = PREPARE_SCRIPT.replace("PREPARE", repr(json.dumps(prepare)), 1)
            changed = simple.ProgrammableFilter(Input=reader, CopyArrays=0, Script=script)
            state["source"] = changed
            changed.UpdatePipeline()
            if "scalar_tuples" in prepare:
                arrays = changed.PointData
                wanted = info["points"] + int(prepare["scalar_tuples"])
                got = [arrays[name].GetNumberOfTuples() for name in arrays.keys()]
                if wanted not in got:
                    raise RuntimeError("prepare failed: %d scalar tuples wanted, arrays have %s"
                                       % (wanted, got))
        return info

    run_step(case, "reader", load)
    for name in job["filters"]:
        def run_filter(name=name):
            if state["reader"] is None:
                raise RuntimeError("no reader")
            make = ns.get(ALIASES.get(name, name))
            if make is None:
                raise RuntimeError("paraview.simple has no filter %s" % name)
            proxy = make(Input=state["source"] or state["reader"])
            try:
                configure(ALIASES.get(name, name), proxy, state["bounds"])
                apply(proxy, job.get("properties", {}).get(name))
                proxy.UpdatePipeline()
                info = describe(proxy)
                if job.get("then", {}).get(name):
                    print("first update: %s" % json.dumps(info))
                    apply(proxy, job["then"][name])
                    proxy.UpdatePipeline()
                    info = describe(proxy)
                return info
            finally:
                simple.Delete(proxy)
        run_step(case, name, run_filter)

    def close():
        for key in ("source", "reader"):
            if state[key] is not None:
                simple.Delete(state[key])
        return {}
    run_step(case, "close", close)


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    plugin, jobs_path = argv[1], argv[2]
    with open(jobs_path) as f:
        jobs = json.load(f)
    from paraview import simple
    ns = globals()
    simple.LoadPlugin(plugin, remote=False, ns=ns)
    ns["__simple"] = simple
    PRISTINE.update(ns)
    emit("READY")
    for job in jobs:
        run_job(job, ns)
    emit("DONE")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
