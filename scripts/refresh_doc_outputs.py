#!/usr/bin/env python3
"""Re-runs every command shown in the docs and writes what it printed back into the page.

The pages are README.md and every page of docs/ (docs/*.md).

A transcript in a page is a ```console block whose first line starts with "$ ": each "$ " line
is a command (a line ending in a backslash continues it), the lines up to the next one are what
it printed (stdout and stderr together, as on a terminal). The blocks of one page run in
order in one bash session started in an empty directory, with the build's `kincal` first on
PATH, so a page reads like the walk-through it is: `mkdir`, `cd`, files made by one block and
used by the next.

  scripts/refresh_doc_outputs.py              rewrite the outputs (and the screenshots)
  scripts/refresh_doc_outputs.py --check      exit 1 naming each block whose output differs

--check compares with times masked ("29.974 ms", "(0.0225 s)": they differ between runs and
machines); everything else must match, digits included. A block preceded by
`<!-- doc-outputs: skip REASON -->` is not run (the script lists it with its reason).

A transcript shows what a user sees doing what the page says, so an error in it is a page
whose commands no longer work (a file the session never made: "cannot open model file")
unless the page means it: a block preceded by `<!-- doc-outputs: shows-error -->` may print
"kincal ...: error: ..."; any other that does is reported by both modes, and --check fails.

Abridged blocks: a block preceded by `<!-- doc-outputs: abridge REGEX -->` shows, of each run
of more than three consecutive output lines matching REGEX (Python's re.match; a parameter
table's rows, say), the first two and one line saying how many more there are. The whole
block, every line of every output, goes to docs/generated/transcripts/<page>-<n>.txt (the
n-th abridged block of docs/<page>.md; top-README-<n>.txt for README.md), and the line after
the block links to it. The script writes the abridged block, the file and the link; --check
compares the file with the full outputs and the page with their abridged form, so nothing
shown or kept goes unchecked, and names a transcript file that no block writes any more.

Screenshots: docs/generated/img/calibration-report.png is the page that
calibrating-a-machine.md's walk-through writes (report.html), taken by headless Chromium. Beside it,
calibration-report.png.source holds the SHA-256 of that page with times masked; --check
recomputes it, so a report page that changed makes the screenshot stale.
"""

import argparse
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
SKIP = re.compile(r"<!-- doc-outputs: skip (.+?) -->")
ABRIDGE = re.compile(r"<!-- doc-outputs: abridge (.+?) -->")
SHOWS_ERROR = re.compile(r"<!-- doc-outputs: shows-error -->")
ERROR_LINE = re.compile(r"^kincal(?: [a-z-]+)?: error: ")
TRANSCRIPTS = DOCS / "generated" / "transcripts"
FULL_OUTPUT = "<sub>Full output: "  # starts the line after an abridged block
KEEP = 2  # lines of a run shown before "… N more"
# Times vary from run to run; nothing else may.
TIME = re.compile(r"\b\d+(?:\.\d+)?(?:e[-+]?\d+)? ?(?:ms|s|µs)\b")
MARK = "@@kincal-doc-outputs@@"
SCREENSHOTS = {
    # page whose session writes the HTML -> (file in that session, image under docs/generated/img)
    "calibrating-a-machine.md": ("hexcal/report.html", "calibration-report.png"),
}


def mask(text):
    return TIME.sub("<time>", text)


class Block:
    def __init__(self, start, end, commands, outputs, skip, abridge, shows_error=False):
        self.start, self.end = start, end  # line indices of the fences
        self.shows_error = shows_error  # the page means the error it shows
        self.commands, self.outputs, self.skip = commands, outputs, skip
        self.abridge = abridge  # the compiled REGEX of an abridged block, else None
        self.transcript = None  # its file under TRANSCRIPTS, set by main


def abridged(output, pattern, transcript_name):
    """`output` (lines) with each run of more than KEEP + 1 lines matching `pattern` cut to its
    first KEEP lines and one saying how many more there are."""
    shown, i = [], 0
    while i < len(output):
        j = i
        while j < len(output) and pattern.match(output[j]):
            j += 1
        if j - i > KEEP + 1:
            indent = output[i][:len(output[i]) - len(output[i].lstrip())]
            shown += output[i:i + KEEP]
            shown.append(f"{indent}… {j - i - KEEP} more like these "
                         f"(full output: {transcript_name})")
            i = j
        elif j > i:
            shown += output[i:j]
            i = j
        else:
            shown.append(output[i])
            i += 1
    return shown


def transcript_text(page_name, commands, outputs):
    header = (f"# The full output of a block abridged in {page_name}, written by "
              "scripts/refresh_doc_outputs.py: do not edit.")
    body = [header]
    for command, output in zip(commands, outputs):
        body += ["$ " + command[0]] + command[1:] + output
    return "\n".join(body) + "\n"


def read_transcript(path):
    """The outputs of a transcript file written by transcript_text, one list per command."""
    lines = path.read_text().rstrip("\n").split("\n")[1:]
    outputs, continued = [], False
    for line in lines:
        if line.startswith("$ ") and not continued:
            outputs.append([])
            continued = line.endswith("\\")
        elif continued:
            continued = line.endswith("\\")
        elif outputs:
            outputs[-1].append(line)
    return outputs


def parse_page(lines):
    """The transcript blocks of a page (lines without their newlines)."""
    blocks = []
    i = 0
    while i < len(lines):
        if lines[i] == "```console" and i + 1 < len(lines) and lines[i + 1].startswith("$ "):
            skip = abridge = None
            shows_error = False
            for back in (i - 1, i - 2):
                if back >= 0 and SHOWS_ERROR.search(lines[back]):
                    shows_error = True
                if back >= 0 and SKIP.search(lines[back]):
                    skip = SKIP.search(lines[back]).group(1)
                if back >= 0 and ABRIDGE.search(lines[back]):
                    abridge = re.compile(ABRIDGE.search(lines[back]).group(1))
            j = i + 1
            commands, outputs = [], []
            while j < len(lines) and not lines[j].startswith("```"):
                if lines[j].startswith("$ "):
                    command = [lines[j][2:]]
                    while command[-1].endswith("\\") and j + 1 < len(lines):
                        j += 1
                        command.append(lines[j])
                    commands.append(command)
                    outputs.append([])
                else:
                    outputs[-1].append(lines[j])
                j += 1
            if skip and abridge:
                sys.exit(f"refresh_doc_outputs: line {i + 1}: a block not run cannot be abridged")
            blocks.append(Block(i, j, commands, outputs, skip, abridge, shows_error))
            i = j + 1
        else:
            i += 1
    return blocks


def run_session(blocks, kincal_dir, build_dir, workdir):
    """Runs every command of the page's blocks in one bash; returns their outputs in order."""
    # `ls` as a terminal shows it (columns), and ./build as in a checkout (./build/cli/kincal,
    # the example programs).
    script = ["exec 2>&1", "shopt -s expand_aliases", "alias ls='ls -C'",
              "cd " + shlex_quote(str(workdir)),
              "ln -s " + shlex_quote(str(build_dir)) + " build"]
    n = 0
    for block in blocks:
        if block.skip:
            continue
        for command in block.commands:
            script.append("echo " + MARK + str(n))
            script.append("\n".join(command))
            n += 1
    script.append("echo " + MARK + "end")
    env = dict(os.environ, PATH=str(kincal_dir) + os.pathsep + os.environ["PATH"],
               COLUMNS="80", LC_ALL="C.UTF-8", TZ="UTC")
    env.pop("KINCAL_PLUGIN_PATH", None)
    result = subprocess.run(["bash", "--noprofile", "--norc"], input="\n".join(script) + "\n",
                            capture_output=True, text=True, env=env, timeout=1800)
    parts = result.stdout.split(MARK)
    outputs = []
    for k in range(n):
        chunk = parts[k + 1]
        assert chunk.startswith(str(k) + "\n"), chunk[:40]
        body = chunk[len(str(k)) + 1:]
        outputs.append(body.rstrip("\n").split("\n") if body.strip("\n") else [])
    return outputs


def shlex_quote(text):
    return "'" + text.replace("'", "'\\''") + "'"


def screenshot(html, image):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        sys.exit("refresh_doc_outputs: chromium is needed for the screenshots (scripts/setup.sh --all)")
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                        "--hide-scrollbars", "--user-data-dir=" + profile,
                        "--window-size=1000,1400", "--screenshot=" + str(image),
                        "file://" + str(html)], check=True, capture_output=True, timeout=180)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    parser.add_argument("--kincal", default=str(ROOT / "build" / "cli" / "kincal"),
                        help="the kincal binary to run (default: build/cli/kincal)")
    parser.add_argument("pages", nargs="*",
                        help="pages under docs/, or README.md (default: every page)")
    args = parser.parse_args()
    kincal = Path(args.kincal).resolve()
    if not kincal.is_file():
        sys.exit(f"refresh_doc_outputs: {kincal}: no such program; build kincal first")
    bin_dir = Path(tempfile.mkdtemp(prefix="kincal-doc-bin-"))
    (bin_dir / "kincal").symlink_to(kincal)
    if args.pages:
        pages = [ROOT / p if p == "README.md" else DOCS / p for p in args.pages]
    else:
        pages = [ROOT / "README.md"] + sorted(DOCS.glob("*.md"))
    stale, broken = [], []
    for page in pages:
        where = page.relative_to(ROOT)
        lines = page.read_text().split("\n")
        blocks = parse_page(lines)
        abridged_blocks = [b for b in blocks if b.abridge]
        # docs/x.md's are x-1.txt, x-2.txt...; README.md's (two READMEs) top-README-1.txt...
        key = page.stem if page.parent == DOCS else "top-" + page.stem
        for n, block in enumerate(abridged_blocks, 1):
            block.transcript = TRANSCRIPTS / f"{key}-{n}.txt"
        # A transcript file of this page that no block writes any more.
        for path in sorted(TRANSCRIPTS.glob(f"{key}-[0-9]*.txt")):
            if path not in [b.transcript for b in abridged_blocks]:
                stale.append(f"{path.relative_to(ROOT)}: no block of {where} writes it")
                if not args.check:
                    path.unlink()
        if not blocks:
            continue
        for block in blocks:
            if block.skip:
                print(f"{where}:{block.start + 1}: not run: {block.skip}")
        with tempfile.TemporaryDirectory(prefix="kincal-doc-") as workdir:
            outputs = iter(run_session(blocks, bin_dir, kincal.parent.parent, Path(workdir)))
            new_lines = list(lines)
            replaced = []
            for block in blocks:
                if block.skip:
                    continue
                full = [next(outputs) for _ in block.commands]
                for command, out in zip(block.commands, full):
                    errors = [line for line in out if ERROR_LINE.match(line)]
                    if errors and not block.shows_error:
                        broken.append(f"{where}:{block.start + 2}: '$ {command[0][:60]}' prints "
                                      f"an error ({errors[0][:100]}); expected what the page "
                                      "describes, or a block marked "
                                      "<!-- doc-outputs: shows-error --> if it means the error")
                link = None
                if block.abridge:
                    name = os.path.relpath(block.transcript, page.parent)
                    link = f"{FULL_OUTPUT}[{name}]({name})</sub>"
                    shown = [abridged(out, block.abridge, name) for out in full]
                    kept = read_transcript(block.transcript) if block.transcript.exists() else []
                    if len(kept) != len(full):
                        stale.append(f"{block.transcript.relative_to(ROOT)}: not the full "
                                     f"output of {where}:{block.start + 1}")
                    for command, old, new in zip(block.commands, kept, full):
                        if mask("\n".join(new)) != mask("\n".join(old)):
                            stale.append(f"{block.transcript.relative_to(ROOT)}: '$ "
                                         f"{command[0][:60]}' prints something else now")
                    text = transcript_text(where, block.commands, full)
                    if not args.check and (not block.transcript.exists()
                                           or block.transcript.read_text() != text):
                        TRANSCRIPTS.mkdir(parents=True, exist_ok=True)
                        block.transcript.write_text(text)
                else:
                    shown = full
                body = []
                for command, old, out in zip(block.commands, block.outputs, shown):
                    body += ["$ " + command[0]] + command[1:] + out
                    if mask("\n".join(out)) != mask("\n".join(old)):
                        stale.append(f"{where}:{block.start + 2}: "
                                     f"'$ {command[0][:60]}' prints something else now")
                after = block.end + 1
                present = new_lines[after] if after < len(new_lines) else ""
                if (link or "") != (present if present.startswith(FULL_OUTPUT) else ""):
                    stale.append(f"{where}:{after + 1}: the link to the full output "
                                 + ("is missing or wrong" if link else "is left over"))
                replaced.append((block, body, link))
            # From the last block up, so that earlier line numbers stay valid.
            for block, body, link in reversed(replaced):
                after = block.end + 1
                if after < len(new_lines) and new_lines[after].startswith(FULL_OUTPUT):
                    del new_lines[after]
                if link:
                    new_lines.insert(after, link)
                new_lines[block.start + 1:block.end] = body
            shot = SCREENSHOTS.get(page.name)
            if shot:
                html = Path(workdir) / shot[0]
                image = DOCS / "generated" / "img" / shot[1]
                source = image.with_name(image.name + ".source")
                digest = hashlib.sha256(mask(html.read_text()).encode()).hexdigest()
                recorded = source.read_text().strip() if source.exists() else ""
                if digest != recorded:
                    stale.append(f"{image.relative_to(ROOT)}: taken from another report page")
                    if not args.check:
                        screenshot(html, image)
                        source.write_text(digest + "\n")
        if not args.check and new_lines != lines:
            page.write_text("\n".join(new_lines))
    shutil.rmtree(bin_dir)
    if broken:
        print("\n".join(broken))
        print(f"refresh_doc_outputs: {len(broken)} documented command(s) fail where the page "
              "does not say they should")
        return 1
    if args.check and stale:
        print("\n".join(stale))
        print(f"refresh_doc_outputs: {len(stale)} output(s) in docs/ differ from what the "
              "commands print now; run scripts/refresh_doc_outputs.py and review the diff")
        return 1
    print("refresh_doc_outputs: " + ("every doc output is current" if args.check else
                                     f"refreshed ({len(stale)} output(s) changed)"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
