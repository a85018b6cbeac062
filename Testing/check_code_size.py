#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks that the sources under Filters/ stay readable (ctest Core.code_size):

- no file longer than 900 lines;
- no class longer than 500 lines of code (its body plus the member functions defined outside it);
- no function longer than 80 lines of code (from its opening brace to its closing one, lambdas
  inside it counted with it).

Lines of code are lines with something other than comments and blanks: a header's reference
documentation costs its class nothing.

    python3 Testing/check_code_size.py [SOURCE_ROOT] [--list N]

The C++ is read with a small scanner, not a compiler: comments, strings and preprocessor lines are
blanked, then braces are matched. A block is a function when the text before its brace ends like a
function head (a closing parenthesis, then qualifiers or a trailing return type) and it opens at
namespace or class scope; a class when that text names a class, struct or union. Before the real
check the scanner runs on made-up sources with one function, class and file just over each limit
(self_test), so a scanner that finds nothing fails. `--list N` prints the N longest functions and
classes, for whoever shortens them next.
"""
import os
import re
import sys

MAX_FILE = 900
MAX_CLASS = 500
MAX_FUNCTION = 80

FUNCTION_HEAD = re.compile(
    r"\)\s*(?:const\b|override\b|final\b|noexcept\b(?:\s*\([^()]*\))?|mutable\b|&&|&|\s)*"
    r"(?:->\s*[\w:<>,\s\*&\[\]]+)?$")
CLASS_HEAD = re.compile(r"^.*\b(?:class|struct|union)\s+(?:\w+_EXPORT\s+)?(\w+)[^()]*$")
NAMESPACE_HEAD = re.compile(r"\bnamespace\b[\w:\s]*$|extern\s*$")
FUNCTION_NAME = re.compile(r"([~\w:]+(?:<[^()]*>)?|operator\s*\S+)\s*\($")


def blank(text):
    """The text with comments, string/char literals and preprocessor lines replaced by spaces
    (newlines kept, so line numbers stay)."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            # a preprocessor line, with its continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:end]))
            i = end
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            end = n if end < 0 else end + len(m.group(1)) + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:end]))
            i = end
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # a digit separator: 1'000'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j + 1, n) - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def blocks(path):
    """(kind, name, first line, lines of code, inside a class) of every function and class in the file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = blank(f.read())
    code_lines = {k + 1 for k, text_line in enumerate(text.split("\n")) if text_line.strip()}
    found = []
    stack = []  # (kind, name, line)
    head_start = 0
    line = 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c in ";":
            head_start = i + 1
        elif c == "{":
            head = " ".join(text[head_start:i].split())
            scope = stack[-1][0] if stack else "namespace"
            kind, name = "block", ""
            if scope in ("namespace", "class"):
                if NAMESPACE_HEAD.search(head):
                    kind = "namespace"
                elif (m := CLASS_HEAD.search(head)) and not head.startswith("enum") and " enum " not in head:
                    kind, name = "class", m.group(1)
                elif FUNCTION_HEAD.search(head):
                    kind = "function"
                    # the name is the identifier before the first parenthesis (a constructor's
                    # initialiser list comes after it)
                    before = head[: head.find("(") + 1]
                    m = FUNCTION_NAME.search(before)
                    name = m.group(1) if m else "(lambda)"
                    if scope == "class" and "::" not in name:
                        name = f"{stack[-1][1]}::{name}"
            stack.append((kind, name, line))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, name, first = stack.pop()
                if kind in ("function", "class"):
                    in_class = any(k == "class" for k, _, _ in stack)
                    size = sum(1 for k in range(first, line + 1) if k in code_lines)
                    found.append((kind, name, first, size, in_class))
            head_start = i + 1
    return found


def check(root):
    """Size problems under root/Filters, with every function and class measured."""
    problems, functions = [], []
    class_body, class_where, outside = {}, {}, {}
    files = 0
    for folder, _, names in sorted(os.walk(os.path.join(root, "Filters"))):
        for name in sorted(names):
            if not name.endswith((".h", ".cxx")):
                continue
            path = os.path.join(folder, name)
            where = os.path.relpath(path, root)
            files += 1
            with open(path, encoding="utf-8", errors="replace") as f:
                lines = sum(1 for _ in f)
            if lines > MAX_FILE:
                problems.append(f"{where}: {lines} lines (at most {MAX_FILE})")
            for kind, name_, first, size, in_class in blocks(path):
                if kind == "function":
                    functions.append((size, f"{where}:{first}", name_))
                    if not in_class and "::" in name_:
                        owner = re.sub(r"<.*>", "", name_.rsplit("::", 2)[-2])  # Foo<T>::f is a member of Foo
                        outside[owner] = outside.get(owner, 0) + size
                elif not in_class:  # nested classes count with their outer class
                    class_body[name_] = class_body.get(name_, 0) + size
                    class_where[name_] = f"{where}:{first}"
    for size, where, fname in functions:
        if size > MAX_FUNCTION:
            problems.append(f"{where}: function {fname} has {size} lines (at most {MAX_FUNCTION})")
    class_sizes = [(body + outside.get(c, 0), class_where[c], c) for c, body in class_body.items()]
    for size, where, cname in class_sizes:
        if size > MAX_CLASS:
            problems.append(f"{where}: class {cname} has {size} lines with its members (at most {MAX_CLASS})")
    return problems, functions, class_sizes, files


def self_test():
    """The scanner on made-up sources: a function of 81 lines of code (with a comment, a string
    holding a brace and a lambda inside), a class of 501 with a member defined outside it, a file
    of 901 lines; each must be found, and their neighbours within the limits must not."""
    import tempfile

    body = "\n".join(f"  x += {k}; // {{" for k in range(77))
    sources = {
        "long_function.cxx": f"int f(int x)\n{{\n  auto g = [](int y) {{ return y; }};\n  const char* s = \"}}\";\n{body}\n}}\n"
                             f"int fine(int x)\n{{\n{body[:-30]}\n}}\n",
        "long_class.h": "class Big\n{\n" + "\n".join(f"  int m{k};" for k in range(479)) + "\n  void f();\n};\n",
        "long_class.cxx": "void Big::f()\n{\n" + "\n".join(f"  m{k} = 0;" for k in range(17)) + "\n}\n",
        "long_file.cxx": "\n" * 901,
    }
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "Filters"))
        for name, text in sources.items():
            with open(os.path.join(root, "Filters", name), "w") as f:
                f.write(text)
        found = check(root)[0]
    expected = ("function f has 81", "class Big has 501", "long_file.cxx: 901 lines")
    missing = [e for e in expected if not any(e in p for p in found)]
    if missing or len(found) != len(expected):
        print("self-test failed: expected", expected, "found", found)
        return False
    return True


def main():
    args = sys.argv[1:]
    listing = 0
    if "--list" in args:
        k = args.index("--list")
        listing = int(args[k + 1])
        del args[k:k + 2]
    root = os.path.abspath(args[0] if args else os.path.join(os.path.dirname(__file__), ".."))
    if not self_test():
        return 1
    problems, functions, class_sizes, files = check(root)
    if listing:
        for size, where, fname in sorted(functions, reverse=True)[:listing]:
            print(f"  function {size:5d}  {fname}  ({where})")
        for size, where, cname in sorted(class_sizes, reverse=True)[:listing]:
            print(f"  class    {size:5d}  {cname}  ({where})")
    for p in problems:
        print(p)
    print(f"{files} files, {len(functions)} functions, {len(class_sizes)} classes checked; "
          f"{len(problems)} size problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
