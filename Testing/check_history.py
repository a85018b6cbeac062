#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks that code comments and reference pages say how things are, not how they came to be
(ctest Core.no_history):

- comments and docstrings in Filters/ and Wrapping/ (.h, .cxx, .py) cite no issue numbers, seeds
  of past runs, generated case names (random_04), sessions or dates;
- the reference pages (README.md, docs/*.md; not docs/journal/) carry no dates, sessions or
  branch names.

A date in the name of a journal file (docs/journal/2026-12-02-slips.md, a link's text or target)
is a pointer to the history, not history, and is allowed.

    python3 Testing/check_history.py [SOURCE_ROOT]

Prints each finding (file, line, text) and exits 1 if there is one. It first checks itself on
made-up lines (self_test), so a pattern that matches nothing fails.
"""
import os
import re
import sys

DATE = r"\b20\d\d-[01]\d-[0-3]\d\b"
JOURNAL_PATH = re.compile(r"(?:journal/)?20\d\d-[01]\d-[0-3]\d-[\w.-]+\.md")
CODE_HISTORY = re.compile(
    r"\bissue[ -]?#?\d+|\bissues? \d+(?:, \d+)*\b|\bseeds? \d+\b|\brandom_\d\d\b|\bsession\b|" + DATE, re.I)
DOC_HISTORY = re.compile(r"\bsessions?\b|\bbranch `|" + DATE, re.I)


def comment_text(path, line):
    """The comment part of a source line ('' when it has none): after // or # (outside strings,
    roughly), or the whole line inside a block comment or docstring (the caller tracks those)."""
    marker = "#" if path.endswith(".py") else "//"
    in_string = None
    for i, c in enumerate(line):
        if in_string:
            if c == in_string and line[i - 1] != "\\":
                in_string = None
        elif c in "\"'":
            in_string = c
        elif line.startswith(marker, i):
            return line[i:]
    return ""


def source_findings(path, lines):
    found = []
    block = False  # inside /* */ or a Python docstring
    for number, line in enumerate(lines, 1):
        text = ""
        if path.endswith(".py"):
            quotes = line.count('"""') + line.count("'''")
            if block or quotes:
                text = line
            if quotes % 2 == 1:
                block = not block
            text = text or comment_text(path, line)
        else:
            if block or "/*" in line:
                text = line
                block = "*/" not in line.split("/*")[-1] if "/*" in line else "*/" not in line
            text = text or comment_text(path, line)
        text = JOURNAL_PATH.sub("journal/…", text)
        m = CODE_HISTORY.search(text)
        if m:
            found.append((number, m.group(0), line.strip()))
    return found


def doc_findings(lines):
    found = []
    for number, line in enumerate(lines, 1):
        m = DOC_HISTORY.search(JOURNAL_PATH.sub("journal/…", line))
        if m:
            found.append((number, m.group(0), line.strip()))
    return found


def check(root):
    problems = []
    for top in ("Filters", "Wrapping"):
        for folder, _, names in sorted(os.walk(os.path.join(root, top))):
            for name in sorted(names):
                if not name.endswith((".h", ".cxx", ".py")):
                    continue
                path = os.path.join(folder, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    lines = f.read().split("\n")
                for number, what, line in source_findings(path, lines):
                    problems.append(f"{os.path.relpath(path, root)}:{number}: \"{what}\" in a comment: {line[:100]}")
    docs = [os.path.join(root, "README.md")]
    docs += sorted(os.path.join(root, "docs", n) for n in os.listdir(os.path.join(root, "docs")) if n.endswith(".md"))
    for path in docs:
        with open(path, encoding="utf-8") as f:
            for number, what, line in doc_findings(f.read().split("\n")):
                problems.append(f"{os.path.relpath(path, root)}:{number}: \"{what}\" in a reference page: {line[:100]}")
    return problems


def self_test():
    """Made-up lines: each history kind is found, the allowed ones are not."""
    cxx = ["int seed = 7; // as in issue 13", "/// seed 61 at radius-edge 1.3 ran away",
           "// figures in docs/journal/2026-12-02-slips.md", "const char* s = \"issue 5\"; // a string",
           "/* measured 2026-12-01", "   on random_05 */", "x = options.seed; // the seed gives the same mesh"]
    py = ['def f():', '    """Measured in session 12."""', "    return 1  # see journal/2026-12-01-x.md"]
    docs = ["Measured 2026-12-01.", "See [the journal](journal/2026-12-01-feature-line-studies.md).",
            "Tried on branch `corner`."]
    got_cxx = [n for n, _, _ in source_findings("a.cxx", cxx)]
    got_py = [n for n, _, _ in source_findings("a.py", py)]
    got_docs = [n for n, _, _ in doc_findings(docs)]
    ok = got_cxx == [1, 2, 5, 6] and got_py == [2] and got_docs == [1, 3]
    if not ok:
        print("self-test failed:", got_cxx, got_py, got_docs)
    return ok


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    if not self_test():
        return 1
    problems = check(root)
    for p in problems:
        print(p)
    print(f"{len(problems)} history finding(s) in comments and reference pages")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
