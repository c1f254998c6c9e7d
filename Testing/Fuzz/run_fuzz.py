#!/usr/bin/env python3
"""Runs the fuzz corpus of issue 10 against volillum-render and the plugin's filters.

    xvfb-run -a python3 run_fuzz.py --cli build/bin/volillum-render --pvpython pvpython \\
        --plugin build/lib/paraview-5.11/plugins/VolumetricIllumination/VolumetricIllumination.so \\
        --corpus build/Testing/Fuzz/corpus [--timeout 30] [--report fuzz.json]

Needs an X display (start it under ``xvfb-run -a``). When the corpus folder has no
cases.json (or with --generate) it is first written by make_corpus.py beside this script.

For every case of cases.json (see make_corpus.py):

* the CLI, when the case has cli_args: ``volillum-render --output TMP/x.png ARGS...``
  run in the corpus folder, in its own process group, with a time limit (--timeout) and
  an address-space limit (--memory-limit, off for sanitizer builds);
* the filters, when the case lists any: through pvpython running fuzz_filters.py, which
  loads the file and runs each filter, framing every step (reader, each filter) with
  marker lines. One worker process takes all the files in turn (fast: pvpython starts
  once); when it crashes or hangs, the step it was in is recorded and a new worker goes
  on with the next step. A crash that was not the first thing its worker did is run
  again alone (the reader and that one filter in a fresh process) to make sure it is not
  the aftermath of an earlier step; the result says if it did not reproduce. With
  --isolate every file gets a worker of its own (slower, as in a per-file ctest).

Outcomes of each run (case x target, the target being "cli", "reader" or a filter):

  ok         exit 0 / the step finished without an error message
  error      a clean refusal: the CLI exits 1 with a line "volillum-render: error: ...";
             a step printed a VTK error (ERR|) or raised a Python exception
  crash      killed by a signal or an abort (negative status, 134, 136, 139), or the
             worker died in the middle of a step
  hang       did not finish within --timeout seconds (--reader-timeout, default 10,
             for ParaView's reader to load a file in pvpython)
  sanitizer  the output holds "ERROR: AddressSanitizer", "ERROR: LeakSanitizer" or
             "runtime error:" (UBSan)
  fail       the CLI exited otherwise (non-zero status without its one error line)

A case passes when none of its runs crashed, hung, failed or had a sanitizer report.
The runner prints a table (class -> number of runs with each outcome, and the number of
failed cases), every failed run with the last lines of its output, the runs that exit 0
where cases.json says an error is required ("expect"), and as its last line
``N passed, M failed`` (cases). It exits 1 when any case failed (with --strict also when an
expected error was missing), else 0. --report FILE writes the table, the summary and
every run as JSON.

Other options: --jobs N runs N things at once (the pvpython worker chain counts as one;
default 2, 1 on a single core), --only TEXT runs the cases whose file name contains
TEXT, --no-cli / --no-filters skip a side, --skip-filter NAME leaves out a filter (the
meshing filters of a build without them), --external-readers counts crashes and hangs
inside ParaView's own readers (the pvpython "reader" step: not the plugin's code) as
"external" (passed, listed separately), -v prints every run.
"""
import argparse
import collections
import concurrent.futures
import json
import os
import queue
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MARK = "@@FUZZ "
OUTCOMES = ["ok", "error", "external", "crash", "hang", "sanitizer", "fail"]
FAILED = {"crash", "hang", "sanitizer", "fail"}
SEVERITY = {name: i for i, name in enumerate(OUTCOMES)}
SANITIZER = re.compile(r"ERROR: AddressSanitizer|ERROR: LeakSanitizer|runtime error:")
VTK_ERROR = re.compile(r"ERR\||^ERROR: |^ERROR In ", re.M)
ANSI = re.compile(r"\x1b\[[0-9;]*m")
CLI_ERROR = "volillum-render: error:"


class Run:
    """One run: a case against one target (cli, reader or a filter)."""

    def __init__(self, case, target, outcome, rc=None, seconds=0.0, output="", note=""):
        self.case = case
        self.target = target
        self.outcome = outcome
        self.rc = rc
        self.seconds = seconds
        self.output = output
        self.note = note

    def status(self):
        if self.rc is None:
            return ""
        if self.rc < 0:
            try:
                return "signal %s" % signal.Signals(-self.rc).name
            except ValueError:
                return "signal %d" % -self.rc
        return "exit %d" % self.rc

    def tail(self, lines=8):
        """The last lines of the output that say something (blank and VTK's
        vtkInformation dumps left out)."""
        keep = [l.rstrip() for l in ANSI.sub("", self.output).splitlines()
                if l.strip() and not l.startswith(MARK) and not l.startswith("  ")]
        return keep[-lines:]

    def as_json(self):
        return {"file": self.case["file"], "class": self.case["class"], "target": self.target,
                "outcome": self.outcome, "status": self.status(),
                "seconds": round(self.seconds, 3), "note": self.note, "tail": self.tail()}


# --------------------------------------------------------------------------------------
# Processes
# --------------------------------------------------------------------------------------
def limited(command, memory_mb):
    """The command under an address-space limit (through sh's ulimit, so nothing runs
    in the child before exec: safe with threads)."""
    if not memory_mb:
        return command
    return ["/bin/sh", "-c", 'ulimit -v %d && exec "$@"' % (memory_mb * 1024), "sh"] + command


def kill_group(process):
    """Kills the process group of a process this runner started (its own session)."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def uses_sanitizer(path):
    """Whether a binary or shared library was built with AddressSanitizer (its symbol
    table names __asan_init); an address-space limit would break ASan's shadow memory."""
    try:
        with open(path, "rb") as f:
            tail = b""
            while True:
                chunk = f.read(1 << 22)
                if not chunk:
                    return False
                if b"__asan_init" in tail + chunk:
                    return True
                tail = chunk[-16:]
    except OSError:
        return False


# --------------------------------------------------------------------------------------
# The CLI
# --------------------------------------------------------------------------------------
X_REFUSED = "bad X server connection"


def classify_cli(rc, text, timed_out):
    if SANITIZER.search(text):
        return "sanitizer"
    if timed_out:
        return "hang"
    if rc < 0 or rc in (134, 136, 139):
        return "crash"
    if rc == 0:
        return "ok"
    if rc == 1 and any(l.startswith(CLI_ERROR) for l in text.splitlines()):
        return "error"
    return "fail"


def run_cli(case, options, scratch):
    output = os.path.join(scratch, os.path.splitext(case["file"])[0] + ".png")
    command = limited([options.cli, "--output", output] + case["cli_args"], options.memory_limit)
    for attempt in range(10):
        start = time.monotonic()
        process = subprocess.Popen(command, cwd=options.corpus, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, start_new_session=True)
        timed_out = False
        try:
            out, _ = process.communicate(timeout=options.timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            kill_group(process)
            out, _ = process.communicate()
        text = out.decode("utf-8", "replace")
        # Xvfb now and then refuses a connection ("bad X server connection", VTK aborts
        # before the CLI does anything): that is the display, not the case: retry.
        display_refused = X_REFUSED in text and attempt < 3
        # 126/127 from sh: the executable could not be started (being relinked?): retry.
        started = timed_out or process.returncode not in (126, 127) or not text.startswith("sh:")
        if started and not display_refused:
            break
        time.sleep(1 if display_refused else 3)
    else:
        raise SystemExit("run_fuzz.py: cannot run %s:\n%s" % (options.cli, text))
    outcome = classify_cli(process.returncode, text, timed_out)
    note = ""
    if outcome == "ok" and VTK_ERROR.search(text):
        note = "exit 0 although VTK reported an error"
    elif outcome == "error" and len([l for l in text.splitlines() if l.strip()]) > 1:
        note = "more than the one error line"
    return Run(case, "cli", outcome, None if timed_out else process.returncode,
               time.monotonic() - start, text, note)


# --------------------------------------------------------------------------------------
# The pvpython worker
# --------------------------------------------------------------------------------------
class WorkerResult:
    def __init__(self):
        self.runs = []          # finished steps (Run)
        self.stopped = None     # (job index, step) where the worker died or hung
        self.first_step = True  # whether that step was the first of the worker
        self.exit_output = ""   # output after the last step (leak reports)
        self.exit_problem = None  # "sanitizer" or "crash" when the worker ended badly
        self.exit_rc = None
        self.started = False


def classify_step(text, info):
    """ok / error for a step that finished, with a note on suspicious results."""
    if SANITIZER.search(text):
        return "sanitizer", ""
    if info.get("exception"):
        return "error", info["exception"]
    empty = not info.get("points") and not info.get("cells")
    if VTK_ERROR.search(text):
        return "error", "" if empty else "error reported but the output is not empty"
    return "ok", ("empty output and no error message" if empty and "points" in info else "")


def run_worker(jobs, cases, options, scratch):
    """Runs one pvpython worker on jobs; returns a WorkerResult. Each step has
    options.timeout seconds (the start-up a minute more)."""
    result = WorkerResult()
    fd, jobs_path = tempfile.mkstemp(suffix=".json", dir=scratch)
    with os.fdopen(fd, "w") as f:
        json.dump(jobs, f)
    command = limited([options.pvpython, os.path.join(HERE, "fuzz_filters.py"), options.plugin,
                       jobs_path], options.memory_limit)
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               stdin=subprocess.DEVNULL, start_new_session=True)
    lines = queue.Queue()

    def pump():
        for raw in process.stdout:
            lines.put(raw.decode("utf-8", "replace"))
        lines.put(None)
    reader = threading.Thread(target=pump, daemon=True)
    reader.start()
    index = {job["case"]: i for i, job in enumerate(jobs)}
    current, log, began = None, [], time.monotonic()
    deadline = began + options.timeout + 60
    steps_done = 0
    timed_out = done = False
    while True:
        try:
            line = lines.get(timeout=max(0.0, deadline - time.monotonic()))
        except queue.Empty:
            timed_out = True
            kill_group(process)
            break
        if line is None:
            break
        if not line.startswith(MARK):
            log.append(line)
            continue
        fields = line[len(MARK):].rstrip("\n").split("\t")
        if fields[0] == "READY":
            result.started = True
            log = []
            deadline = time.monotonic() + options.timeout
        elif fields[0] == "BEGIN":
            current, log, began = (fields[1], fields[2]), [], time.monotonic()
            deadline = began + (options.reader_timeout if fields[2] == "reader" else options.timeout)
        elif fields[0] == "END":
            info = json.loads(fields[3])
            text = "".join(log)
            outcome, note = classify_step(text, info)
            case = cases[fields[1]]
            if not (fields[2] == "close" and outcome == "ok"):
                result.runs.append(Run(case, fields[2], outcome, None, time.monotonic() - began,
                                       text, note))
            current, log = None, []
            steps_done += 1
            deadline = time.monotonic() + options.timeout
        elif fields[0] == "DONE":
            done = True
            log = []
    rc = process.wait()
    reader.join(timeout=5)
    text = "".join(log)
    if current is not None:
        case = cases[current[0]]
        if SANITIZER.search(text):
            outcome = "sanitizer"
        elif timed_out:
            outcome = "hang"
        else:
            outcome = "crash"
        result.runs.append(Run(case, current[1], outcome, None if timed_out else rc,
                               time.monotonic() - began, text))
        result.stopped = (index[current[0]], current[1])
        result.first_step = steps_done == 0 or (steps_done == 1 and current[1] != "reader"
                                                and index[current[0]] == 0)
    elif done and not timed_out:
        # Everything ran; a report or a crash now comes from the worker's exit (leaks,
        # destructors, unloading the plugin).
        result.exit_output = text
        if SANITIZER.search(text):
            result.exit_problem = "sanitizer"
        elif rc != 0:
            result.exit_problem = "crash"
        result.exit_rc = rc
    else:
        raise SystemExit("run_fuzz.py: the pvpython worker failed outside any case "
                         "(status %s):\n%s" % (rc, ANSI.sub("", text)[-3000:]))
    return result


def make_job(case, corpus, filters=None):
    return {"case": case["file"], "file": os.path.join(corpus, case["file"]),
            "filters": list(case["filters"] if filters is None else filters),
            "properties": case.get("properties", {}), "then": case.get("then", {}),
            "prepare": case.get("prepare", {})}


def run_filters(chain, cases, options, scratch):
    """Runs the cases of chain (a list) through workers, restarting after each crash or
    hang; returns the runs."""
    runs = []
    pending = [make_job(case, options.corpus) for case in chain]
    while pending:
        result = run_worker(pending, cases, options, scratch)
        runs += result.runs
        if result.stopped is None:
            if result.exit_problem:
                runs += attribute_exit_report(pending, cases, options, scratch, result)
            break
        job_index, step = result.stopped
        job = pending[job_index]
        if not result.first_step and runs[-1].outcome in ("crash", "sanitizer"):
            confirm_alone(job, step, cases, options, scratch, runs[-1])
        remaining = job["filters"][job["filters"].index(step) + 1:] if step in job["filters"] else []
        pending = pending[job_index + 1:]
        if remaining:
            pending.insert(0, dict(job, filters=remaining))
    return runs


def confirm_alone(job, step, cases, options, scratch, run):
    """Runs the reader and the one step that died in a fresh worker."""
    filters = [step] if step in job["filters"] else []
    again = run_worker([dict(job, filters=filters)], cases, options, scratch)
    if again.stopped is None:
        run.note = "did not reproduce when run alone (damage from an earlier step?)"
    elif again.stopped[1] != step:
        run.note = "run alone, it died in %s instead" % again.stopped[1]


def attribute_exit_report(jobs, cases, options, scratch, result):
    """A sanitizer report or a crash after the last step (LeakSanitizer at exit, a
    destructor): rerun the worker's cases one per process to find which cause it."""
    if len(jobs) == 1:
        return [Run(cases[jobs[0]["case"]], "exit", result.exit_problem, result.exit_rc, 0.0,
                    result.exit_output)]
    runs = []
    for job in jobs:
        alone = run_worker([job], cases, options, scratch)
        if alone.stopped is None and alone.exit_problem:
            runs.append(Run(cases[job["case"]], "exit", alone.exit_problem, alone.exit_rc, 0.0,
                            alone.exit_output))
    if not runs:
        runs.append(Run(cases[jobs[-1]["case"]], "exit", result.exit_problem, result.exit_rc, 0.0,
                        result.exit_output, "only when the cases ran together; attributed "
                        "to the last one"))
    return runs


# --------------------------------------------------------------------------------------
# Report
# --------------------------------------------------------------------------------------
def summarize(runs, cases, options, seconds):
    by_case = collections.OrderedDict((c["file"], []) for c in cases)
    for run in runs:
        if options.external_readers and run.target == "reader" and run.outcome in ("crash", "hang"):
            run.note = ("%s in ParaView's reader; " % run.outcome) + run.note
            run.outcome = "external"
        by_case[run.case["file"]].append(run)
    table = collections.OrderedDict()
    failed_cases = []
    for case in cases:
        row = table.setdefault(case["class"], collections.OrderedDict(
            [("cases", 0), ("failed cases", 0)] + [(o, 0) for o in OUTCOMES]))
        row["cases"] += 1
        case_runs = by_case[case["file"]]
        for run in case_runs:
            row[run.outcome] += 1
        if any(run.outcome in FAILED for run in case_runs):
            row["failed cases"] += 1
            failed_cases.append(case["file"])
    missing = []
    for case in cases:
        for run in by_case[case["file"]]:
            if case.get("expect", {}).get(run.target) == "error" and run.outcome == "ok":
                missing.append(run)

    columns = ["cases", "failed cases"] + [o for o in OUTCOMES if o != "external" or options.external_readers]
    width = max([len("class")] + [len(k) for k in table]) + 2
    print()
    print("class".ljust(width) + "".join(c.rjust(max(len(c), 5) + 2) for c in columns))
    totals = collections.Counter()
    for klass, row in table.items():
        print(klass.ljust(width) + "".join(str(row[c]).rjust(max(len(c), 5) + 2) for c in columns))
        totals.update(row)
    print("total".ljust(width) + "".join(str(totals[c]).rjust(max(len(c), 5) + 2) for c in columns))
    print("(runs of each outcome: a case runs the CLI, the pvpython reader and each filter)")

    bad = [r for r in runs if r.outcome in FAILED]
    if bad:
        print("\nFailed runs:")
        for run in bad:
            print("\n%s %s [%s] %s%s%s" % (run.outcome.upper(), run.case["file"], run.target,
                                          run.status(), " after %.0f s" % run.seconds
                                          if run.outcome == "hang" else "",
                                          " (%s)" % run.note if run.note else ""))
            if run.case.get("note"):
                print("    case: %s" % run.case["note"])
            if run.target == "cli":
                print("    args: %s" % " ".join(run.case["cli_args"]))
            for line in run.tail():
                print("    | " + line[:300])
    external = [r for r in runs if r.outcome == "external"]
    if external:
        print("\nCounted as passed (--external-readers): ParaView's own reader crashed or hung:")
        for run in external:
            print("  %s [%s] %s" % (run.case["file"], run.target, run.note))
    notes = collections.OrderedDict()
    for run in runs:
        if run.note and run.outcome not in FAILED and run.outcome != "external":
            notes.setdefault("%s: %s" % ("CLI" if run.target == "cli" else "pvpython", run.note),
                             []).append(run)
    if notes:
        print("\nNotes on runs that passed:")
        for note, noted in notes.items():
            print("  %s (%d): %s" % (note, len(noted), ", ".join(
                r.case["file"] + ("" if r.target == "cli" else " [%s]" % r.target) for r in noted)))
    if missing:
        print("\nExit 0 where an error is required (cases.json 'expect')%s:" %
              ("" if options.strict else ", not counted as failures without --strict"))
        for run in missing:
            print("  %s [%s]%s" % (run.case["file"], run.target, " (%s)" % run.note if run.note else ""))
    if options.strict:
        for run in missing:
            if run.case["file"] not in failed_cases:
                failed_cases.append(run.case["file"])
    passed = len(cases) - len(failed_cases)
    if options.report:
        with open(options.report, "w") as f:
            json.dump({"passed": passed, "failed": len(failed_cases), "seconds": round(seconds, 1),
                       "table": table, "failed_cases": failed_cases,
                       "missing_errors": [r.as_json() for r in missing],
                       "runs": [r.as_json() for r in runs]}, f, indent=1)
            f.write("\n")
    print("\ntotal time %.1f s" % seconds)
    print("%d passed, %d failed" % (passed, len(failed_cases)))
    return 1 if failed_cases else 0


# --------------------------------------------------------------------------------------
def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cli", required=True, help="volillum-render")
    parser.add_argument("--pvpython", required=True)
    parser.add_argument("--plugin", required=True, help="VolumetricIllumination.so")
    parser.add_argument("--corpus", required=True, help="corpus folder (made when missing)")
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds per run (30)")
    parser.add_argument("--reader-timeout", type=float, default=10.0,
                        help="seconds for ParaView's reader to load a file in pvpython (10)")
    parser.add_argument("--report", help="write the results as JSON")
    parser.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1),
                        help="runs at once (2, or 1 on one core)")
    parser.add_argument("--memory-limit", type=int, default=4096, metavar="MB",
                        help="address-space limit per process (4096; 0: none; "
                             "off for AddressSanitizer builds)")
    parser.add_argument("--isolate", action="store_true", help="one pvpython worker per file")
    parser.add_argument("--generate", action="store_true", help="rewrite the corpus first")
    parser.add_argument("--only", help="only cases whose file name contains this")
    parser.add_argument("--no-cli", action="store_true")
    parser.add_argument("--no-filters", action="store_true")
    parser.add_argument("--skip-filter", action="append", default=[], metavar="NAME",
                        help="leave out a filter the plugin was built without (repeatable)")
    parser.add_argument("--external-readers", action="store_true",
                        help="count crashes/hangs in ParaView's readers as passed")
    parser.add_argument("--strict", action="store_true",
                        help="also fail when a required error is missing (exit 0)")
    parser.add_argument("-v", "--verbose", action="store_true")
    options = parser.parse_args(argv)
    options.corpus = os.path.abspath(options.corpus)
    options.cli = os.path.abspath(options.cli) if os.sep in options.cli else shutil.which(options.cli)
    options.pvpython = shutil.which(options.pvpython) or options.pvpython
    options.plugin = os.path.abspath(options.plugin)
    return options


def main(argv):
    options = parse_arguments(argv)
    start = time.monotonic()
    cases_path = os.path.join(options.corpus, "cases.json")
    if options.generate or not os.path.exists(cases_path):
        subprocess.run([sys.executable, os.path.join(HERE, "make_corpus.py"), options.corpus],
                       check=True)
    with open(cases_path) as f:
        cases = json.load(f)
    if options.only:
        cases = [c for c in cases if options.only in c["file"]]
    for case in cases:
        case["filters"] = [f for f in case["filters"] if f not in options.skip_filter]
    if options.memory_limit and any(uses_sanitizer(p) for p in (options.cli, options.plugin)):
        print("AddressSanitizer build: no address-space limit")
        options.memory_limit = 0
    os.environ.setdefault("VTK_SMP_BACKEND_IN_USE", "STDThread")
    if "DISPLAY" not in os.environ:
        print("run_fuzz.py: warning: no DISPLAY; run it under xvfb-run -a")
    by_name = {c["file"]: c for c in cases}
    lock = threading.Lock()
    runs = []

    def record(new_runs):
        with lock:
            runs.extend(new_runs)
            for run in new_runs:
                if options.verbose or run.outcome in FAILED:
                    print("%-9s %s [%s] %s" % (run.outcome, run.case["file"], run.target,
                                               run.status()), flush=True)

    binaries = (options.cli, options.plugin)
    stamps = [os.path.getmtime(p) if os.path.exists(p) else None for p in binaries]
    scratch = tempfile.mkdtemp(prefix="volillum-fuzz-")
    try:
        tasks = []
        filter_cases = [] if options.no_filters else [c for c in cases if c["filters"]]
        chains = [[c] for c in filter_cases] if options.isolate else [filter_cases]
        print("%d cases: %d CLI runs, %d files through pvpython" % (
            len(cases), 0 if options.no_cli else sum(1 for c in cases if c["cli_args"] is not None),
            len(filter_cases)), flush=True)
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, options.jobs)) as pool:
            for chain in chains:
                if chain:
                    tasks.append(pool.submit(lambda ch=chain: record(run_filters(ch, by_name, options, scratch))))
            if not options.no_cli:
                for case in cases:
                    if case["cli_args"] is not None:
                        tasks.append(pool.submit(lambda c=case: record([run_cli(c, options, scratch)])))
            for task in tasks:
                task.result()
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    for path, stamp in zip(binaries, stamps):
        if (os.path.getmtime(path) if os.path.exists(path) else None) != stamp:
            print("run_fuzz.py: warning: %s changed during the run" % path)
    order = {c["file"]: i for i, c in enumerate(cases)}
    runs.sort(key=lambda r: (order[r.case["file"]], r.target != "cli"))
    return summarize(runs, cases, options, time.monotonic() - start)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
