#!/usr/bin/env python3
"""header_guards_test.py — ctest header_guards: every header of the tree has
the include guard of the house rule (common/README.md, "Rules of the house"):

    #ifndef RAS_<NAME>_H
    #define RAS_<NAME>_H

as its first preprocessor lines, NAME being the file's name without .h and
without a leading ras_, in capitals; outside common/, the short name of its
assignment or folder goes first (hw1_transform: HW1, fast/: FAST,
tests/bench/: BENCH, the assignment template: HWX) unless the name already
begins with it or is a ras_ name (ras_app.h: RAS_APP_H, stage2_clip.h:
RAS_STAGE2_CLIP_H, hw3_shading/scene.h: RAS_HW3_SCENE_H, fast/fast_priv.h:
RAS_FAST_PRIV_H, tests/unit/ras_test_main.h: RAS_TEST_MAIN_H). No two
headers share a guard (two that did would silently hide one another). Headers under build*/ and the attack
catalogue (hostile submissions, tests/grading/attacks/) are not the tree's. A
template, NAME_tmp.h, has no guard by design: it is included once per
variant it generates (fast/fast_rast_tile_tmp.h, as Mesa's lp_rast_tri_tmp.h).

    tests/header_guards_test.py SOURCE_DIR

Prints each offending header with what was expected; exit 0 when all hold,
1 when one does not, 2 on bad arguments.
"""
import os
import re
import sys

DIRECTIVE = re.compile(r"^\s*#\s*(\w+)\s*(\S*)")
GUARD = re.compile(r"^RAS_[A-Z0-9_]+_H$")


def headers(root):
    for d, dirs, names in os.walk(root):
        rel = os.path.relpath(d, root)
        dirs[:] = sorted(x for x in dirs
                         if not x.startswith(("build", ".")) and
                         os.path.join(rel, x) != os.path.join("tests", "grading", "attacks"))
        for n in sorted(names):
            if n.endswith(".h") and not n.endswith("_tmp.h"):
                yield os.path.relpath(os.path.join(d, n), root)


def short_name(rel):
    """The short name of the assignment or folder a header outside common/ is in."""
    parts = rel.split(os.sep)
    if parts[:3] == ["tests", "grading", "assignment-template"]:
        return "hwx"  # the template's placeholder assignment (hwX_template)
    if re.match(r"hw\d+_", parts[0]):
        return parts[0].split("_")[0]  # hw1_transform: hw1
    if parts[0] == "tests" and len(parts) > 2:
        return parts[1]  # tests/bench: bench
    return parts[0]  # fast


def expected_guard(rel):
    stem = os.path.basename(rel)[: -len(".h")]
    name = stem[len("ras_"):] if stem.startswith("ras_") else stem
    if rel.split(os.sep)[0] != "common" and not stem.startswith("ras_"):
        short = short_name(rel)
        if name != short and not name.startswith(short + "_"):
            name = short + "_" + name
    return "RAS_" + re.sub(r"[^A-Za-z0-9]", "_", name).upper() + "_H"


def guard_of(path):
    """The (#ifndef NAME, #define NAME) of the first two directives, or why not."""
    found = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = DIRECTIVE.match(line)
            if m:
                found.append(m.groups())
                if len(found) == 2:
                    break
    if len(found) < 2 or found[0][0] != "ifndef" or found[1][0] != "define" or found[0][1] != found[1][1]:
        return None, "its first two directives are not #ifndef NAME / #define NAME"
    return found[0][1], None


def main():
    if len(sys.argv) != 2 or not os.path.isdir(sys.argv[1]):
        print("usage: header_guards_test.py SOURCE_DIR", file=sys.stderr)
        return 2
    root = os.path.abspath(sys.argv[1])
    bad, seen, count = [], {}, 0
    for rel in headers(root):
        count += 1
        guard, why = guard_of(os.path.join(root, rel))
        if why:
            bad.append(f"{rel}: {why} (expected #ifndef RAS_<NAME>_H first)")
        elif not GUARD.match(guard):
            bad.append(f"{rel}: guard {guard}, expected RAS_<NAME>_H (common/README.md)")
        elif guard != expected_guard(rel):
            bad.append(f"{rel}: guard {guard}, expected {expected_guard(rel)} (common/README.md)")
        elif guard in seen:
            bad.append(f"{rel}: guard {guard} is also {seen[guard]}'s: one of them is hidden")
        else:
            seen[guard] = rel
    for line in bad:
        print(line)
    print(f"header_guards: {count} headers; {len(bad)} break the rule")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
