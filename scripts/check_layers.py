#!/usr/bin/env python3
"""Checks that #includes follow the layers of docs/architecture.md.

Top level: framework/ includes no model, backend, test problem or program file; models/,
solvers/ and problems/ include only framework/ (and themselves): nothing of each other, no
program file.
Inside framework/: a folder includes only folders below it (ALLOWED); report/ (the pages for
people) is included by no other framework folder and no model, backend or test problem. Exit 1, one line per
offending include (file:line: what it includes and why that is not allowed)."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALLOWED = {  # framework folder -> the framework folders it may include (besides itself)
    "base": set(),
    "least_squares": {"base"},
    "kinematics": {"base"},
    "io": {"base", "kinematics"},
    "calibration": {"base", "least_squares", "kinematics"},
    "analysis": {"base", "least_squares", "kinematics", "calibration"},
    "design": {"base", "least_squares", "kinematics", "calibration", "analysis"},
    "extension": {"base", "least_squares", "kinematics", "io"},
    "workflows": {"base", "least_squares", "kinematics", "io", "calibration", "analysis", "design"},
    "report": {"base", "least_squares", "kinematics", "io", "calibration", "analysis", "design",
               "workflows"},
}
# Framework folders only the faces (cli/, python/) and programs on top may include: no other
# framework folder, model, backend or test problem.
TOP_ONLY = {"report"}
TOP_FORBIDDEN = {  # top-level folder -> the kincal folders it must not include
    "framework": {"models", "solvers", "problems", "cli", "vision"},
    "models": {"solvers", "problems", "cli", "vision"},
    "solvers": {"models", "problems", "cli", "vision"},
    "problems": {"models", "solvers", "cli", "vision"},  # backends only through SolverRegistry
    "vision": {"solvers", "problems", "cli"},  # images: framework/ and models/ only
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]kincal/([a-z_]+)/(?:([a-z_]+)/)?')


def main() -> int:
    problems = []
    folders = set(os.listdir(os.path.join(ROOT, "framework")))
    unknown = sorted(f for f in folders if os.path.isdir(os.path.join(ROOT, "framework", f)) and f not in ALLOWED)
    for f in unknown:
        problems.append(f"framework/{f}: a folder scripts/check_layers.py does not know: add it to ALLOWED and to docs/architecture.md")
    flat = sorted(f for f in folders if os.path.isfile(os.path.join(ROOT, "framework", f)))
    for f in flat:
        problems.append(f"framework/{f}: files belong in a subfolder of framework/ (docs/architecture.md)")
    for top in TOP_FORBIDDEN:
        for dirpath, _dirs, files in os.walk(os.path.join(ROOT, top)):
            for name in sorted(files):
                if not name.endswith((".hpp", ".cpp")):
                    continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, ROOT)
                parts = rel.split(os.sep)
                here = parts[1] if top == "framework" and len(parts) > 2 else None
                with open(path, encoding="utf-8") as text:
                    for number, line in enumerate(text, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        folder, sub = m.group(1), m.group(2)
                        if folder in TOP_FORBIDDEN[top]:
                            problems.append(f"{rel}:{number}: includes kincal/{folder}/: {top}/ must not depend on {folder}/")
                        elif folder == "framework" and sub in TOP_ONLY and top != "framework":
                            problems.append(f"{rel}:{number}: includes framework/{sub}/: only the faces (cli/, python/) may include it")
                        elif here and folder == "framework" and sub != here and sub not in ALLOWED.get(here, set()):
                            problems.append(f"{rel}:{number}: includes framework/{sub}/: framework/{here}/ may include only {', '.join(sorted(ALLOWED[here])) or 'nothing else'}")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
