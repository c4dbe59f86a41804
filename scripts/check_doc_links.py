#!/usr/bin/env python3
"""Checks the links of README.md and of every page under docs/: each relative link names a file
or folder of the repository, and each #anchor a heading (or an <a id>/<a name>) of its page;
and that the index, docs/README.md, lists every page of docs/.

Anchors are GitHub's: a heading's text in lower case, without punctuation but for '-' and
'_', spaces as '-', and '-1', '-2'... after a repeated one. Links inside code (fenced blocks,
`spans`) are not links and are skipped; http(s) and mailto addresses are not fetched.
Exit 1, one line per broken link (page:line: link: what is wrong)."""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
SPAN = re.compile(r"(`+).*?\1")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
HTML_ANCHOR = re.compile(r"<a\s+(?:id|name)=\"([^\"]+)\"")


def slug(text):
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link in a heading: its text
    text = re.sub(r"<[^>]+>", "", text).strip().lower()  # backticks go with the punctuation
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def prose_lines(path):
    """(line number, text) of the lines outside code blocks."""
    fence = None
    for number, line in enumerate(path.read_text(encoding="utf-8").split("\n"), 1):
        stripped = line.lstrip()
        if fence:
            if stripped.startswith(fence):
                fence = None
            continue
        m = re.match(r"(```+|~~~+)", stripped)
        if m:
            fence = m.group(1)
            continue
        if line.startswith("    ") and not stripped.startswith(("-", "*", "|")):
            continue  # an indented code block (or a list item's continuation: no links lost
            # in practice, as continuations here are indented by two)
        yield number, line


def anchors(path, cache={}):
    if path not in cache:
        found, seen = set(), {}
        for _number, line in prose_lines(path):
            m = HEADING.match(line)
            if m:
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
            found.update(HTML_ANCHOR.findall(line))
        cache[path] = found
    return cache[path]


def main():
    index = ROOT / "docs" / "README.md"
    pages = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
    problems = []
    listed = set()
    for page in pages:
        for number, line in prose_lines(page):
            for target in LINK.findall(SPAN.sub("", line)):
                if re.match(r"[a-z]+:", target):
                    continue
                where = f"{page.relative_to(ROOT)}:{number}: {target}"
                name, _, anchor = target.partition("#")
                path = (page.parent / name).resolve() if name else page
                if page == index:
                    listed.add(path)
                if ROOT not in path.parents and path != ROOT:
                    problems.append(f"{where}: outside the repository")
                elif not path.exists():
                    problems.append(f"{where}: no such file or folder")
                elif anchor and path.suffix == ".md" and anchor not in anchors(path):
                    problems.append(f"{where}: no heading #{anchor} in {path.relative_to(ROOT)}")
    for page in sorted((ROOT / "docs").glob("*.md")):
        if page != index and page not in listed:
            problems.append(f"{page.relative_to(ROOT)}: not listed in the index, docs/README.md")
    for p in problems:
        print(p)
    print(f"check_doc_links: {len(problems)} problem(s) in {len(pages)} pages"
          if problems else f"check_doc_links: every link of {len(pages)} pages resolves")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
