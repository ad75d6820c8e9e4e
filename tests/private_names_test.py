#!/usr/bin/env python3
"""private_names_test.py — ctest private_names: a source file's private names
follow the house rule (common/README.md, "Rules of the house"):

  - a file's static functions and constant tables have bare names: no public
    prefix (ras_, cv_bridge_, fast_, hw1_ ... hw9_), so a prefix always says
    the name is in a header;
  - its mutable file-scope state (a static variable that changes at run
    time: a counter, a cache, a once-flag, a pointer set later) is g_<name>,
    and nothing else is: such state is shared by every function of the file
    (threads, signal handlers), and g_ keeps it apart from the locals of the
    same meaning (limit, g_limit).

Checked in the .c, .cpp and .c.in files of common/, fast/, the assignments
(hw*/, their solution/ and tools/) and examples/, but not in the files the
students write (an assignment's STUDENT sources that are not also its
REFERENCE ones, read from its CMakeLists.txt: transform.c, rasterizer.c,
shading.c): their private names are the student's to choose, and the
handout's `make test` runs this test. Headers are not checked: their static
inline functions are public and carry their module's prefix (or, in a
student header, the course's bare names).

    tests/private_names_test.py SOURCE_DIR

Prints each offending definition as FILE:LINE: NAME — what the rule wants;
exit 0 when all hold, 1 when one does not, 2 on bad arguments.
"""
import os
import re
import sys

TOPS = ("common", "fast", "examples")
PUBLIC = re.compile(r"^(ras_|cv_bridge_|fast_|hw[0-9]_)")
COMMENT_OR_LITERAL = re.compile(r"/\*.*?\*/|//[^\n]*|\"(?:\\.|[^\"\\\n])*\"|'(?:\\.|[^'\\\n])*'", re.S)
PREPROCESSOR = re.compile(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", re.M)


def student_files(root, assignment):
    """The sources only the student's build compiles (STUDENT minus REFERENCE)."""
    try:
        with open(os.path.join(root, assignment, "CMakeLists.txt"), encoding="utf-8") as f:
            text = f.read()
    except OSError:
        return set()
    lists = {}
    for m in re.finditer(r"raster101_assignment\((.*?)\)", text, re.S):
        words = m.group(1).split()
        key = None
        for w in words:
            if w in ("STUDENT", "REFERENCE", "PROGRAM", "DEPENDS"):
                key = w
            elif key:
                lists.setdefault(key, set()).add(w)
    return {os.path.join(assignment, x) for x in lists.get("STUDENT", set()) - lists.get("REFERENCE", set())}


def sources(root):
    assignments = sorted(d for d in os.listdir(root) if re.match(r"hw\d", d))
    skip = set().union(*(student_files(root, a) for a in assignments))
    for top in list(TOPS) + assignments:
        for d, dirs, names in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(x for x in dirs if not x.startswith(("build", ".")))
            for n in sorted(names):
                rel = os.path.relpath(os.path.join(d, n), root)
                if n.endswith((".c", ".cpp", ".c.in")) and rel not in skip:
                    yield rel


def blank(m):
    """The match with everything but its newlines as spaces (lines keep their numbers)."""
    return re.sub(r"[^\n]", " ", m.group())


def top_level_statics(text):
    """(line, declaration head) of every file-scope declaration starting with static."""
    text = PREPROCESSOR.sub(blank, COMMENT_OR_LITERAL.sub(blank, text))
    found, depth, start, keep = [], 0, 0, None
    for i, ch in enumerate(text):
        if ch == "{":
            if depth == 0:
                head = text[start:i]
                # static struct { ... } name; : the name comes after the braces
                struct = re.search(r"\b(struct|union|enum)(\s+\w+)?\s*$", head)
                keep = (start, head) if struct else None
                found.append((start, head))
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                start = i + 1
                if keep is not None:
                    found.pop()
        elif ch == ";" and depth == 0:
            head = text[start:i]
            if keep is not None:
                (start, head), keep = (keep[0], keep[1] + " " + head), None
            found.append((start, head))
            start = i + 1
    for pos, head in found:
        stripped = head.lstrip()
        if not stripped.startswith("static"):
            continue
        line = text.count("\n", 0, pos + len(head) - len(stripped)) + 1
        yield line, " ".join(stripped.split())


def classify(head):
    """(name, kind) of a static declaration: kind is function, constant or state."""
    pointer_to_function = re.search(r"\(\s*\*\s*(const\s+)?(\w+)\s*\)\s*\(", head)
    if pointer_to_function:
        return pointer_to_function.group(2), "constant" if pointer_to_function.group(1) else "state"
    decl = head.split("=")[0].strip()
    function = re.match(r"[^(]*?(\w+)\s*\(", decl)
    if function and "(" in decl:
        return function.group(1), "function"
    m = re.search(r"(\w+)\s*(\[[^\]]*\]\s*)*$", decl)
    if not m:
        return None, None
    name = m.group(1)
    before = decl[: m.start()]
    if "*" in before:
        constant = re.search(r"\*\s*const\s*$", before) is not None
    else:
        constant = re.search(r"\bconst\b", before) is not None
    return name, "constant" if constant else "state"


def main():
    if len(sys.argv) != 2 or not os.path.isdir(sys.argv[1]):
        print("usage: private_names_test.py SOURCE_DIR", file=sys.stderr)
        return 2
    root = os.path.abspath(sys.argv[1])
    bad, count = [], 0
    for rel in sources(root):
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for line, head in top_level_statics(text):
            name, kind = classify(head)
            if not name:
                continue
            count += 1
            where = f"{rel}:{line}: {name}"
            if PUBLIC.match(name):
                bad.append(f"{where} — a private {kind} with a public prefix: give it a bare name")
            elif kind == "state" and not name.startswith("g_"):
                bad.append(f"{where} — mutable file-scope state: expected g_{name}")
            elif kind != "state" and name.startswith("g_"):
                bad.append(f"{where} — a {kind}, not mutable state: expected a bare name, not g_")
    for line in bad:
        print(line)
    print(f"private_names: {count} private names; {len(bad)} break the rule")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
