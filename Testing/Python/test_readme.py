# SPDX-License-Identifier: GPL-3.0-or-later
"""The README's examples work as printed: the Python block runs, the C++ block is the tested file."""
import os
import re
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def readme_block(language):
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
        text = f.read()
    match = re.search(r"```" + language + r"\n(.*?)```", text, re.S)
    if not match:
        raise AssertionError(f"README has no ```{language} block")
    return match.group(1)


class Readme(unittest.TestCase):
    def test_the_python_example_meshes(self):
        namespace = {}
        exec(compile(readme_block("python"), "README.md (python)", "exec"), namespace)  # noqa: S102
        mesh = namespace["mesh"]
        materials = mesh.GetCellData().GetArray("Material")
        self.assertGreater(mesh.GetNumberOfCells(), 100)
        self.assertEqual({int(materials.GetValue(i)) for i in range(materials.GetNumberOfValues())}, {1, 2})

    def test_the_cxx_example_is_the_tested_file(self):
        with open(os.path.join(ROOT, "Testing", "VTK", "ReadmeExample.cxx"), encoding="utf-8") as f:
            source = f.read()
        self.assertEqual(readme_block("cpp"), source[source.index("#include"):])


if __name__ == "__main__":
    unittest.main()
