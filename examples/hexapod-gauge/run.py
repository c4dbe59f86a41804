#!/usr/bin/env python3
"""The hexapod walk-through of docs/calibrating-a-machine.md two ways: its command sequence
(kincal model, simulate, observability, calibrate, verify, export, each run in an empty
folder as the document shows them) and project.yaml beside this script (kincal run), which
must write the same files (examples/project_check.py).

    run.py [--kincal PATH] [--out DIR]

Exit codes: 0 the same; 1 a difference or a failed command; 2 bad arguments."""

import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import project_check  # noqa: E402

SEQUENCE = [
    ["model", "--preset", "cube-hexapod", "--out", "nominal.json"],
    ["simulate", "--model", "nominal.json", "--case", "5", "--seed", "7", "--solver", "gn",
     "--write-data", "measured.csv"],
    ["observability", "--model", "nominal.json", "--data", "measured.csv"],
    ["calibrate", "--model", "nominal.json", "--data", "measured.csv", "--out",
     "calibrated.json", "--json", "report.json", "--html", "report.html"],
    ["verify", "--report", "report.json", "--model", "calibrated.json"],
    ["export", "--model", "calibrated.json", "--format", "csv", "--out", "hexapod-joints.csv"],
]
OUTPUTS = ["nominal.json", "measured.csv", "measured.truth.json", "calibrated.json",
           "report.json", "report.html", "hexapod-joints.csv"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--kincal", default=shutil.which("kincal") or "kincal")
    ap.add_argument("--out", default="hexapod-gauge-out", help="folder for the files written")
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    if os.sep in args.kincal:  # the commands run in a folder of their own
        args.kincal = os.path.abspath(args.kincal)
    commands, project = os.path.join(out, "commands"), os.path.join(out, "project")
    shutil.rmtree(commands, ignore_errors=True)
    os.makedirs(commands)
    for step in SEQUENCE:
        p = subprocess.run([args.kincal] + step, cwd=commands, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            sys.stderr.write(p.stdout + p.stderr)
            print("FAILED: kincal %s exited with %d" % (" ".join(step), p.returncode))
            return 1
    failures = project_check.check(args.kincal, os.path.join(HERE, "project.yaml"),
                                   {"out": project}, commands, project, OUTPUTS,
                                   [(project + "/", "")])
    for f in failures:
        print("FAILED: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
