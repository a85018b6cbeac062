# SPDX-License-Identifier: GPL-3.0-or-later
"""The ParaView plugin's server-manager XML (menus, documentation, property groups, widgets) and the
tetrahedralizer's per-material criteria table (AddMaterialCriteria / RemoveAllMaterialCriteria, the
methods behind the GUI table), without ParaView."""
import os
import unittest
import xml.etree.ElementTree as ET

import oraclemesh as om
from vtkmodules.util.numpy_support import vtk_to_numpy

XML = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Plugin", "OracleMesh", "OracleMesh.xml")
PROPERTY_TAGS = ("IntVectorProperty", "DoubleVectorProperty", "IdTypeVectorProperty", "StringVectorProperty",
                 "ProxyProperty", "InputProperty")


def all_proxies():
    root = ET.parse(XML).getroot()
    return {p.get("name"): p for group in root.findall("ProxyGroup") for p in group.findall("SourceProxy")}


def proxies():
    """The sources and filters of the menus (not the readers of File > Open)."""
    return {n: p for n, p in all_proxies().items() if p.find("Hints/ReaderFactory") is None}


def readers():
    return {n: p for n, p in all_proxies().items() if p.find("Hints/ReaderFactory") is not None}


class PluginXML(unittest.TestCase):
    def test_every_proxy_is_in_the_menu_with_a_label_and_documentation(self):
        for name, proxy in proxies().items():
            with self.subTest(proxy=name):
                self.assertTrue(proxy.get("label"), "no readable label")
                menu = proxy.find("Hints/ShowInMenu")
                self.assertIsNotNone(menu, "not in the Sources/Filters menus")
                self.assertEqual(menu.get("category"), "OracleMesh")
                doc = proxy.find("Documentation")
                self.assertTrue(doc is not None and doc.get("short_help") and doc.text.strip())

    def test_every_property_has_a_tooltip_and_sits_in_a_group(self):
        for name, proxy in proxies().items():
            grouped = {p.get("name") for g in proxy.findall("PropertyGroup") for p in g.findall("Property")}
            for prop in proxy:
                if prop.tag not in PROPERTY_TAGS or prop.get("is_internal") == "1":
                    continue
                with self.subTest(proxy=name, property=prop.get("name")):
                    doc = prop.find("Documentation")
                    self.assertTrue(doc is not None and doc.text and doc.text.strip(), "no tooltip")
                    # inputs and shapes are shown on their own; every other property in a group
                    if prop.tag not in ("InputProperty", "ProxyProperty"):
                        self.assertIn(prop.get("name"), grouped, "in no property group")

    def test_validity_check_proxy_matches_the_class(self):
        check = proxies()["OracleMeshValidityCheck"]
        self.assertEqual(check.get("class"), "vtkMeshValidityCheck")
        instance = om.vtkMeshValidityCheck()
        for prop in check.findall("DoubleVectorProperty"):
            with self.subTest(property=prop.get("name")):
                self.assertAlmostEqual(float(prop.get("default_values")), getattr(instance, "Get" + prop.get("name"))())

    def test_tetrahedralizer_groups_defaults_and_display_hints(self):
        mesher = proxies()["OracleMeshTetrahedralizer"]
        groups = [g.get("label") for g in mesher.findall("PropertyGroup")]
        for label in ("Size criteria", "Shape criteria", "Features", "Optimisation", "Advanced"):
            self.assertIn(label, groups)
        for prop in ("CellSize", "FacetSize", "FacetDistance"):
            # the C++ default (0 = no bound), not one scaled from the input's bounds (which gave
            # -1e298 in pvpython before the input was updated, and a different mesh than the CLI)
            self.assertIsNone(mesher.find(f"DoubleVectorProperty[@name='{prop}']/BoundsDomain"))
        hints = mesher.find("Hints")
        self.assertEqual(hints.find("RepresentationType[@port='0']").get("type"), "Surface With Edges")
        self.assertEqual({v.get("port") for v in hints.findall("View") if v.get("type") == "None"}, {"1", "2"})
        table = mesher.find("DoubleVectorProperty[@name='MaterialCriteria']")
        self.assertEqual((table.get("command"), table.get("clean_command"), table.get("repeat_command"),
                          table.get("number_of_elements_per_command")),
                         ("AddMaterialCriteria", "RemoveAllMaterialCriteria", "1", "7"))
        self.assertEqual(len(table.findall("Hints/ShowComponentLabels/ComponentLabel")), 7)

    def test_default_values_are_the_cxx_defaults(self):
        """Every property's default_values (a base proxy's too) equals what the getter of a fresh
        object of the proxy's VTK class returns: the C++ is the one source of the defaults."""
        root = ET.parse(XML).getroot()
        bases = {(g.get("name"), p.get("name")): p for g in root.findall("ProxyGroup") for p in g.findall("Proxy")}
        checked = 0
        for name, proxy in proxies().items():
            instance = getattr(om, proxy.get("class"))()
            props = list(proxy)
            if proxy.get("base_proxyname"):
                props += list(bases[(proxy.get("base_proxygroup"), proxy.get("base_proxyname"))])
            for prop in props:
                command, default = prop.get("command", ""), prop.get("default_values")
                if prop.tag not in PROPERTY_TAGS or default is None or not command.startswith("Set") \
                        or prop.get("repeat_command") == "1" or not hasattr(instance, "Get" + command[3:]):
                    continue
                with self.subTest(proxy=name, property=prop.get("name")):
                    value = getattr(instance, "Get" + command[3:])()
                    if prop.tag == "StringVectorProperty":
                        self.assertEqual(default, value)
                        continue
                    expected = [float(v) for v in default.split()]
                    actual = [float(v) for v in (value if isinstance(value, (tuple, list)) else [value])]
                    self.assertEqual(expected, actual)
                    checked += 1
        # the tetrahedralizer's criteria, strategy, optimiser, sliver angles, seed and budget; every
        # domain's cut and criteria
        self.assertGreater(checked, 40)

    def test_domain_criteria_are_one_base_proxy(self):
        root = ET.parse(XML).getroot()
        domains = [p for p in proxies().values() if p.get("class").endswith("Domain")]
        self.assertEqual(len(domains), 4)
        for proxy in domains:
            self.assertEqual((proxy.get("base_proxygroup"), proxy.get("base_proxyname")),
                             ("oraclemesh_bases", "DomainCriteria"))
            self.assertIsNone(proxy.find("DoubleVectorProperty[@name='FacetSize']"), "criteria repeated")
        self.assertEqual(len(root.findall(".//DoubleVectorProperty[@name='CellRadiusEdgeRatio']")), 2)

    def test_domains_have_the_3d_widgets(self):
        p = proxies()
        self.assertEqual([g.get("panel_widget") for g in p["OracleMeshSphereDomain"].findall("PropertyGroup")
                          if g.get("panel_widget")], ["InteractiveSphere"])
        shapes = [x.get("name") for x in
                  p["OracleMeshImplicitDomain"].findall("ProxyProperty/ProxyListDomain/Proxy")]
        self.assertEqual(shapes, ["Plane", "Box", "Sphere", "Cylinder"])  # ParaView's widget-backed functions
        for name in ("OracleMeshSurfaceDomain", "OracleMeshLabelMapDomain", "OracleMeshSphereDomain",
                     "OracleMeshImplicitDomain"):
            self.assertIn("Domain", [g.get("label") for g in p[name].findall("PropertyGroup")])

    def test_the_label_map_reader_is_the_command_lines(self):
        """File > Open: one reader proxy for the label-map formats the command line reads (but .vti,
        which ParaView reads itself), backed by the Python class embedded in the plugin."""
        import importlib.util

        from oraclemesh.readers import LABEL_MAP_EXTENSIONS, SPACES

        self.assertEqual(list(readers()), ["OracleMeshLabelMapReader"])
        reader = readers()["OracleMeshLabelMapReader"]
        expected = [e.lstrip(".") for e in LABEL_MAP_EXTENSIONS if e != ".vti"]
        self.assertEqual(reader.find("Hints/ReaderFactory").get("extensions").split(), expected)
        self.assertEqual(reader.find("StringVectorProperty[@name='FileName']/Hints/FileChooser")
                         .get("extensions").split(), expected)
        self.assertEqual(reader.get("si_class"), "vtkSIPythonSourceProxy")
        self.assertTrue(reader.get("label") and reader.find("Documentation").text.strip())
        module_name, _, class_name = reader.get("class").partition(".")
        path = os.path.join(os.path.dirname(XML), module_name + ".py")
        spec = importlib.util.spec_from_file_location(module_name, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        instance = getattr(module, class_name)()
        for prop in reader:
            if prop.tag in PROPERTY_TAGS:
                with self.subTest(property=prop.get("name")):
                    self.assertTrue(prop.find("Documentation").text.strip(), "no tooltip")
                    self.assertTrue(callable(getattr(instance, prop.get("command"))))
        space = reader.find("IntVectorProperty[@name='Space']")
        entries = {int(e.get("value")): e.get("text") for e in space.findall("EnumerationDomain/Entry")}
        self.assertEqual([entries[i] for i in sorted(entries)], list(module.SPACES))
        self.assertEqual(list(module.SPACES), list(SPACES))
        self.assertEqual(entries[int(space.get("default_values"))], "LPS")  # as scene files


def two_balls():
    """Material 2 (radius 0.5) inside material 1 (radius 1)."""
    inner, outer = om.vtkSphereDomain(), om.vtkSphereDomain()
    inner.SetRadius(0.5)
    inner.SetMaterialId(2)
    outer.SetRadius(1.0)
    outer.SetMaterialId(1)
    oracle = om.vtkHierarchicalOracle()
    oracle.AddInputConnection(inner.GetOutputPort())
    oracle.AddInputConnection(outer.GetOutputPort())
    mesher = om.vtkFeaturePreservingTetrahedralizer()
    mesher.SetInputConnection(oracle.GetOutputPort())
    mesher.SetFeatureStrategyToNone()
    mesher.SetCellSize(0.4)
    mesher.SetFacetSize(0.4)
    mesher.SetFacetDistance(0.05)
    mesher.SetSeed(3)
    mesher._keep = (inner, outer, oracle)
    return mesher


def mean_tet_volume(grid, material):
    stats = grid.GetFieldData()
    names = stats.GetAbstractArray("StatisticNames")
    values = stats.GetArray("StatisticValues")
    volume = {names.GetValue(i): values.GetValue(i) for i in range(names.GetNumberOfValues())}[
        f"volume.material_{material}"]
    count = int((vtk_to_numpy(grid.GetCellData().GetArray("Material")) == material).sum())
    return volume / count


class MaterialCriteriaTable(unittest.TestCase):
    def test_a_table_row_is_the_same_as_set_material_criteria(self):
        by_table, by_call = two_balls(), two_balls()
        by_table.AddMaterialCriteria(2.0, -1, -1, -1, 0.1, -1, -1)
        by_call.SetMaterialCriteria(2, -1, -1, -1, 0.1, -1, -1)
        a, b = om.update(by_table), om.update(by_call)
        self.assertEqual(a.GetNumberOfCells(), b.GetNumberOfCells())
        self.assertEqual(vtk_to_numpy(a.GetPoints().GetData()).tolist(), vtk_to_numpy(b.GetPoints().GetData()).tolist())
        # the row acts: material 2's tetrahedra are much smaller than material 1's
        self.assertLess(mean_tet_volume(a, 2), 0.3 * mean_tet_volume(a, 1))

    def test_clearing_the_table_restores_the_global_criteria(self):
        mesher = two_balls()
        plain = om.update(mesher).GetNumberOfCells()
        mesher.AddMaterialCriteria(2.0, -1, -1, -1, 0.1, -1, -1)
        self.assertGreater(om.update(mesher).GetNumberOfCells(), plain)
        mesher.RemoveAllMaterialCriteria()
        self.assertEqual(om.update(mesher).GetNumberOfCells(), plain)

    def test_bad_rows_are_named(self):
        mesher = two_balls()
        mesher.AddMaterialCriteria(1.0, -1, -1, -1, 0.3, -1, -1)
        mesher.AddMaterialCriteria(2.5, -1, -1, -1, 0.3, -1, -1)
        with self.assertRaisesRegex(om.OracleMeshError, r"row 2: the material id must be an integer >= 0, got 2\.5"):
            om.update(mesher)
        mesher.RemoveAllMaterialCriteria()
        mesher.AddMaterialCriteria(2.0, -1, -1, -1, 0.3, -1, -1)
        mesher.AddMaterialCriteria(2.0, -1, -1, -1, 0.2, -1, -1)
        with self.assertRaisesRegex(om.OracleMeshError, "row 2: material 2 is listed twice"):
            om.update(mesher)
        mesher.RemoveAllMaterialCriteria()
        mesher.AddMaterialCriteria(-1.0, -1, -1, -1, 0.3, -1, -1)
        with self.assertRaisesRegex(om.OracleMeshError, "row 1: the material id must be an integer >= 0"):
            om.update(mesher)
        mesher.RemoveAllMaterialCriteria()  # a clean table meshes again
        self.assertGreater(om.update(mesher).GetNumberOfCells(), 0)


if __name__ == "__main__":
    unittest.main()
