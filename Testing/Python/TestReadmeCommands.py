"""Every command the README shows works as written.

Extracts the README's code blocks (lines indented by four spaces, continuation lines joined)
and runs, in order, each shell command that runs a project program (volillum-render, the
benchmarks, the pvpython examples and benchmarks, plot_benchmark.py) and each paraview.simple
example (with pvpython), from a scratch folder that holds the build, the sources' Testing/
and Data/ and ../shared as a fresh clone beside ../shared has them. Commands run as written
with DISPLAY unset, so a command that needs a display and does not say `xvfb-run -a` fails;
long ones run in their smoke form (SMOKE below), and against a build for another ParaView
line than the README's the plugin's folder is that build's (README_PARAVIEW below): the only
changes made to a command. Each
must exit 0 and write the files it names (arguments ending in .png or .json, and the folder
plot_benchmark.py draws into); a paraview.simple example fails on a property or filter name
the plugin does not have. The set-up commands (./setup.sh) are the ones CI runs.
Usage: python3 TestReadmeCommands.py SOURCE_DIR BUILD_DIR SHARED_DIR PVPYTHON
"""
import os
import shlex
import subprocess
import sys
import tempfile
import time

# Programs whose README command runs long: the flag that gives their smoke run.
SMOKE = {
    "volillum-benchmark": "--smoke",
    "volillum-unstructured-benchmark": "--smoke",
    "IlluminatedVolumeBenchmark.py": "--smoke",
    "ParallelBenchmark.py": "--smoke",
}
PROGRAMS = ("build/bin/volillum-", "Testing/", "plot_benchmark.py")
# The ParaView line whose plugin folder (build/lib/paraview-X.Y/plugins) the README names.
README_PARAVIEW = "paraview-5.11"


def code_blocks(readme):
    """The README's indented code blocks, each a list of lines (continuations joined)."""
    blocks, current, previous_blank = [], [], True
    for line in open(readme).read().splitlines():
        if line.startswith("    ") and (current or previous_blank):
            current.append(line[4:])
        elif current and not line.strip():
            current.append("")
        else:
            if current:
                blocks.append(current)
            current = []
        previous_blank = not line.strip()
    if current:
        blocks.append(current)
    joined = []
    for block in blocks:
        text = "\n".join(block).strip("\n").replace("\\\n", " ")
        lines = text.splitlines()
        joined.append(lines if is_python(text) else [" ".join(l.split()) for l in lines])
    return joined


def is_python(text):
    return text.lstrip().startswith(("from ", "import "))


def smoke_form(command):
    for program, flag in SMOKE.items():
        if program in command and flag not in command:
            return command + " " + flag
    return command


def named_outputs(command, work):
    """The files a command names that do not exist before it runs (its outputs)."""
    words = shlex.split(command)
    outputs = [w for w in words if w.endswith((".png", ".json"))]
    if "plot_benchmark.py" in command:
        outputs.append(words[-1])
    return [w for w in outputs if not os.path.exists(os.path.join(work, w))]


def main():
    source, build, shared, pvpython = sys.argv[1:5]
    scratch = tempfile.mkdtemp(prefix="volillum-readme-")
    work = os.path.join(scratch, "clone")
    os.makedirs(work)
    os.symlink(os.path.abspath(shared), os.path.join(scratch, "shared"))
    os.symlink(os.path.abspath(build), os.path.join(work, "build"))
    for name in ("Testing", "Data", "README.md"):
        os.symlink(os.path.join(os.path.abspath(source), name), os.path.join(work, name))
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    env["PATH"] = os.path.dirname(os.path.abspath(pvpython)) + os.pathsep + env.get("PATH", "")
    # The build's own ParaView line (build/lib/paraview-X.Y holds its plugin).
    lines = [d for d in os.listdir(os.path.join(build, "lib")) if d.startswith("paraview-")]
    line = lines[0] if len(lines) == 1 else README_PARAVIEW
    failures, ran = [], 0
    for block in code_blocks(os.path.join(source, "README.md")):
        block = [l.replace(README_PARAVIEW, line) for l in block]
        text = "\n".join(block)
        if is_python(text):
            if "LoadPlugin" not in text:
                continue
            commands = [(pvpython + " -", text)]
        else:
            commands = [(smoke_form(l), None) for l in block
                        if l and any(p in l for p in PROGRAMS) and not l.startswith("./setup.sh")]
        for command, stdin in commands:
            ran += 1
            outputs = [] if stdin else named_outputs(command, work)
            print("$ " + command, flush=True)
            start = time.time()
            run = subprocess.run(command, shell=True, cwd=work, env=env, input=stdin, text=True,
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=1200)
            print("\n".join(run.stdout.splitlines()[-8:]))
            print("(%.1f s)" % (time.time() - start), flush=True)
            if run.returncode != 0:
                failures.append("exit %d: %s" % (run.returncode, command))
                continue
            for output in outputs:
                if not os.path.exists(os.path.join(work, output)):
                    failures.append("%s did not write %s" % (command, output))
    print("ran %d README command(s)" % ran)
    for failure in failures:
        print("FAIL  " + failure)
    if ran < 8:
        failures.append("found %d commands in the README, expected at least 8" % ran)
        print("FAIL  " + failures[-1])
    print("%d passed, %d failed" % (ran - len(failures), len(failures)))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
