# SPDX-License-Identifier: GPL-3.0-or-later
"""Finite-element output (issue 11): boundary and interface sets in every format, files that meshio
and gmsh read cleanly, `report` on every format, atomic writes and the one-call Python API.

The sets are checked against faces counted here independently of the package (a dict of sorted
vertex triples) and, for Abaqus, the face numbering of the Abaqus manual (C3D4: S1 = nodes 1-2-3,
S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1)."""
import collections
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import oraclemesh as om

COMMAND = os.environ.get("ORACLEMESH_COMMAND")
FORMATS = (".vtu", ".inp", ".msh", ".mesh")
ABAQUS_FACES = {1: (0, 1, 2), 2: (0, 3, 1), 3: (1, 3, 2), 4: (2, 3, 0)}

# Three materials: an implant ball inside a bone block, a screw crossing the block's top into the ball:
# interfaces between every pair and boundaries of the block and the screw.
SCENE = {
    "domains": [
        {"name": "implant", "type": "sphere", "center": [0, 0, 0], "radius": 3, "material": 3},
        {"name": "screw", "type": "cylinder", "center": [0, 0, 5], "axis": [0, 0, 1], "radius": 1.2, "height": 8,
         "material": 4},
        {"name": "cortical bone", "type": "box", "bounds": [-5, 5, -5, 5, -5, 5], "material": 1},
    ],
    "mesh": {"strategy": "None", "criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.5}, "seed": 1},
}
SET_NAMES = {1: "CORTICAL_BONE", 3: "IMPLANT", 4: "SCREW", -1: "EXTERIOR"}


def run(*args):
    prefix = [COMMAND] if COMMAND else [sys.executable, "-m", "oraclemesh"]
    return subprocess.run(prefix + [str(a) for a in args], capture_output=True, encoding="utf-8", check=False)


def expected_faces(cells, material):
    """{sorted face: [tets]} of the faces on the boundary or between two materials."""
    tets = collections.defaultdict(list)
    for t, cell in enumerate(cells.tolist()):
        for face in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            tets[tuple(sorted(cell[i] for i in face))].append(t)
    return {f: ts for f, ts in tets.items() if len(ts) == 1 or (len(ts) == 2 and material[ts[0]] != material[ts[1]])}


def abaqus_surfaces(path):
    """{surface name: [(element number, face number)]} from the *SURFACE sections of an .inp file."""
    surfaces, current = {}, None
    with open(path) as f:
        for line in f:
            if line.startswith("**"):
                continue
            if line.startswith("*"):
                match = re.match(r"\*SURFACE,\s*NAME=([^,\s]+),\s*TYPE=ELEMENT", line.strip(), re.I)
                current = surfaces.setdefault(match.group(1), []) if match else None
            elif current is not None and line.strip():
                element, face = (x.strip() for x in line.split(","))
                current.append((int(element), int(face[1:])))
    return surfaces


class SurfaceSetsInEveryFormat(unittest.TestCase):
    """A real mesh written by the command line in every format and read back."""

    @classmethod
    def setUpClass(cls):
        import meshio

        cls.tmp = tempfile.TemporaryDirectory()
        scene = os.path.join(cls.tmp.name, "three.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f)
        cls.files = {ext: os.path.join(cls.tmp.name, "out", "three" + ext) for ext in FORMATS}
        args = ["mesh", scene]
        for path in cls.files.values():
            args += ["-o", path]
        cls.result = run(*args)
        if cls.result.returncode == 0:
            mesh = meshio.read(cls.files[".vtu"])
            cls.points = mesh.points
            cls.cells = mesh.cells_dict["tetra"]
            cls.material = mesh.cell_data_dict["Material"]["tetra"].astype(int)
            cls.faces = expected_faces(cls.cells, cls.material)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)

    def pair_name(self, face):
        """The set a boundary or interface face must be in: lower material id first, exterior last."""
        tets = self.faces[face]
        pair = sorted(int(self.material[t]) for t in tets) if len(tets) == 2 else [int(self.material[tets[0]]), -1]
        return f"{SET_NAMES[pair[0]]}__{SET_NAMES[pair[1]]}", pair[0]

    def assertSetsExact(self, triangles_by_name, what):
        """Every named triangle is a boundary/interface face of the named materials, each such face is
        in exactly one set, and the sets cover them all."""
        seen = collections.Counter()
        for name, triangles in triangles_by_name.items():
            for triangle in triangles:
                face = tuple(sorted(int(v) for v in triangle))
                self.assertIn(face, self.faces, f"{what}: {name}: {face} is no boundary or interface face")
                self.assertEqual(self.pair_name(face)[0], name, f"{what}: {face}")
                seen[face] += 1
        self.assertEqual(set(seen), set(self.faces), f"{what}: the sets do not cover every face")
        self.assertEqual(max(seen.values()), 1, f"{what}: a face is in two sets")

    def assertOutward(self, triangles_by_name, what):
        """Triangle normals point out of the first-named material's tetrahedron."""
        for name, triangles in triangles_by_name.items():
            for triangle in triangles:
                face = tuple(sorted(int(v) for v in triangle))
                owner_material = self.pair_name(face)[1]
                owner = next(t for t in self.faces[face] if self.material[t] == owner_material)
                a, b, c = self.points[list(triangle)]
                normal = np.cross(b - a, c - a)
                self.assertGreater(normal @ ((a + b + c) / 3 - self.points[self.cells[owner]].mean(axis=0)), 0,
                                   f"{what}: {name}: {triangle} points into its material")

    def test_the_scene_has_interfaces_between_every_pair_and_boundaries(self):
        names = {self.pair_name(face)[0] for face in self.faces}
        self.assertEqual(names, {"CORTICAL_BONE__IMPLANT", "CORTICAL_BONE__SCREW", "IMPLANT__SCREW",
                                 "CORTICAL_BONE__EXTERIOR", "SCREW__EXTERIOR"})
        self.assertIn("boundary and interface sets", self.result.stdout)

    def test_abaqus_surfaces_are_element_faces_and_node_sets_their_nodes(self):
        import meshio

        mesh = meshio.read(self.files[".inp"])
        np.testing.assert_array_equal(mesh.cells_dict["tetra"], self.cells)
        surfaces = abaqus_surfaces(self.files[".inp"])
        triangles = {}
        for name, faces in surfaces.items():
            triangles[name] = []
            for element, number in faces:
                owner = element - 1
                triangles[name].append(self.cells[owner][list(ABAQUS_FACES[number])])
                face = tuple(sorted(triangles[name][-1].tolist()))
                self.assertEqual(self.material[owner], self.pair_name(face)[1], f"{name}: the first material's face")
        self.assertSetsExact(triangles, ".inp *SURFACE")
        self.assertEqual(set(mesh.point_sets), set(surfaces))
        for name, nodes in mesh.point_sets.items():
            self.assertEqual(set(nodes.tolist()), set(np.concatenate(triangles[name]).tolist()), name)
        self.assertEqual(set(mesh.cell_sets), {"CORTICAL_BONE", "IMPLANT", "SCREW"})

    def test_gmsh_physical_surfaces_are_named_triangles(self):
        import meshio

        mesh = meshio.read(self.files[".msh"], file_format="gmsh")
        names = {int(v[0]): name for name, v in mesh.field_data.items() if int(v[1]) == 2}
        volumes = {int(v[0]): name for name, v in mesh.field_data.items() if int(v[1]) == 3}
        self.assertEqual(volumes, {1: "cortical bone", 3: "implant", 4: "screw"})
        self.assertFalse(set(names) & set(volumes), "surface tags differ from material tags")
        tags = mesh.cell_data_dict["gmsh:physical"]
        np.testing.assert_array_equal(tags["tetra"], self.material)
        triangles = collections.defaultdict(list)
        for triangle, tag in zip(mesh.cells_dict["triangle"], tags["triangle"]):
            triangles[names[int(tag)]].append(triangle)
        self.assertSetsExact(triangles, ".msh")
        self.assertOutward(triangles, ".msh")

    def test_gmsh_reads_the_msh_without_warnings(self):
        gmsh = shutil.which("gmsh")
        self.assertIsNotNone(gmsh, "gmsh is not installed (scripts/setup-debian.sh installs it)")
        result = subprocess.run([gmsh, "-check", self.files[".msh"]], capture_output=True, encoding="utf-8",
                                check=False)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        output = result.stdout + result.stderr
        self.assertNotRegex(output, r"(?i)warning|error", output)
        elements = int(re.search(r"(\d+) elements", output).group(1))
        self.assertEqual(elements, len(self.cells) + len(self.faces))

    def test_medit_triangle_references_are_the_named_surfaces(self):
        import meshio

        mesh = meshio.read(self.files[".mesh"])
        with open(self.files[".mesh"]) as f:
            names = {int(m.group(1)): m.group(2) for m in re.finditer(r"^# surface (\d+) (\S+)$", f.read(), re.M)}
        refs = mesh.cell_data_dict["medit:ref"]
        np.testing.assert_array_equal(refs["tetra"], self.material)
        triangles = collections.defaultdict(list)
        for triangle, ref in zip(mesh.cells_dict["triangle"], refs["triangle"]):
            triangles[names[int(ref)]].append(triangle)
        self.assertSetsExact(triangles, ".mesh")
        self.assertOutward(triangles, ".mesh")

    def test_vtu_companion_holds_the_surfaces(self):
        import meshio
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

        from oraclemesh.fielddata import labelled

        companion = os.path.join(self.tmp.name, "out", "three_surfaces.vtu")
        mesh = meshio.read(companion)
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(companion)
        reader.Update()
        names = {int(tag): name for name, tag in labelled(reader.GetOutput().GetFieldData(), "SurfaceTags")}
        # the companion has only the surfaces' points: map them back to the mesh's by position
        index = {tuple(p): i for i, p in enumerate(self.points.tolist())}
        to_mesh = np.array([index[tuple(p)] for p in mesh.points.tolist()])
        triangles = collections.defaultdict(list)
        pairs = mesh.cell_data_dict["Materials"]["triangle"]
        for triangle, tag, pair in zip(mesh.cells_dict["triangle"], mesh.cell_data_dict["Surface"]["triangle"], pairs):
            name = names[int(tag)]
            triangles[name].append(to_mesh[triangle])
            self.assertEqual(name, f"{SET_NAMES[int(pair[0])]}__{SET_NAMES[int(pair[1])]}")
        self.assertSetsExact(triangles, "_surfaces.vtu")
        self.assertOutward(triangles, "_surfaces.vtu")

    def test_every_file_reads_in_meshio_without_warnings(self):
        for path in list(self.files.values()) + [os.path.join(self.tmp.name, "out", "three_surfaces.vtu")]:
            result = subprocess.run([sys.executable, "-c", "import sys, meshio; meshio.read(sys.argv[1])", path],
                                    capture_output=True, encoding="utf-8", check=False)
            self.assertEqual(result.returncode, 0, f"{path}: {result.stdout} {result.stderr}")
            self.assertEqual(result.stderr, "", path)  # meshio's warnings and errors go to stderr

    def test_report_reads_every_format_with_the_materials(self):
        rows = {}
        for ext, path in self.files.items():
            result = run("report", path, "--no-png")
            self.assertEqual(result.returncode, 0, f"{path}: {result.stderr}")
            rows[ext] = sorted([p[0], " ".join(p[1:-8]), p[-8]] for p in  # material, name, tets, 7 more columns
                               (line.split() for line in result.stdout.splitlines() if re.match(r"\s+\d+\s", line)))
            self.assertIn("validity: no defects", result.stdout)
        counts = collections.Counter(self.material.tolist())
        expected = sorted([str(m), name, str(counts[m])] for m, name in
                          {1: "cortical bone", 3: "implant", 4: "screw"}.items())
        for ext in FORMATS:
            self.assertEqual(rows[ext], expected, ext)

    def test_vtu_field_data_keeps_names_statistics_and_warnings(self):
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

        from oraclemesh.report import material_names, statistics

        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(self.files[".vtu"])
        reader.Update()
        grid = reader.GetOutput()
        self.assertEqual(material_names(grid), {1: "cortical bone", 3: "implant", 4: "screw"})
        stats = statistics(grid)
        for m in (1, 3, 4):
            self.assertGreater(stats[f"volume.material_{m}"], 0)
        fd = grid.GetFieldData()
        self.assertFalse([fd.GetAbstractArray(i).GetName() for i in range(fd.GetNumberOfArrays())
                          if fd.GetAbstractArray(i).IsA("vtkStringArray")])


def _two_tetrahedra(materials):
    from vtkmodules.util.vtkConstants import VTK_TETRA
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints, vtkStringArray
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, -1)):
        points.InsertNextPoint(p)
    grid.SetPoints(points)
    array = vtkIntArray()
    array.SetName("Material")
    for ids, m in zip(((0, 1, 2, 3), (0, 2, 1, 4)), materials):
        grid.InsertNextCell(VTK_TETRA, 4, ids)
        array.InsertNextValue(m)
    grid.GetCellData().AddArray(array)
    warnings = vtkStringArray()
    warnings.SetName("Warnings")
    warnings.InsertNextValue('a <warning> with "quotes" & ampersands\nover two lines')
    grid.GetFieldData().AddArray(warnings)
    return grid


class CalculiX(unittest.TestCase):
    """The Abaqus files run as written in CalculiX (Debian's calculix-ccx, which reads Abaqus decks
    and takes at most 20 characters per number): an implant ball in a bone block, linear and
    10-node, the materials on the element sets, the bottom clamped through a node set, a pressure
    on the block's exterior *SURFACE. Both orders solve and agree on the top's displacement."""

    SCENE = {"domains": [{"name": "implant", "type": "sphere", "center": [0, 0, 0], "radius": 2, "material": 2},
                         {"name": "bone", "type": "box", "bounds": [-5, 5, -5, 5, -5, 5], "material": 1}],
             "mesh": {"criteria": {"cell_size": 2, "facet_size": 2, "facet_distance": 0.2}, "seed": 1}}

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.files = {}
        for order in (1, 2):
            cls.files[order] = os.path.join(cls.tmp.name, f"mesh{order}.inp")
            om.mesh(cls.SCENE, element_order=order).save(cls.files[order])

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_number_fits_twenty_characters(self):
        for path in self.files.values():
            with open(path) as f:
                text = f.read()
            nodes = text.split("*NODE\n", 1)[1].split("*", 1)[0]
            widths = [len(field.strip()) for line in nodes.splitlines() for field in line.split(",")]
            self.assertGreater(len(widths), 100)
            self.assertLessEqual(max(widths), 20, path)

    def solve(self, order):
        """The top-centre node's displacement (ux, uy, uz) from ccx on a deck that includes the mesh."""
        import meshio

        points = meshio.read(self.files[order]).points
        z = points[:, 2]
        bottom = np.flatnonzero(np.abs(z - z.min()) < 1e-9) + 1
        probe = int(np.argmin(np.linalg.norm(points - [0, 0, z.max()], axis=1))) + 1
        job = f"job{order}"
        lines = [f"*INCLUDE, INPUT={os.path.basename(self.files[order])}", "*NSET, NSET=PROBE", str(probe),
                 "*NSET, NSET=BOTTOM"]
        lines += [",".join(map(str, bottom[i:i + 8])) for i in range(0, len(bottom), 8)]
        lines += ["*MATERIAL, NAME=CANCELLOUS", "*ELASTIC", "1000., 0.3", "*MATERIAL, NAME=TITANIUM", "*ELASTIC",
                  "110000., 0.3", "*SOLID SECTION, ELSET=BONE, MATERIAL=CANCELLOUS",
                  "*SOLID SECTION, ELSET=IMPLANT, MATERIAL=TITANIUM", "*BOUNDARY", "BOTTOM, 1, 3, 0.",
                  "*STEP", "*STATIC", "*DSLOAD", "BONE__EXTERIOR, P, 10.", "*NODE PRINT, NSET=PROBE", "U",
                  "*END STEP"]
        with open(os.path.join(self.tmp.name, job + ".inp"), "w") as f:
            f.write("\n".join(lines) + "\n")
        result = subprocess.run([self.ccx, job], cwd=self.tmp.name, capture_output=True, encoding="utf-8",
                                errors="replace", env=dict(os.environ, OMP_NUM_THREADS="1"), timeout=600)
        output = result.stdout + result.stderr
        self.assertEqual(result.returncode, 0, output[-2000:])
        self.assertNotIn("*ERROR", output)
        with open(os.path.join(self.tmp.name, job + ".dat")) as f:
            rows = [line.split() for line in f if line.split() and line.split()[0] == str(probe)]
        self.assertEqual(len(rows), 1, output[-2000:])
        return np.array([float(v) for v in rows[0][1:4]])

    def test_both_orders_solve_and_agree(self):
        self.ccx = shutil.which("ccx")
        self.assertIsNotNone(self.ccx, "ccx is not installed (scripts/setup-debian.sh installs calculix-ccx)")
        linear, quadratic = self.solve(1), self.solve(2)
        self.assertLess(linear[2], 0)  # the pressure on the exterior pushes the top down
        self.assertLess(quadratic[2], 0)
        self.assertLess(abs(linear[2] - quadratic[2]), 0.05 * abs(quadratic[2]), (linear, quadratic))


class Writers(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def leftovers(self):
        return [f for f in os.listdir(self.tmp.name) if f.startswith(".")]

    def test_two_materials_share_one_interface_face_oriented_out_of_the_first(self):
        from oraclemesh.surfaces import surface_sets
        from vtkmodules.util.numpy_support import vtk_to_numpy

        grid = _two_tetrahedra((7, 2))
        points = vtk_to_numpy(grid.GetPoints().GetData())
        cells = np.array([[0, 1, 2, 3], [0, 2, 1, 4]])
        sets = surface_sets(points, cells, np.array([7, 2]), {7: "cortical bone", 2: None})
        self.assertEqual(sets.names, ["MATERIAL_2__CORTICAL_BONE", "MATERIAL_2__EXTERIOR", "CORTICAL_BONE__EXTERIOR"])
        shared = sets.faces[sets.select(0)]
        self.assertEqual(len(shared), 1)
        self.assertEqual(sorted(shared[0].tolist()), [0, 1, 2])
        self.assertEqual(sets.owner[sets.select(0)].tolist(), [1])  # material 2's tetrahedron
        self.assertGreater(np.cross(*(points[shared[0][1:]] - points[shared[0][0]]))[2], 0)  # towards z > 0
        # the same mesh with the tetrahedra listed the other way round: the same sets
        again = surface_sets(points, cells[::-1], np.array([2, 7]), {7: "cortical bone"})
        self.assertEqual(again.names, sets.names)
        self.assertEqual({tuple(sorted(f)) for f in again.faces.tolist()}, {tuple(sorted(f)) for f in sets.faces.tolist()})

    def test_field_data_text_survives_the_vtu_and_meshio_reads_it(self):
        import meshio

        from oraclemesh.fielddata import strings
        from oraclemesh.meshfiles import read_mesh
        from oraclemesh.meshing import describe
        from oraclemesh.report import material_names
        from oraclemesh.writers import write_mesh

        grid = _two_tetrahedra((1, 2))
        names = {1: 'bone "A" & <B>', 2: "implant\tTi"}
        describe(grid, names, 0)
        path = os.path.join(self.tmp.name, "two.vtu")
        self.assertEqual(write_mesh(grid, path, names), [path, os.path.join(self.tmp.name, "two_surfaces.vtu")])
        back = read_mesh(path)
        self.assertEqual(material_names(back), names)
        self.assertEqual(strings(back.GetFieldData(), "Warnings"), strings(grid.GetFieldData(), "Warnings"))
        self.assertEqual(set(meshio.read(path).field_data), {"FeatureSegments", "MaterialIds", "Warnings"})
        self.assertEqual(material_names(grid), names, "the grid in memory is left as it was")

    def test_a_failed_write_keeps_the_previous_file_and_names_the_path(self):
        import meshio

        from oraclemesh.writers import write_mesh

        path = os.path.join(self.tmp.name, "good.inp")
        write_mesh(_two_tetrahedra((1, 2)), path)
        with open(path) as f:
            before = f.read()
        original = meshio.abaqus.write

        def interrupted(filename, mesh, **options):
            with open(filename, "w") as f:
                f.write("*HEADING\nhalf a fi")
            raise KeyboardInterrupt  # as if the run were stopped while writing

        meshio.abaqus.write = interrupted
        try:
            with self.assertRaises(KeyboardInterrupt):
                write_mesh(_two_tetrahedra((1, 3)), path)
        finally:
            meshio.abaqus.write = original
        with open(path) as f:
            self.assertEqual(f.read(), before)
        self.assertEqual(self.leftovers(), [])

    def test_a_failing_vtk_writer_raises_naming_the_path(self):
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

        from oraclemesh.writers import write_vtk_xml

        class Failing(vtkXMLUnstructuredGridWriter):
            def Write(self):
                return 0

        path = os.path.join(self.tmp.name, "x.vtu")
        with self.assertRaises(om.OracleMeshError) as ctx:
            write_vtk_xml(_two_tetrahedra((1, 2)), path, Failing)
        self.assertIn(f"{path}: could not be written", str(ctx.exception))
        self.assertFalse(os.path.exists(path))
        self.assertEqual(self.leftovers(), [])

    def test_the_command_line_never_says_wrote_after_a_failure(self):
        scene = os.path.join(self.tmp.name, "three.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f)
        blocker = os.path.join(self.tmp.name, "file")
        with open(blocker, "w") as f:
            f.write("not a folder")
        for ext in FORMATS:
            out = os.path.join(blocker, "mesh" + ext)
            result = run("mesh", scene, "-o", out)
            self.assertEqual(result.returncode, 2, ext)
            # refused before meshing (the writers' own failures are tested above through the API)
            self.assertIn(f"{out}: cannot write the mesh: {blocker} is a file, not a folder", result.stderr)
            self.assertNotIn("wrote", result.stdout)


class PythonApi(unittest.TestCase):
    def test_mesh_a_dict_or_a_file_and_save_every_format(self):
        import meshio
        from vtkmodules.util.numpy_support import vtk_to_numpy

        with tempfile.TemporaryDirectory() as tmp:
            result = om.mesh(SCENE)
            self.assertIsInstance(result, om.MeshResult)
            self.assertIn(f"{result.grid.GetNumberOfCells()} tetrahedra", result.report)
            self.assertEqual(set(result.quality["materials"]), {1, 3, 4})
            self.assertGreater(result.statistics["volume.material_3"], 0)
            scene = os.path.join(tmp, "three.json")
            with open(scene, "w") as f:
                json.dump(SCENE, f)
            again = om.mesh(scene)  # the same scene and seed: the same mesh
            for name in ("Material",):
                np.testing.assert_array_equal(vtk_to_numpy(again.grid.GetCellData().GetArray(name)),
                                              vtk_to_numpy(result.grid.GetCellData().GetArray(name)))
            np.testing.assert_array_equal(vtk_to_numpy(again.grid.GetPoints().GetData()),
                                          vtk_to_numpy(result.grid.GetPoints().GetData()))
            paths = [os.path.join(tmp, "m" + ext) for ext in FORMATS]
            written = result.save(*paths)
            self.assertEqual(set(written), set(paths) | {os.path.join(tmp, "m_surfaces.vtu")})
            self.assertEqual(set(meshio.read(paths[1]).point_sets), set(result.surface_sets.names))

    def test_the_mesher_faces_give_the_sets_the_writers_find_alone(self):
        """A fresh result's sets come from the faces the mesher's validity check found (field array
        SeparatingFaces); found again from the tetrahedra alone they are the same, face for face."""
        from oraclemesh.writers import MeshArrays

        for order in (1, 2):
            result = om.mesh(SCENE, element_order=order)
            fast = result.surface_sets
            self.assertIsNotNone(result._separating, "the mesher gave its faces")
            alone = MeshArrays(result.grid, result.material_names).sets
            self.assertEqual(fast.names, alone.names)
            self.assertEqual(fast.materials, alone.materials)
            for field in ("faces", "owner", "side", "pairs", "surface"):
                np.testing.assert_array_equal(getattr(fast, field), getattr(alone, field), err_msg=f"order {order}: {field}")
            with tempfile.TemporaryDirectory() as tmp:  # the writers' own data stays out of the files
                path = os.path.join(tmp, "m.vtu")
                result.save(path)
                with open(path, "rb") as f:
                    self.assertNotIn(b"SeparatingFaces", f.read())

    def test_bad_scenes_and_paths_are_named(self):
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.mesh("/nonexistent/scene.json")
        self.assertIn("/nonexistent/scene.json: scene file not found", str(ctx.exception))
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.mesh({"domains": [{"type": "sphere", "radius": -1, "material": 1, "center": [0, 0, 0]}]})
        self.assertIn("$.domains[0].radius", str(ctx.exception))
        with self.assertRaises(om.OracleMeshError) as ctx:
            om.mesh(42)
        self.assertIn("expected a scene file path, a dict", str(ctx.exception))
        result = om.mesh(SCENE)
        with self.assertRaises(om.OracleMeshError) as ctx:
            result.save("x.stl")
        self.assertIn("x.stl: unknown mesh format '.stl'", str(ctx.exception))


if __name__ == "__main__":
    unittest.main()
