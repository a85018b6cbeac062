# SPDX-License-Identifier: GPL-3.0-or-later
"""Quadratic tetrahedra (issue 11 item 2): 10-node elements whose interface mid-edge nodes lie on the
true surfaces, in every format, checked from the files read back, independently of the package's
code: meshio (or a few lines of numpy for Medit's P2 keywords, which meshio 5.0 does not read), an
own Jacobian on a denser sample than the mesher's (a degree-4 lattice and Gauss points), an own
volume rule (a collapsed Gauss product, exact for the cubic det J), and gmsh's own reader and
Jacobian bounds (of the .msh and the .mesh alike)."""
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
CRITERIA = {"cell_size": 0.3, "facet_size": 0.3, "facet_distance": 0.02}
BALL = {"name": "ball", "type": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": 2}
SCENES = {
    "ball": {"domains": [BALL], "mesh": {"strategy": "None", "criteria": CRITERIA, "seed": 1}},
    # two materials: a ball inside a box
    "ball_in_box": {"domains": [BALL, {"name": "box", "type": "box", "bounds": [-1.5, 1.5] * 3, "material": 1}],
                    "mesh": {"strategy": "None", "criteria": CRITERIA, "seed": 1}},
    # a ball cut by a plane (the half-space behind its normal is cut away): a curved and a flat boundary
    # meeting at a circle
    "cut_ball": {"domains": [{"name": "cut", "type": "plane", "origin": [0, 0, 0.4], "normal": [0, 0, 1], "cut": True},
                             BALL],
                 "mesh": {"strategy": "None", "criteria": CRITERIA, "seed": 1}},
}
BALL_VOLUME = 4 / 3 * np.pi
CAP = np.pi * 0.6 ** 2 * (3 - 0.6) / 3  # the part of the ball above z = 0.4 (height 0.6)
EXACT = {"ball": {2: BALL_VOLUME}, "ball_in_box": {2: BALL_VOLUME, 1: 27 - BALL_VOLUME},
         "cut_ball": {2: CAP}}
EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # VTK / C3D10 mid-edge nodes 4..9


def run(*args):
    prefix = [COMMAND] if COMMAND else [sys.executable, "-m", "oraclemesh"]
    return subprocess.run(prefix + [str(a) for a in args], capture_output=True, encoding="utf-8", check=False)


def shape_gradients(l):
    """d N_i / d (l1, l2, l3) of the ten P2 shape functions at barycentric l (l0 = 1 - l1 - l2 - l3): [10, 3]."""
    g = np.zeros((10, 3))
    dl = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)  # d l_k / d (l1, l2, l3)
    for k in range(4):
        g[k] = (4 * l[k] - 1) * dl[k]
    for e, (i, j) in enumerate(EDGES):
        g[4 + e] = 4 * (l[i] * dl[j] + l[j] * dl[i])
    return g


def det_j(x, l):
    """det of d position / d (l1, l2, l3) of elements x [m, 10, 3] at l."""
    return np.linalg.det(np.einsum("ni,mnj->mji", shape_gradients(l), x))


def lattice(order):
    return [np.array([order - a - b - c, a, b, c]) / order
            for a in range(order + 1) for b in range(order + 1 - a) for c in range(order + 1 - a - b)]


GAUSS = [np.where(np.arange(4) == i, 0.5854101966249685, 0.1381966011250105) for i in range(4)]


def smallest_det_j(x):
    return np.min([det_j(x, l) for l in lattice(4) + GAUSS], axis=0)


def volumes(x):
    """Volume of each element: det J integrated by a 3x3x3 Gauss product in collapsed coordinates."""
    t, w = np.polynomial.legendre.leggauss(3)
    t, w = (t + 1) / 2, w / 2
    total = np.zeros(len(x))
    for u, wu in zip(t, w):
        for v, wv in zip(t, w):
            for s, ws in zip(t, w):
                l1, l2, l3 = u, (1 - u) * v, (1 - u) * (1 - v) * s
                total += wu * wv * ws * (1 - u) ** 2 * (1 - v) * det_j(x, [1 - l1 - l2 - l3, l1, l2, l3])
    return total


def read_medit_p2(path):
    """points, {keyword: rows} of an ASCII Medit file (comments skipped)."""
    with open(path) as f:
        tokens = " ".join(line for line in f if not line.startswith("#")).split()
    widths = {"Vertices": 4, "TrianglesP2": 7, "TetrahedraP2": 11}
    blocks, i = {}, 0
    while i < len(tokens):
        if tokens[i] in widths:
            n, w = int(tokens[i + 1]), widths[tokens[i]]
            blocks[tokens[i]] = np.array(tokens[i + 2:i + 2 + n * w], dtype=float).reshape(n, w)
            i += 2 + n * w
        else:
            i += 1
    return blocks["Vertices"][:, :3], blocks


class QuadraticScenes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.files, cls.linear, cls.results = {}, {}, {}
        for name, scene in SCENES.items():
            cls.linear[name] = om.mesh(scene)
            cls.results[name] = om.mesh(scene, element_order=2)
            paths = [os.path.join(cls.tmp.name, f"{name}{ext}") for ext in (".vtu", ".inp", ".msh", ".mesh")]
            cls.results[name].save(*paths)
            cls.files[name] = dict(zip((".vtu", ".inp", ".msh", ".mesh"), paths))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def read(self, name, ext):
        """(points, [m, 10] element nodes, material, [k, 6] surface triangles) of a written file."""
        import meshio

        path = self.files[name][ext]
        if ext == ".mesh":
            points, blocks = read_medit_p2(path)
            tets, tris = blocks["TetrahedraP2"], blocks["TrianglesP2"]
            return points, tets[:, :10].astype(int) - 1, tets[:, 10].astype(int), tris[:, :6].astype(int) - 1
        mesh = meshio.read(path)
        cells = mesh.cells_dict
        self.assertEqual(set(cells) - {"triangle6"}, {"tetra10"}, f"{path}: {set(cells)}")
        if ext == ".vtu":
            material = mesh.cell_data_dict["Material"]["tetra10"]
            tris = meshio.read(path.replace(".vtu", "_surfaces.vtu")).cells_dict["triangle6"]
            tris_points = meshio.read(path.replace(".vtu", "_surfaces.vtu")).points
            # the companion has its own numbering: map its points back by coordinates
            index = {tuple(p): i for i, p in enumerate(mesh.points.tolist())}
            tris = np.array([[index[tuple(tris_points[k])] for k in row] for row in tris.tolist()])
        elif ext == ".msh":
            material = mesh.cell_data_dict["gmsh:physical"]["tetra10"]
            tris = cells["triangle6"]
        else:
            material = np.zeros(len(cells["tetra10"]), dtype=int)
            for set_name, parts in mesh.cell_sets_dict.items():
                if "tetra10" in parts:
                    material[parts["tetra10"]] = {"BALL": 2, "BOX": 1}[set_name]
            tris = None
        return mesh.points, cells["tetra10"], material, tris

    def test_no_inverted_element_in_any_file(self):
        for name in SCENES:
            for ext in (".vtu", ".inp", ".msh", ".mesh"):
                with self.subTest(scene=name, format=ext):
                    points, nodes, _, _ = self.read(name, ext)
                    self.assertEqual(len(nodes), self.linear[name].quality["tets"])  # same tetrahedra, 10 nodes
                    self.assertGreater(smallest_det_j(points[nodes]).min(), 0.0)

    def test_interface_mid_nodes_lie_on_the_sphere(self):
        for name in SCENES:
            for ext in (".vtu", ".msh", ".mesh"):
                with self.subTest(scene=name, format=ext):
                    points, _, _, tris = self.read(name, ext)
                    corners = points[tris[:, :3]]
                    radius = np.linalg.norm(corners, axis=2)
                    on_sphere = (np.abs(radius - 1) < 1e-9).all(axis=1)  # triangles with corners on the sphere
                    self.assertGreater(on_sphere.sum(), 100)
                    curved, straight = [], []
                    for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
                        curved.append(np.abs(np.linalg.norm(points[tris[on_sphere, 3 + k]], axis=1) - 1))
                        straight.append(np.abs(np.linalg.norm((corners[on_sphere, i] + corners[on_sphere, j]) / 2,
                                                              axis=1) - 1))
                    curved, straight = np.concatenate(curved), np.concatenate(straight)
                    # most on the sphere; the few pulled back for validity lie between
                    self.assertGreater(np.mean(curved < 1e-9), 0.8, f"{np.mean(curved < 1e-9)}")
                    self.assertLess(curved.mean(), 0.1 * straight.mean())

    def test_volumes_are_closer_to_the_exact_ones(self):
        for name in SCENES:
            with self.subTest(scene=name):
                points, nodes, material, _ = self.read(name, ".msh")
                v = volumes(points[nodes])
                for m, exact in EXACT[name].items():
                    quadratic = v[material == m].sum()
                    linear = self.linear[name].quality["materials"][m]["volume"]
                    print(f"{name} material {m}: volume error linear {linear - exact:+.2e}, "
                          f"quadratic {quadratic - exact:+.2e}", file=sys.stderr)
                    self.assertLess(abs(quadratic - exact), 0.2 * abs(linear - exact))
                    # the report's volume (its own rule) agrees
                    self.assertAlmostEqual(self.results[name].quality["materials"][m]["volume"], quadratic, places=9)

    def test_abaqus_elements_are_c3d10_and_surfaces_keep_their_faces(self):
        with open(self.files["ball_in_box"][".inp"]) as f:
            text = f.read()
        self.assertEqual(re.findall(r"^\*ELEMENT, TYPE=(\S+)$", text, re.M), ["C3D10"])
        self.assertTrue("*SURFACE, NAME=BOX__BALL, TYPE=ELEMENT" in text, "no *SURFACE BOX__BALL")
        # each surface's *NSET holds its triangles' mid-edge nodes too
        import meshio

        mesh = meshio.read(self.files["ball_in_box"][".inp"])
        tris = self.results["ball_in_box"].surface_sets
        self.assertEqual(len(mesh.point_sets["BOX__BALL"]),
                         len(np.unique(self.read("ball_in_box", ".msh")[3][tris.select(0)])))

    def test_gmsh_reads_msh_and_mesh_cleanly_and_bounds_their_jacobians_above_zero(self):
        """gmsh reads the .msh and the Medit P2 .mesh (an independent reader of its node order): no
        warning, and its own (Bezier) bounds of det J over each whole element are positive and the
        same for both files."""
        gmsh = shutil.which("gmsh")
        self.assertIsNotNone(gmsh, "gmsh is not installed (scripts/setup-debian.sh installs it)")
        for name in SCENES:
            bounds = {}
            for ext in (".msh", ".mesh"):
                with self.subTest(scene=name, format=ext):
                    path = self.files[name][ext]
                    result = subprocess.run([gmsh, "-check", path], capture_output=True, encoding="utf-8",
                                            check=False)
                    output = result.stdout + result.stderr
                    self.assertEqual(result.returncode, 0, output)
                    self.assertNotRegex(output, r"(?i)warning|error", output)
                    script = os.path.join(self.tmp.name, f"{name}_jacobian.geo")
                    with open(script, "w") as f:
                        f.write(f'Merge "{path}";\nPlugin(AnalyseMeshQuality).JacobianDeterminant = 1;\n'
                                "Plugin(AnalyseMeshQuality).DimensionOfElements = 3;\n"
                                "Plugin(AnalyseMeshQuality).CreateView = 0;\nPlugin(AnalyseMeshQuality).Run;\n")
                    result = subprocess.run([gmsh, script, "-0", "-o", os.path.join(self.tmp.name, "unrolled.geo")],
                                            capture_output=True, encoding="utf-8", check=False)
                    output = result.stdout + result.stderr
                    found = re.search(r"minJ\s*=\s*(\S+),\s*(\S+),\s*(\S+)", output)
                    self.assertIsNotNone(found, output)
                    self.assertGreater(float(found.group(1)), 0.0, output)
                    bounds[ext] = found.groups()
            self.assertEqual(bounds[".msh"], bounds[".mesh"])

    def test_report_reads_every_format(self):
        for ext in (".vtu", ".inp", ".msh", ".mesh"):
            with self.subTest(format=ext):
                result = run("report", self.files["ball_in_box"][ext], "--no-png")
                self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
                self.assertRegex(result.stdout, r"\d+ 10-node tetrahedra")
                ratio = float(re.search(r"smallest Jacobian ratio (\S+)", result.stdout).group(1))
                self.assertGreater(ratio, 0.0)

    def test_statistics_and_report_of_the_made_mesh(self):
        stats = self.results["ball_in_box"].statistics
        self.assertGreater(stats["quadratic.snapped_nodes"], 0)
        self.assertGreaterEqual(stats["quadratic.min_jacobian_ratio"], 0.2 - 1e-12)
        self.assertIn("pulled back for validity", self.results["ball_in_box"].report)
        self.assertIn("time.quadratic", stats)


class Doors(unittest.TestCase):
    def test_command_line_and_scene_key_give_the_python_mesh(self):
        import json

        import meshio

        with tempfile.TemporaryDirectory() as tmp:
            scene = os.path.join(tmp, "ball.json")
            with open(scene, "w") as f:
                json.dump(SCENES["ball"], f)
            by_flag = os.path.join(tmp, "flag.msh")
            result = run("mesh", scene, "--order", 2, "-o", by_flag)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            keyed = dict(SCENES["ball"], mesh=dict(SCENES["ball"]["mesh"], element_order=2))
            by_key = om.mesh(keyed)
            by_key.save(os.path.join(tmp, "key.msh"))
            a, b = meshio.read(by_flag), meshio.read(os.path.join(tmp, "key.msh"))
            np.testing.assert_array_equal(a.points, b.points)
            np.testing.assert_array_equal(a.cells_dict["tetra10"], b.cells_dict["tetra10"])
            self.assertEqual(om.mesh(SCENES["ball"]).grid.GetCell(0).GetNumberOfPoints(), 4)  # default 1

    def test_bad_orders_are_named(self):
        bad = dict(SCENES["ball"], mesh=dict(SCENES["ball"]["mesh"], element_order=3))
        with self.assertRaisesRegex(om.OracleMeshError, r"element_order.*1 \(linear\) or 2"):
            om.mesh(bad)
        with self.assertRaisesRegex(om.OracleMeshError, r"element_order.*got 0"):
            om.mesh(SCENES["ball"], element_order=0)
        mesher = om.vtkFeaturePreservingTetrahedralizer()
        mesher.SetElementOrder(3)
        sphere = om.vtkSphereDomain()
        mesher.SetInputConnection(sphere.GetOutputPort())
        with self.assertRaisesRegex(om.OracleMeshError, "ElementOrder 3 is out of range"):
            om.update(mesher)


if __name__ == "__main__":
    unittest.main()
