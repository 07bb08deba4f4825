#!/usr/bin/env python3
"""Checks that the library's folders include each other only as docs/architecture.md says.

The table under the heading "Layers" in docs/architecture.md lists, for every folder of
src/steradian/, the folders its sources may include besides itself. This script reads that
table (so the document and the check cannot disagree) and reports every `#include
"steradian/<folder>/..."` in a non-test source that the table does not allow, every folder
of the library that the table does not list, and every inclusion of Embree outside accel/.
Tests (`*_test.cpp`) may include anything: they sit at the top of the layers.

Usage: scripts/check_layers.py [REPO_ROOT]    (exit status 1 on any violation)
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
doc = root / "docs" / "architecture.md"
lib = root / "src" / "steradian"

# The table: the first Markdown table after a heading line "## ... Layers ...".
allowed = {}
in_section = False
for line in doc.read_text(encoding="utf-8").splitlines():
    if line.startswith("#"):
        in_section = "layers" in line.lower()
        continue
    if not in_section or not line.startswith("|"):
        continue
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) < 2 or set(cells[0]) <= set("-: "):
        continue
    folder = cells[0].strip("`/ ")
    if folder in ("folder", ""):
        continue
    may = re.findall(r"`([a-z_]+)/?`", cells[-1])
    allowed[folder] = set(may)

if not allowed:
    sys.exit(f"check_layers: no Layers table found in {doc}")

problems = []
folders = sorted(p.name for p in lib.iterdir() if p.is_dir())
for f in folders:
    if f not in allowed:
        problems.append(f"src/steradian/{f}/: not in the Layers table of docs/architecture.md")
for f in allowed:
    if f not in folders:
        problems.append(f"docs/architecture.md lists {f}/, which src/steradian/ does not have")

include_re = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]')
for src in sorted(lib.rglob("*")):
    if src.suffix not in (".h", ".cpp") or src.name.endswith("_test.cpp"):
        continue
    folder = src.relative_to(lib).parts[0]
    for n, line in enumerate(src.read_text(encoding="utf-8").splitlines(), 1):
        m = include_re.match(line)
        if not m:
            continue
        inc = m.group(1)
        where = f"{src.relative_to(root)}:{n}"
        if inc.startswith("embree") and folder != "accel":
            problems.append(f"{where}: includes {inc}; only accel/ may include Embree")
        if not inc.startswith("steradian/"):
            continue
        target = inc.split("/")[1]
        if target != folder and target not in allowed.get(folder, set()):
            problems.append(f"{where}: {folder}/ includes {inc}, but docs/architecture.md "
                            f"allows {folder}/ only {sorted(allowed.get(folder, set())) or 'itself'}")

for p in problems:
    print(p)
if problems:
    sys.exit(1)
print(f"check_layers: {len(folders)} folders, every include allowed by docs/architecture.md")
