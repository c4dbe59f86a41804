#!/usr/bin/env python3
"""Replaces the generated blocks of a markdown file with files from a results directory.

usage: update_docs.py DOC.md RESULTS_DIR

A block is everything between "<!-- BEGIN generated:NAME -->" and "<!-- END generated:NAME -->";
it is replaced by RESULTS_DIR/NAME.md. Blocks whose file is missing are left as they are.
"""

import os
import re
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    doc, results = sys.argv[1], sys.argv[2]
    with open(doc) as f:
        text = f.read()

    def replace(match):
        name = match.group(1)
        path = os.path.join(results, name + ".md")
        if not os.path.exists(path):
            return match.group(0)
        with open(path) as f:
            body = f.read().rstrip("\n")
        return (f"<!-- BEGIN generated:{name} -->\n{body}\n<!-- END generated:{name} -->")

    pattern = re.compile(r"<!-- BEGIN generated:(\S+) -->.*?<!-- END generated:\1 -->", re.S)
    with open(doc, "w") as f:
        f.write(pattern.sub(replace, text))


if __name__ == "__main__":
    main()
