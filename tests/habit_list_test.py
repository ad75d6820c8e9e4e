#!/usr/bin/env python3
"""habit_list_test.py — ctest habit_list: the one list of course habits holds.

    tests/habit_list_test.py SOURCE_DIR [--pitfalls FILE]
    tests/habit_list_test.py SOURCE_DIR --self-test   (ctest habit_list_catches)

docs/pitfalls.md, "Coming from the GAMES101 framework", lists the habits of
the GAMES101 course's C++ framework that are wrong here, each with its
assignment, the test that names it, the advice that undoes it (with a link
into a handout) and the grader's words (in double quotes; "…" stands for text
left out). Below it a second table lists advice that no message may give,
because the handout's own code already follows it. This checks, for each
habit row:
  1. its test exists in tests/unit/test_hwN.c (N: the row's assignment) and
     is registered there (cmocka_unit_test(NAME));
  2. each piece of its quoted words (split at "…") appears in that test's
     messages: the C string literals (adjacent ones joined) of the test's
     body and of the functions and macros of the same file it uses, however
     deep;
  3. its advice links to a handout file that exists, at a heading that exists
     (GitHub's anchors);
and, for each row of the second table, that no string literal of
tests/unit/test_hwN.c contains the advice (case aside).

Prints each broken row as "pitfalls.md: habit 'X': what is wrong, what to do";
exit 0 when the list holds, 1 when it does not, 2 on bad arguments or when
the tables cannot be found (a table that cannot be read checks nothing).
"""
import os
import re
import sys

HEADING = "## Coming from the GAMES101 framework"
HABIT_COLUMNS = ["habit", "assignment", "the test", "undo it:", "the grader's words"]
ADVICE_COLUMNS = ["advice", "assignment", "why no message gives it"]
MIN_PIECE = 4  # shorter pieces of quoted words ("(", "x") say nothing


def fail(msg):
    print(msg)
    return 1


def section(text):
    """The lines of the habits section, or None."""
    lines = text.split("\n")
    try:
        start = lines.index(HEADING)
    except ValueError:
        return None
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    return lines[start + 1:end]


def cells(line):
    """A Markdown table row's cells (a '|' inside backticks is no border)."""
    out, cur, code = [], "", False
    for ch in line.strip()[1:]:
        if ch == "`":
            code = not code
        if ch == "|" and not code:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    return out


def tables(lines):
    """Every table of the section: (header cells, [row cells...])."""
    found, i = [], 0
    while i < len(lines):
        if lines[i].startswith("|") and i + 1 < len(lines) and lines[i + 1].startswith("|---"):
            head, rows, i = cells(lines[i]), [], i + 2
            while i < len(lines) and lines[i].startswith("|"):
                rows.append(cells(lines[i]))
                i += 1
            found.append((head, rows))
        else:
            i += 1
    return found


def slug(heading):
    """GitHub's anchor of a Markdown heading."""
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)  # \w keeps letters, digits and _
    return s.replace(" ", "-")


def anchors(path):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    text = re.sub(r"```.*?```", "", text, flags=re.S)  # a '#' in a code block is no heading
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6}\s+(.*)$", text, flags=re.M)}


LITERAL = re.compile(r'"((?:[^"\\\n]|\\.)*)"')


def strip_comments(src):
    """C source without comments (string literals kept whole)."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("/*", i):
            j = src.find("*/", i + 2)
            i = n if j < 0 else j + 2
            out.append(" ")
        elif src.startswith("//", i):
            j = src.find("\n", i)
            i = n if j < 0 else j
        elif src[i] == '"' or src[i] == "'":
            q, j = src[i], i + 1
            while j < n and src[j] != q:
                j += 2 if src[j] == "\\" else 1
            out.append(src[i:j + 1])
            i = j + 1
        else:
            out.append(src[i])
            i += 1
    return "".join(out)


def joined_literals(code):
    """The text of the string literals of `code`, adjacent ones joined into
    one (as the compiler does), one message per line."""
    out, last_end = [], None
    for m in LITERAL.finditer(code):
        text = m.group(1).replace('\\"', '"').replace("\\n", " ")
        if last_end is not None and code[last_end:m.start()].strip() == "":
            out[-1] += text
        else:
            out.append(text)
        last_end = m.end()
    return out


def definitions(code):
    """Top-level functions and macros of a C file: name -> their text."""
    defs = {}
    for m in re.finditer(r"^#\s*define\s+(\w+)((?:.*\\\n)*.*)$", code, flags=re.M):
        defs[m.group(1)] = m.group(2)
    for m in re.finditer(r"^[A-Za-z_][\w \t\*]*?\b(\w+)\s*\([^;{]*\)\s*\{", code, flags=re.M):
        depth, j = 1, m.end()
        while j < len(code) and depth:
            depth += {"{": 1, "}": -1}.get(code[j], 0)
            j += 1
        defs.setdefault(m.group(1), code[m.start():j])
    # file-scope tables and strings (static const char *const hints[] = {...};)
    # (the second form: a table of an anonymous struct, `} name[] = {`)
    for m in re.finditer(r"^(?:(?:static\s+)?(?:const\s+)?\w[\w \t\*]*?|\}\s*)\b(\w+)\s*(?:\[[^\]]*\])*\s*=",
                         code, flags=re.M):
        end = code.find(";\n", m.end())
        defs.setdefault(m.group(1), code[m.start():end if end >= 0 else len(code)])
    return defs


def test_messages(code, defs, test):
    """The string literals a test can print: its body's and those of every
    function or macro of the file it uses, however deep."""
    seen, todo, texts = set(), [test], []
    while todo:
        name = todo.pop()
        if name in seen or name not in defs:
            continue
        seen.add(name)
        body = defs[name]
        texts += joined_literals(body)
        todo += [w for w in set(re.findall(r"\b[A-Za-z_]\w*\b", LITERAL.sub('""', body)))
                 if w in defs and w not in seen]
    return texts


def quoted_pieces(words):
    """The quoted words of a cell, split at "…", trimmed, long enough."""
    pieces = []
    for q in re.findall(r'"([^"]*)"', words):
        pieces += [p.strip() for p in q.split("…") if len(p.strip()) >= MIN_PIECE]
    return pieces


def check_habit(row, src, docs, test_files):
    habit, hw, test_cell, advice, words = row[:5]
    where = f"pitfalls.md: habit '{habit}'"
    bad = 0
    m = re.fullmatch(r"hw(\d+)", hw)
    path = os.path.join(src, "tests", "unit", f"test_{hw}.c")
    if not m or not os.path.exists(path):
        return fail(f"{where}: assignment '{hw}' has no tests/unit/test_{hw}.c; write hw1, hw2 or hw3")
    test = test_cell.strip("` ")
    code, defs = test_files[hw]
    if not re.fullmatch(r"test_\w+", test):
        return fail(f"{where}: the test column holds '{test_cell}', expected one `test_...` name")
    if test not in defs or not re.search(r"cmocka_unit_test\(\s*" + test + r"\s*\)", code):
        return fail(f"{where}: expected a test {test} in tests/unit/test_{hw}.c (defined and "
                    f"listed in cmocka_unit_test), found none: rename the row's test, or the "
                    f"habit is no longer named by any test")
    pieces = quoted_pieces(words)
    if not pieces:
        bad |= fail(f"{where}: no quoted words in '{words}': quote what the test's message "
                    f"says, in double quotes")
    messages = test_messages(code, defs, test)
    for p in pieces:
        if not any(p in msg for msg in messages):
            bad |= fail(f"{where}: expected the words \"{p}\" in a message of {test} (its "
                        f"string literals and those of the functions and macros it uses), found "
                        f"none: quote the message as it is, or name the habit in it")
    links = re.findall(r"\]\(([^)\s]+)\)", advice)
    if not links:
        bad |= fail(f"{where}: the advice has no link into a handout: add ([hwN](hwN.md#section))")
    for link in links:
        file, _, anchor = link.partition("#")
        target = os.path.normpath(os.path.join(docs, file))
        if not os.path.exists(target):
            bad |= fail(f"{where}: the advice links to {link}, but docs/{file} does not exist")
        elif anchor and anchor not in anchors(target):
            bad |= fail(f"{where}: the advice links to {link}, but docs/{file} has no heading "
                        f"with the anchor #{anchor}: link a heading it has")
    return bad


def check_advice(row, test_files):
    advice, hw = row[0], row[1]
    bad = 0
    for said in re.findall(r'"([^"]+)"', advice):
        if hw not in test_files:
            return fail(f"pitfalls.md: advice \"{said}\": assignment '{hw}' has no test file")
        code, defs = test_files[hw]
        for name, body in defs.items():
            if not name.startswith("test_") and name not in code:
                continue
            for msg in joined_literals(body):
                if said.lower() in msg.lower():
                    bad |= fail(f"tests/unit/test_{hw}.c: {name}: a message says \"{said}\", "
                                f"advice the handout already follows (pitfalls.md's second "
                                f"table): name the mistake the student's code shows instead "
                                f"(message: \"{msg[:160]}…\")")
                    break
    return bad


def self_test(src):
    """The check catches what it is for: three copies of the table, each
    broken one way (a test renamed, words no message says, a link to no
    heading), must each fail. Returns 0 when all three are caught."""
    import subprocess
    import tempfile
    with open(os.path.join(src, "docs", "pitfalls.md"), encoding="utf-8") as f:
        text = f.read()
    # what to break, how, and the words the new failure must name
    breaks = {
        "a test that does not exist": ("`test_raster_depth_test_order`",
                                       "`test_raster_depth_test_order_gone`", "order_gone"),
        "words no message says": ("`z_interpolated *= w_reciprocal` snippet",
                                  "`z_interpolated /= w_reciprocal` snippet", "/= w_reciprocal"),
        "a link to no heading": ("(hw3.md#coming-from-the-games101-framework)",
                                 "(hw3.md#coming-from-the-games-framework)", "games-framework"),
    }
    run = [sys.executable, __file__, src, "--pitfalls"]
    # failures of the table as it is (a habit another change is still to
    # name) are not the broken copy's: only a new failure counts
    baseline = set(subprocess.run(run + [os.path.join(src, "docs", "pitfalls.md")],
                                  capture_output=True, text=True).stdout.splitlines())
    bad = 0
    for what, (old, new, token) in breaks.items():
        if old not in text:
            bad |= fail(f"self-test: cannot break the table with {what}: '{old}' is not in it")
            continue
        with tempfile.NamedTemporaryFile("w", suffix=".md", dir=os.path.join(src, "docs"),
                                         delete=False, encoding="utf-8") as f:
            f.write(text.replace(old, new, 1))
        try:
            r = subprocess.run(run + [f.name], capture_output=True, text=True)
        finally:
            os.unlink(f.name)
        caught = r.returncode == 1 and any(
            token in line and line not in baseline for line in r.stdout.splitlines())
        print(f"self-test: a table with {what}: {'caught' if caught else 'NOT caught'}")
        if not caught:
            bad |= fail(f"self-test: expected exit 1 naming '{new}', got exit {r.returncode}:\n"
                        f"{r.stdout}")
    return bad


def main(argv):
    if len(argv) == 3 and argv[2] == "--self-test" and os.path.isdir(argv[1]):
        return self_test(argv[1])
    if len(argv) < 2 or not os.path.isdir(argv[1]):
        print(__doc__.split("\n\n")[1])
        return 2
    src = argv[1]
    pitfalls = os.path.join(src, "docs", "pitfalls.md")
    if len(argv) == 4 and argv[2] == "--pitfalls":
        pitfalls = argv[3]
    with open(pitfalls, encoding="utf-8") as f:
        lines = section(f.read())
    if lines is None:
        print(f"{pitfalls}: no '{HEADING}' section: the habit list is gone (exit 2)")
        return 2
    found = tables(lines)
    habits = [rows for head, rows in found if [h.lower() for h in head] == HABIT_COLUMNS]
    advice = [rows for head, rows in found if [h.lower() for h in head] == ADVICE_COLUMNS]
    if len(habits) != 1 or len(advice) != 1 or not habits[0]:
        print(f"{pitfalls}: expected in '{HEADING}' one table with the columns "
              f"{' | '.join(HABIT_COLUMNS)} and one with {' | '.join(ADVICE_COLUMNS)}, found "
              f"{[h for h, _ in found]} (exit 2)")
        return 2
    test_files = {}
    for hw in ("hw1", "hw2", "hw3"):
        path = os.path.join(src, "tests", "unit", f"test_{hw}.c")
        if os.path.exists(path):
            with open(path, encoding="utf-8") as f:
                code = strip_comments(f.read())
            test_files[hw] = (code, definitions(code))
    bad = 0
    for row in habits[0]:
        if len(row) < 5:
            bad |= fail(f"pitfalls.md: the habit row {row} has {len(row)} cells, expected 5")
            continue
        bad |= check_habit(row, src, os.path.join(src, "docs"), test_files)
    for row in advice[0]:
        bad |= check_advice(row, test_files)
    print(f"habit_list: {len(habits[0])} habits, {len(advice[0])} advice rows checked: "
          f"{'FAILED' if bad else 'all hold'}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
