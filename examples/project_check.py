"""What the example scripts use to hold a project file (docs/projects.md) to the command
sequence it replaces: `kincal run PROJECT` must write the same files, byte for byte, except
that the paths it records are its own and its JSON reports record the project (the key
"project": the file's content and SHA-256, the step, the variables)."""

import hashlib
import json
import os
import shutil
import subprocess
import sys


def run_project(kincal, project, variables):
    """Runs `kincal run PROJECT --set NAME=VALUE...`; returns the completed process."""
    cmd = [kincal, "run", project]
    for name, value in variables.items():
        cmd += ["--set", "%s=%s" % (name, value)]
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def compare(sequence_files, project_files, project_path, replace):
    """Failures (one line each) where a project output differs from the command sequence's.
    sequence_files and project_files are parallel lists of paths; `replace` maps the
    project's path prefixes to the sequence's, applied to the project's file texts."""
    with open(project_path, "rb") as f:
        content = f.read()
    digest = hashlib.sha256(content).hexdigest()
    failures = []
    for expected_path, got_path in zip(sequence_files, project_files):
        name = os.path.basename(got_path)
        if not os.path.isfile(got_path):
            failures.append("kincal run wrote no %s" % got_path)
            continue
        with open(expected_path, encoding="utf-8") as f:
            expected = f.read()
        with open(got_path, encoding="utf-8") as f:
            got = f.read()
        for old, new in replace:
            got = got.replace(old, new)
        if name.endswith(".json") and '"project"' in got:
            report = json.loads(got)
            record = report.pop("project")
            if record["sha256"] != digest or record["content"] != content.decode("utf-8"):
                failures.append("%s: the project record is not the project file's" % name)
            got = json.dumps(report, indent=2)
            expected = json.dumps(json.loads(expected), indent=2)
        if got != expected:
            failures.append("%s differs from the command sequence's %s" % (got_path,
                                                                           expected_path))
    return failures


def check(kincal, project, variables, sequence_dir, project_dir, names, replace):
    """Runs the project into `project_dir` (emptied first; `variables` set on the command
    line) and compares the files `names` with the command sequence's in `sequence_dir`;
    prints the outcome and returns the failures."""
    shutil.rmtree(project_dir, ignore_errors=True)
    p = run_project(kincal, project, variables)
    if p.returncode != 0:
        sys.stderr.write(p.stdout + p.stderr)
        return ["kincal run %s exited with %d" % (project, p.returncode)]
    failures = compare([os.path.join(sequence_dir, n) for n in names],
                       [os.path.join(project_dir, n) for n in names], project, replace)
    if not failures:
        print("kincal run %s wrote the %d files of the command sequence, the same"
              % (os.path.basename(project), len(names)))
    return failures
