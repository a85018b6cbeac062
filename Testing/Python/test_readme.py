# SPDX-License-Identifier: GPL-3.0-or-later
"""The README's examples work as printed: the Python blocks run, the C++ block is the tested file."""
import os
import re
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def readme_blocks(language):
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
        text = f.read()
    blocks = re.findall(r"```" + language + r"\n(.*?)```", text, re.S)
    if not blocks:
        raise AssertionError(f"README has no ```{language} block")
    return blocks


def readme_block(language):
    return readme_blocks(language)[0]


def run_block(source, name):
    """Runs a README block in a temporary working folder (it may write files); returns its namespace."""
    namespace, here = {}, os.getcwd()
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)
        try:
            exec(compile(source, f"README.md ({name})", "exec"), namespace)  # noqa: S102
            namespace["_files"] = sorted(os.listdir(tmp))
        finally:
            os.chdir(here)
    return namespace


class Readme(unittest.TestCase):
    def test_the_python_example_meshes(self):
        mesh = run_block(readme_blocks("python")[0], "python, first block")["mesh"]
        materials = mesh.GetCellData().GetArray("Material")
        self.assertGreater(mesh.GetNumberOfCells(), 100)
        self.assertEqual({int(materials.GetValue(i)) for i in range(materials.GetNumberOfValues())}, {1, 2})

    def test_the_one_call_example_meshes_and_saves_with_its_sets(self):
        namespace = run_block(readme_blocks("python")[1], "python, oraclemesh.mesh")
        result = namespace["result"]
        self.assertIs(namespace["grid"], result.grid)
        self.assertIn(f"{result.grid.GetNumberOfCells()} tetrahedra", result.report)
        self.assertEqual(set(result.quality["materials"]), {1, 2})
        self.assertEqual(result.surface_sets.names, ["BONE__IMPLANT", "BONE__EXTERIOR", "IMPLANT__EXTERIOR"])
        self.assertEqual(namespace["_files"], ["bone.inp", "bone.vtu", "bone_surfaces.vtu"])

    def test_the_cxx_example_is_the_tested_file(self):
        with open(os.path.join(ROOT, "Testing", "VTK", "ReadmeExample.cxx"), encoding="utf-8") as f:
            source = f.read()
        self.assertEqual(readme_block("cpp"), source[source.index("#include"):])

    def test_the_cmake_example_is_the_installed_package_tests(self):
        """The README's find_package / target_link_libraries lines are those of the outside project
        that the test Install.find_package builds against an installed tree."""
        with open(os.path.join(ROOT, "Testing", "Install", "consumer", "CMakeLists.txt"), encoding="utf-8") as f:
            consumer = f.read()
        block = readme_block("cmake")
        find = re.search(r"^find_package\(OracleMesh[^)]*\)", block, re.M).group(0)
        link = re.search(r"^target_link_libraries\(my_mesher [^)]*\)", block, re.M).group(0)
        self.assertIn(find, consumer)
        self.assertIn(link, consumer)

    def test_the_design_notes_name_files_that_exist(self):
        """docs/*.md name files in backquotes (`Filters/Core/Quality/MeshQuality.h`, `SegmentRules.h`): a path
        must exist, a bare file name must exist somewhere in the source tree, so the notes follow
        the code when files move or go."""
        names = set()
        for top, dirs, files in os.walk(ROOT):
            dirs[:] = [d for d in dirs if not d.startswith((".", "build"))]
            names.update(files)
        docs = os.path.join(ROOT, "docs")
        # the reference pages (docs/journal holds dated studies: what they name may since have moved)
        for doc in sorted(f for f in os.listdir(docs) if f.endswith(".md")):
            with open(os.path.join(docs, doc), encoding="utf-8") as f:
                text = f.read()
            for ref in re.findall(r"`([\w./-]+\.(?:h|cxx|py|xml|json|md|sh|module))`", text):
                with self.subTest(doc=doc, ref=ref):
                    if "/" in ref:
                        self.assertTrue(os.path.exists(os.path.join(ROOT, ref)), f"{doc} names {ref}, which does not exist")
                    else:
                        self.assertIn(ref, names, f"{doc} names {ref}, found nowhere in the source tree")


if __name__ == "__main__":
    unittest.main()
