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

    def test_faces_point_out_of_their_owner_and_a_known_orientation_gives_the_same(self):
        """Every boundary and interface face points away from its owner's fourth vertex, on inverted
        tetrahedra too (measured); `oriented` (all volumes known positive: the mesher's check) gives
        the same faces without measuring."""
        from oraclemesh.surfaces import TET_FACES, surface_sets

        rng = np.random.default_rng(4)
        corners = np.array([[(v >> 0) & 1, (v >> 1) & 1, (v >> 2) & 1] for v in range(8)], float)
        points, cells, material = [], [], []
        for cube, offset in enumerate(np.ndindex(3, 2, 2)):  # twelve cubes of six Kuhn tetrahedra
            base = len(points)
            points += (corners + offset + rng.uniform(-0.1, 0.1, (8, 3))).tolist()
            cells += [[base + i for i in t] for t in KUHN]
            material += [1 + cube % 3] * len(KUHN)
        points, cells, material = np.array(points), np.array(cells), np.array(material)
        volume = lambda t: np.einsum("ij,ij->i", np.cross(points[t[:, 1]] - points[t[:, 0]], points[t[:, 2]] - points[t[:, 0]]),
                                     points[t[:, 3]] - points[t[:, 0]])
        negative = volume(cells) < 0
        cells[negative] = cells[negative][:, [1, 0, 2, 3]]  # all positive, as the mesher's
        self.assertTrue((volume(cells) > 0).all())
        known = surface_sets(points, cells, material, oriented=True)
        measured = surface_sets(points, cells, material)
        np.testing.assert_array_equal(known.faces, measured.faces)
        flipped = cells.copy()
        flipped[::5, [0, 1]] = flipped[::5, [1, 0]]  # every fifth tetrahedron inverted
        sets = surface_sets(points, flipped, material)
        fourth = flipped[sets.owner, [next(v for v in range(4) if v not in TET_FACES[s - 1]) for s in sets.side]]
        f = points[sets.faces]
        normal = np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0])
        self.assertTrue((np.einsum("ij,ij->i", normal, points[fourth] - f[:, 0]) < 0).all())
        self.assertEqual(sorted(map(sorted, sets.faces.tolist())), sorted(map(sorted, measured.faces.tolist())))

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
        from oraclemesh import meshtext
        from oraclemesh.writers import write_mesh

        path = os.path.join(self.tmp.name, "good.inp")
        write_mesh(_two_tetrahedra((1, 2)), path)
        with open(path) as f:
            before = f.read()
        original = meshtext.write_rows

        def interrupted(f, *args, **options):
            f.write("half a ro")
            raise KeyboardInterrupt  # as if the run were stopped while writing, after the heading

        meshtext.write_rows = interrupted
        try:
            with self.assertRaises(KeyboardInterrupt):
                write_mesh(_two_tetrahedra((1, 3)), path)
        finally:
            meshtext.write_rows = original
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


KUHN = [[0, 1 << a, (1 << a) | (1 << b), 7] for a, b in ((0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1))]
VTK_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # mid-edge nodes 4..9 of a 10-node tetrahedron
BLOCK_NAMES = {1: "block", 2: "post", 3: "top"}
BLOCK_SETS = {1: "BLOCK", 2: "POST", 3: "TOP", -1: "EXTERIOR"}


def _cube_block(n, order=1):
    """n^3 cubes of six tetrahedra each (around the cube's diagonal: conforming), materials 3 (the top
    layer), 2 (a post in one quarter below it) and 1; for order 2 a mid-edge node per edge. Returns
    (grid, points, nodes [m x 4 or 10] in VTK's order, material)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.util.vtkConstants import VTK_ID_TYPE, VTK_QUADRATIC_TETRA, VTK_TETRA
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid

    bits = np.array([(b & 1, (b >> 1) & 1, (b >> 2) & 1) for b in range(8)])
    ijk = np.array([(i, j, k) for k in range(n + 1) for j in range(n + 1) for i in range(n + 1)])
    points = ijk * 0.7 + np.sin(ijk.sum(axis=1) * 1.3)[:, None] * 0.05  # coordinates with all their digits
    cubes = np.array([(i, j, k) for k in range(n) for j in range(n) for i in range(n)])
    corner = bits @ [1, n + 1, (n + 1) ** 2]
    nodes = ((cubes @ [1, n + 1, (n + 1) ** 2])[:, None, None] + corner[np.array(KUHN)]).reshape(-1, 4)
    p = points[nodes]
    negative = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) < 0
    nodes[negative] = nodes[negative][:, [0, 2, 1, 3]]
    material = np.where(cubes[:, 2] == n - 1, 3, np.where((cubes[:, 0] < n // 2) & (cubes[:, 1] < n // 2), 2, 1))
    material = np.repeat(material, 6).astype(np.int32)
    if order == 2:
        mids, extra = {}, []
        for cell in nodes.tolist():
            for i, j in VTK_EDGES:
                key = (min(cell[i], cell[j]), max(cell[i], cell[j]))
                if key not in mids:
                    mids[key] = len(points) + len(extra)
                    extra.append((points[key[0]] + points[key[1]]) / 2)
        nodes = np.array([c + [mids[min(c[i], c[j]), max(c[i], c[j])] for i, j in VTK_EDGES]
                          for c in nodes.tolist()])
        points = np.concatenate([points, extra])
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtk(np.arange(0, nodes.size + 1, nodes.shape[1]), deep=True, array_type=VTK_ID_TYPE),
                  numpy_to_vtk(nodes.ravel(), deep=True, array_type=VTK_ID_TYPE))
    grid.SetCells(VTK_QUADRATIC_TETRA if order == 2 else VTK_TETRA, cells)
    array = numpy_to_vtk(material, deep=True)
    array.SetName("Material")
    grid.GetCellData().AddArray(array)
    return grid, points, nodes, material


class StreamedWriting(unittest.TestCase):
    """The text formats are written a block of rows at a time and the mesh is not copied: files that
    meshio reads back as the mesh with its sets (sets found here from the tetrahedra alone), the same
    bytes for any block size, and the arrays the writers read are the grid's own."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, grid, name, **options):
        from oraclemesh.writers import write_mesh

        path = os.path.join(self.tmp.name, name)
        write_mesh(grid, path, BLOCK_NAMES, **options)
        return path

    def expected_sets(self, nodes, material):
        """{surface name: set of its sorted corner triples}, {surface name: set of its nodes}."""
        faces = expected_faces(nodes[:, :4], material)
        mid = {}
        if nodes.shape[1] == 10:
            for cell in nodes.tolist():
                mid.update({frozenset((cell[i], cell[j])): cell[4 + e] for e, (i, j) in enumerate(VTK_EDGES)})
        triangles, node_sets = collections.defaultdict(set), collections.defaultdict(set)
        for face, tets in faces.items():
            pair = sorted(int(material[t]) for t in tets) if len(tets) == 2 else [int(material[tets[0]]), -1]
            name = f"{BLOCK_SETS[pair[0]]}__{BLOCK_SETS[pair[1]]}"
            triangles[name].add(face)
            node_sets[name] |= set(face) | {mid[frozenset(e)] for e in ((face[0], face[1]), (face[1], face[2]),
                                                                         (face[0], face[2])) if mid}
        return triangles, node_sets

    def test_meshio_reads_back_the_mesh_and_its_sets(self):
        import meshio

        for order in (1, 2):
            grid, points, nodes, material = _cube_block(3, order)
            kind = "tetra10" if order == 2 else "tetra"
            triangles, node_sets = self.expected_sets(nodes, material)
            self.assertEqual(set(triangles), {"BLOCK__POST", "BLOCK__TOP", "POST__TOP", "BLOCK__EXTERIOR",
                                              "POST__EXTERIOR", "TOP__EXTERIOR"})
            inp = meshio.read(self.write(grid, f"m{order}.inp"))
            np.testing.assert_allclose(inp.points, points, rtol=1e-12, atol=1e-12)
            np.testing.assert_array_equal(inp.cells_dict[kind], nodes)
            self.assertEqual({k: v[0].tolist() for k, v in inp.cell_sets.items()},
                             {BLOCK_SETS[m]: np.flatnonzero(material == m).tolist() for m in (1, 2, 3)})
            self.assertEqual({k: set(v.tolist()) for k, v in inp.point_sets.items()}, dict(node_sets))
            msh = meshio.read(self.write(grid, f"m{order}.msh"))
            np.testing.assert_array_equal(msh.points, points)  # 17 significant digits: exact
            np.testing.assert_array_equal(msh.cells_dict[kind], nodes)
            tags = msh.cell_data_dict["gmsh:physical"]
            np.testing.assert_array_equal(tags[kind], material)
            names = {int(v[0]): name for name, v in msh.field_data.items() if int(v[1]) == 2}
            found = collections.defaultdict(set)
            face_kind = "triangle6" if order == 2 else "triangle"
            for triangle, tag in zip(msh.cells_dict[face_kind], tags[face_kind]):
                found[names[int(tag)]].add(tuple(sorted(triangle[:3].tolist())))
            self.assertEqual(dict(found), dict(triangles))
            vtu = meshio.read(self.write(grid, f"m{order}.vtu"))
            np.testing.assert_array_equal(vtu.points, points)
            np.testing.assert_array_equal(vtu.cells_dict[kind], nodes)
            np.testing.assert_array_equal(vtu.cell_data_dict["Material"][kind], material)
            if order == 1:  # meshio 5.0 reads no P2 Medit keywords
                medit = meshio.read(self.write(grid, "m1.mesh"))
                np.testing.assert_array_equal(medit.points, points)
                np.testing.assert_array_equal(medit.cells_dict["tetra"], nodes)
                np.testing.assert_array_equal(medit.cell_data_dict["medit:ref"]["tetra"], material)
                self.assertEqual(len(medit.cells_dict["triangle"]), sum(map(len, triangles.values())))

    def test_the_block_size_changes_nothing(self):
        for order in (1, 2):
            grid = _cube_block(3, order)[0]  # 162 tetrahedra, sets of 8 to 60 ids
            for ext in (".inp", ".msh", ".mesh"):
                with open(self.write(grid, "whole" + ext, block_rows=10 ** 6), "rb") as f:
                    whole = f.read()
                for rows in (1, 2, 3, 7, 8, 9, 50):
                    with open(self.write(grid, f"{rows}{ext}", block_rows=rows), "rb") as f:
                        self.assertEqual(f.read(), whole, f"order {order}, {ext}, {rows} rows a block")

    def test_abaqus_id_lists_break_as_one_list(self):
        import io

        from oraclemesh.meshtext import write_id_lines

        for count in (1, 7, 8, 9, 16, 17, 30):
            ids = list(range(1, count + 1))
            expected = ",\n".join(",".join(map(str, ids[i:i + 8])) for i in range(0, count, 8)) + "\n"
            for size in (1, 3, 8, 100):
                out = io.StringIO()
                write_id_lines(out, (np.array(ids[i:i + size]) for i in range(0, count, size)))
                self.assertEqual(out.getvalue(), expected, f"{count} ids in chunks of {size}")

    def test_the_writers_read_the_grid_own_arrays(self):
        from vtkmodules.util.numpy_support import vtk_to_numpy

        from oraclemesh.writers import MeshArrays

        for order in (1, 2):
            grid = _cube_block(2, order)[0]
            arrays = MeshArrays(grid, BLOCK_NAMES)
            for mine, theirs in ((arrays.points, grid.GetPoints().GetData()),
                                 (arrays.nodes, grid.GetCells().GetConnectivityArray()),
                                 (arrays.material, grid.GetCellData().GetArray("Material"))):
                self.assertTrue(np.shares_memory(mine, vtk_to_numpy(theirs)), f"order {order}: a copy")
                self.assertFalse(mine.flags.writeable, "the writers leave the mesh as it is")


if __name__ == "__main__":
    unittest.main()
