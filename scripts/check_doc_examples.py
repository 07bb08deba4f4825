#!/usr/bin/env python3
"""Runs the command examples of README.md, CONTRIBUTING.md and docs/*.md, so the documentation stays true.

Every line of a code block (indented by four spaces, or fenced with ``` and no language or
sh/bash/console/shell) that starts with `steradian` or `build/release/steradian` is a
command example and is executed, with the binary given on the command line, on the bundled
scenes, at low cost: a render gets `--spp 1` (its --spp value replaced), a measure
`--rel-error 0.2` (its --rel-error value replaced). Synopses, which name placeholders such as
SCENE.pbrt, go in blocks fenced as ```text and are not run. Commands run in a scratch
directory where scenes/, tests/ and docs/ of the repository are reachable by the same
relative paths, so an example's outputs (out/cb.png, ...) land there, not in the tree.

Usage: scripts/check_doc_examples.py STERADIAN_BINARY [REPO_ROOT]
Exit status 1 if any example fails (its output is printed) or if no example was found.
"""
import os
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile

binary = pathlib.Path(sys.argv[1]).resolve()
root = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else pathlib.Path(__file__).parent.parent)
root = root.resolve()
docs = [root / "README.md", root / "CONTRIBUTING.md"] + sorted((root / "docs").glob("*.md"))
runnable_fences = {"", "sh", "bash", "console", "shell"}


def code_lines(path):
    """(line number, text) of every line inside a runnable code block of a Markdown file."""
    fence = None  # language of the open fence, or None outside one
    prev_blank = True
    in_indented = False
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        stripped = line.strip()
        if fence is not None:
            if stripped.startswith("```"):
                fence = None
            elif fence in runnable_fences:
                yield n, stripped
            continue
        if stripped.startswith("```"):
            fence = stripped[3:].strip().lower()
            in_indented = False
            continue
        if line.startswith("    ") and (prev_blank or in_indented) and not re.match(r"\s*([-*]|\d+\.)\s", line):
            in_indented = True
            yield n, stripped
        elif stripped:
            in_indented = False
        prev_blank = not stripped


def examples(path):
    pending = None
    for n, text in code_lines(path):
        if pending is not None:
            pending = (pending[0], pending[1] + " " + text.rstrip("\\").strip())
            if not text.endswith("\\"):
                yield pending
                pending = None
            continue
        if re.match(r"(build/release/)?steradian(\s|$)", text):
            if text.endswith("\\"):
                pending = (n, text.rstrip("\\").strip())
            else:
                yield n, text


def cheap(argv):
    """The example's arguments with its sample count or error target made cheap."""
    argv = [a for a in argv]
    sub = argv[1] if len(argv) > 1 else ""

    def force(flag, value):
        if flag in argv:
            argv[argv.index(flag) + 1] = value
        else:
            argv.extend([flag, value])

    if sub == "render":
        force("--spp", "1")
    elif sub == "measure":
        force("--rel-error", "0.2")
    return argv


failures = 0
count = 0
with tempfile.TemporaryDirectory() as tmp:
    for name in ("scenes", "tests", "docs"):
        os.symlink(root / name, pathlib.Path(tmp) / name)
    os.makedirs(pathlib.Path(tmp) / "out")
    for doc in docs:
        for n, text in examples(doc):
            command = text.split(" #", 1)[0].strip()  # a trailing shell comment
            argv = shlex.split(command)
            argv[0] = str(binary)
            argv = cheap(argv)
            count += 1
            where = f"{doc.relative_to(root)}:{n}"
            r = subprocess.run(argv, cwd=tmp, capture_output=True, text=True, timeout=600)
            if r.returncode != 0:
                failures += 1
                print(f"FAILED {where}: {command}\n  ran: {shlex.join(argv)}\n  exit {r.returncode}")
                print("  " + (r.stdout + r.stderr).strip().replace("\n", "\n  "))
            else:
                print(f"ok     {where}: {command}")

print(f"{count - failures} passed, {failures} failed")
if count == 0:
    sys.exit("check_doc_examples: no examples found")
sys.exit(1 if failures else 0)
