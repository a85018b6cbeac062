# SPDX-License-Identifier: GPL-3.0-or-later
"""The names of a mesh's arrays and statistics come from one list, Filters/FieldDataKeys.txt: the C++
header and the Python module generated from it hold the same list, and no key is written again as a
string literal in the C++ (Filters/) or the Python package (Wrapping/Python/oraclemesh/)."""
import glob
import io
import os
import re
import tokenize
import unittest

from oraclemesh import fieldkeys

SOURCE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
LIST = os.path.join(SOURCE, "Filters", "FieldDataKeys.txt")


def listed():
    pairs = []
    with open(LIST) as f:
        for line in f:
            line = line.split("#")[0].strip()
            if line:
                name, key = line.split()
                pairs.append((name, key))
    return pairs


def cxx_literals(text, keys):
    """(line, key) for every C++ string literal equal to a key, comments left out."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    found = []
    for number, line in enumerate(text.split("\n"), 1):
        code = re.sub(r"//.*", "", line)
        found += [(number, key) for key in re.findall(r'"((?:[^"\\]|\\.)*)"', code) if key in keys]
    return found


def python_literals(text, keys):
    """(line, key) for every Python string equal to a key, or quoting one inside a longer string
    (an f-string's text); docstrings and comments left out."""
    found = []
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type != tokenize.STRING:
            continue
        body = token.string.lstrip("rbfuRBFU")
        if body.startswith(('"""', "'''")):
            continue
        inner = body[1:-1]
        if inner in keys or any(f"'{key}'" in inner or f'"{key}"' in inner for key in keys):
            found.append((token.start[0], inner))
    return found


class FieldKeys(unittest.TestCase):
    def test_python_module_is_the_list(self):
        self.assertEqual(list(fieldkeys.KEYS), [(name, key) for name, key in listed()])
        for name, key in listed():
            self.assertEqual(getattr(fieldkeys, name), key)

    def test_cxx_header_is_the_list(self):
        header = os.environ.get("ORACLEMESH_FIELD_KEYS_HEADER")
        if not header:
            self.skipTest("ORACLEMESH_FIELD_KEYS_HEADER not set (ctest sets it)")
        with open(header) as f:
            text = f.read()
        self.assertEqual(re.findall(r'constexpr const char\* (\w+) = "([^"]*)";', text), listed())

    def test_no_key_literal_outside_the_generated_files(self):
        keys = {key for _, key in listed()}
        places = []
        for path in sorted(glob.glob(os.path.join(SOURCE, "Filters", "**", "*.cxx"), recursive=True) +
                           glob.glob(os.path.join(SOURCE, "Filters", "**", "*.h"), recursive=True)):
            with open(path) as f:
                places += [f"{os.path.relpath(path, SOURCE)}:{n}: {k}" for n, k in cxx_literals(f.read(), keys)]
        for path in sorted(glob.glob(os.path.join(SOURCE, "Wrapping", "Python", "oraclemesh", "*.py"))):
            with open(path) as f:
                places += [f"{os.path.relpath(path, SOURCE)}:{n}: {k}" for n, k in python_literals(f.read(), keys)]
        self.assertEqual(places, [], "use omesh::keys / oraclemesh.fieldkeys (Filters/FieldDataKeys.txt)")

    def test_the_scanners_see_literals(self):
        keys = {fieldkeys.MATERIAL, fieldkeys.FEATURE_COVERAGE}
        cxx = '// "Material" in a comment\n/* "Material" */ a->SetName("Material");\nx = "Materials";\n'
        self.assertEqual(cxx_literals(cxx, keys), [(2, "Material")])
        py = '"""Docstring: "Material"."""\n# "Material"\nx = "feature_coverage"\ny = f"array \'Material\' {z}"\n'
        self.assertEqual([n for n, _ in python_literals(py, keys)], [3, 4])


if __name__ == "__main__":
    unittest.main()
