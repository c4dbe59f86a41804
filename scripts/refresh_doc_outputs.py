#!/usr/bin/env python3
"""Re-runs the commands shown in the docs and pastes their real output under them.

usage: scripts/refresh_doc_outputs.py [--kincal PATH] DOC.md [DOC.md ...]

In every ```console block of each DOC, a line "$ command" is a command and the lines after
it, up to the next "$ " line or the end of the block, are its output. Each command is run
again with bash (stdout and stderr together, as a terminal shows them) and its output
replaces the old one. The commands of one DOC run in order in one fresh scratch directory,
where `kincal` is on PATH and ./build/cli/kincal exists, both pointing to --kincal
(default: build/cli/kincal of this checkout). "mkdir D && cd D" and "cd D" change the
directory of the commands that follow. Nothing outside the scratch directory is touched
except the DOCs, and a DOC is only rewritten when every command in it ran.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

BLOCK = re.compile(r"```console\n(.*?)```", re.S)


def run_commands(doc_text, kincal):
    scratch = tempfile.mkdtemp(prefix="kincal-doc-")
    try:
        bindir = os.path.join(scratch, ".bin")
        os.makedirs(bindir)
        os.symlink(kincal, os.path.join(bindir, "kincal"))
        os.makedirs(os.path.join(scratch, "build", "cli"))
        os.symlink(kincal, os.path.join(scratch, "build", "cli", "kincal"))
        env = dict(os.environ, PATH=bindir + os.pathsep + os.environ["PATH"], COLUMNS="80")
        cwd = scratch

        def run(command):
            nonlocal cwd
            change = re.fullmatch(r"(?:mkdir (\S+) && )?cd (\S+)", command)
            if change:
                cwd = os.path.normpath(os.path.join(cwd, change.group(2)))
                os.makedirs(cwd, exist_ok=True)
                return ""
            if command == "ls":
                command = "ls -C"  # the columns a terminal shows, not one name per line
            done = subprocess.run(["bash", "-c", command + " 2>&1"], cwd=cwd, env=env,
                                  stdout=subprocess.PIPE, text=True)
            return done.stdout

        pieces, position = [], 0
        for block in BLOCK.finditer(doc_text):
            pieces.append(doc_text[position:block.start(1)])
            for line in block.group(1).splitlines():
                if line.startswith("$ "):
                    pieces.append(line + "\n" + run(line[2:]))
            position = block.end(1)
        pieces.append(doc_text[position:])
        return "".join(pieces)
    finally:
        shutil.rmtree(scratch)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kincal", default=os.path.join(root, "build", "cli", "kincal"))
    parser.add_argument("docs", nargs="+")
    args = parser.parse_args()
    kincal = os.path.abspath(args.kincal)
    if not os.access(kincal, os.X_OK):
        sys.exit(f"refresh_doc_outputs: {kincal}: not an executable (build kincal first)")
    for doc in args.docs:
        with open(doc) as f:
            text = f.read()
        refreshed = run_commands(text, kincal)
        with open(doc + ".tmp", "w") as f:
            f.write(refreshed)
        os.replace(doc + ".tmp", doc)
        print(f"refreshed {doc}")


if __name__ == "__main__":
    main()
