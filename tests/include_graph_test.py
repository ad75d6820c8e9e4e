#!/usr/bin/env python3
"""include_graph_test.py — ctest include_graph: the include rules of the tree.

    tests/include_graph_test.py SOURCE_DIR

1. No student-visible file includes from solution/ or fast/. Student-visible:
   every .c/.h under an assignment folder (hw*/) outside its solution/
   folder, i.e. what the handout ships of it. An include is from solution/
   or fast/ (the fast renderer, top-level, solution code) when its path goes
   through such a folder ("solution/shading.c", "../fast/fast_render.h") or
   when its file exists only there (`#include "fast_render.h"` found through
   an include directory the build adds).
2. Nothing in common/ includes from an assignment or from tests/: the core is
   the "GPU" the assignments plug into, and it is built and shipped alone. An
   include of common/ must name a file of common/ (or a system header, <...>).
3. Within common/, the layers go one way (common/README.md): base → io →
   pipeline → scene → app. A file includes headers of its own layer or of the
   layers before it, never after: the stages do not know the scene files or
   the program shell, the file and image code does not know the stages.

Prints each offending line as FILE:LINE: #include "..." — the rule it breaks;
exit 0 when the graph holds, 1 when it does not, 2 on bad arguments.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
SOURCES = (".c", ".h", ".cpp")


def files_under(root, top):
    for d, dirs, names in os.walk(os.path.join(root, top)):
        dirs[:] = sorted(x for x in dirs if not x.startswith("build"))
        for n in sorted(names):
            if n.endswith(SOURCES):
                yield os.path.relpath(os.path.join(d, n), root)


def includes(root, rel):
    with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
        for no, line in enumerate(f, 1):
            m = INCLUDE.match(line)
            if m:
                yield no, m.group(1)


def hidden(rel):
    """True for a file in an assignment's solution/ folder or in fast/."""
    parts = rel.split(os.sep)
    if len(parts) > 1 and parts[0] == "fast":
        return True
    return len(parts) > 2 and parts[0].startswith("hw") and parts[1] == "solution"


LAYERS = ("base", "io", "pipeline", "scene", "app")


def layer_of(rel):
    """The layer of a file under common/ (its folder), or None."""
    parts = rel.split(os.sep)
    return parts[1] if len(parts) > 2 and parts[0] == "common" and parts[1] in LAYERS else None


def main():
    if len(sys.argv) != 2 or not os.path.isdir(sys.argv[1]):
        print("usage: include_graph_test.py SOURCE_DIR", file=sys.stderr)
        return 2
    root = os.path.abspath(sys.argv[1])
    hw_dirs = sorted(d for d in os.listdir(root) if d.startswith("hw") and os.path.isdir(os.path.join(root, d)))
    hw_files = [f for d in hw_dirs for f in files_under(root, d)]
    common_files = list(files_under(root, "common"))
    # Names a build could find through an include directory: those that exist
    # only in solution/ or fast/ are hidden names.
    visible_names = {os.path.basename(f) for f in hw_files + common_files if not hidden(f)}
    fast_files = list(files_under(root, "fast")) if os.path.isdir(os.path.join(root, "fast")) else []
    hidden_names = {os.path.basename(f) for f in hw_files + fast_files if hidden(f)} - visible_names
    common_names = {os.path.basename(f) for f in common_files}
    layer_by_name = {os.path.basename(f): layer_of(f) for f in common_files}

    bad = []
    checked = 0
    for rel in hw_files:
        if hidden(rel):
            continue
        for no, inc in includes(root, rel):
            checked += 1
            target = os.path.normpath(os.path.join(os.path.dirname(rel), inc))
            through = {"solution", "fast"} & set(inc.split("/"))
            if through or hidden(target) or os.path.basename(inc) in hidden_names:
                bad.append(f'{rel}:{no}: #include "{inc}" — a student-visible file includes from '
                           f'{"/".join(sorted(through)) or "solution/ or fast/"} (the handout has neither)')
    for rel in common_files:
        for no, inc in includes(root, rel):
            checked += 1
            target = os.path.normpath(os.path.join(os.path.dirname(rel), inc))
            if not target.startswith("common" + os.sep) or os.path.basename(inc) not in common_names:
                bad.append(f'{rel}:{no}: #include "{inc}" — common/ includes a file that is not in '
                           f'common/ (an assignment\'s or tests/\'s): the core names no assignment')
                continue
            mine, theirs = layer_of(rel), layer_by_name.get(os.path.basename(inc))
            if mine is None:
                bad.append(f'{rel}: a file of common/ outside its layers ({", ".join(LAYERS)})')
            elif theirs is not None and LAYERS.index(theirs) > LAYERS.index(mine):
                bad.append(f'{rel}:{no}: #include "{inc}" — {mine}/ includes from {theirs}/, a later '
                           f'layer (common/README.md: {" → ".join(LAYERS)})')
    for line in bad:
        print(line)
    print(f"include_graph: {checked} includes in {len(hw_files)} assignment and {len(common_files)} "
          f"common files; {len(bad)} break the rules")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
