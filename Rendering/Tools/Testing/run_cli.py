"""Runs volillum-render and checks its behaviour.

  run_cli.py --cli EXE [--expect-error TEXT] [--compare EXE BASELINE THRESHOLD] -- ARGS...

Without --expect-error the command must exit 0, print the illumination and frame times,
print no VTK error and write its PNG (the --output argument); with --compare the PNG is then compared to
the baseline. With --expect-error it must exit 1 and print exactly one line on stderr,
"volillum-render: error: ..." containing TEXT.
"""
import argparse
import os
import re
import subprocess
import sys


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cli", required=True)
    parser.add_argument("--expect-error")
    parser.add_argument("--compare", nargs=3, metavar=("EXE", "BASELINE", "THRESHOLD"))
    parser.add_argument("args", nargs=argparse.REMAINDER)
    options = parser.parse_args()
    args = [a for a in options.args if a != "--"]
    run = subprocess.run([options.cli] + args, capture_output=True, text=True, timeout=600)
    sys.stdout.write(run.stdout)
    sys.stderr.write(run.stderr)
    if options.expect_error is not None:
        lines = [l for l in run.stderr.splitlines() if l.strip()]
        ok = (run.returncode == 1 and len(lines) == 1
              and lines[0].startswith("volillum-render: error:")
              and options.expect_error in lines[0])
        print("expected one error line with %r and exit 1: %s" % (options.expect_error, "ok" if ok else "FAILED"))
        return 0 if ok else 1
    if run.returncode != 0:
        print("FAILED: exit status %d" % run.returncode)
        return 1
    if "ERR|" in run.stderr or "ERROR:" in run.stderr:
        print("FAILED: VTK reported an error")
        return 1
    for pattern in (r"illumination \(.*\): [0-9.e-]+ s", r"^frame: [0-9.e-]+ s", r"^wrote (.+)$"):
        if not re.search(pattern, run.stdout, re.M):
            print("FAILED: output lacks %r" % pattern)
            return 1
    output = re.search(r"^wrote (.+)$", run.stdout, re.M).group(1)
    if not os.path.isfile(output) or os.path.getsize(output) == 0:
        print("FAILED: %s was not written" % output)
        return 1
    if options.compare:
        exe, baseline, threshold = options.compare
        return subprocess.run([exe, output, baseline, threshold]).returncode
    return 0


if __name__ == "__main__":
    sys.exit(main())
