# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the pipeline of a scene file (Data/demo/scene.json) from the OracleMesh plugin's ParaView
proxies, and writes the ParaView state Data/demo_scene.pvsm of the demo scene:

    pvpython Data/make_demo_state.py build/lib/paraview-plugins/OracleMesh/OracleMesh.so

The state names its data files relative to Data/ ("demo/implant.vtp"): load it with the data
directory option (GUI: File > Load State, "Search files under specified directory" = Data/;
pvpython: LoadState("Data/demo_scene.pvsm", data_directory="Data")) or from inside Data/.
The plugin must be loaded first.

Importable from pvpython: build_pipeline(scene_file) returns the proxies by name (one per scene
domain and its reader, "Oracle", "Feature Edges", "Tetrahedralizer"), the plugin loaded with
paraview.simple.LoadPlugin(path) (no ns argument: the constructors go to paraview.simple)."""
import json
import os
import sys

# Scene keys (the command line's "mesh" block) -> tetrahedralizer properties, in the order of the
# per-material table's columns. A key the scene leaves out is not set: the proxy's default (the
# XML's, checked equal to the C++'s by Testing/Python/test_plugin.py) applies, as in the command line.
CRITERIA = [("facet_angle", "FacetAngle"), ("facet_size", "FacetSize"), ("facet_distance", "FacetDistance"),
            ("cell_size", "CellSize"), ("cell_radius_edge_ratio", "CellRadiusEdgeRatio"), ("edge_size", "EdgeSize")]
MESH_PROPERTIES = {"perturb": "Perturb", "exude": "Exude", "sliver_angle": "SliverAngle",
                   "interface_sliver_angle": "InterfaceSliverAngle", "picking_sliver_angle": "PickingSliverAngle",
                   "perturbation_failures_per_bound": "PerturbationFailuresPerBound",
                   "exudation_sliver_bound": "ExudationSliverBound",
                   "perturbation_steps_per_vertex": "PerturbationStepsPerVertex",
                   "exudation_steps_per_cell": "ExudationStepsPerCell",
                   "optimisation_time_limit": "OptimisationTimeLimit", "seed": "Seed",
                   "maximum_number_of_vertices": "MaximumNumberOfVertices", "time_limit": "TimeLimit",
                   "element_order": "ElementOrder", "threads": "Threads"}
STRATEGIES = {"Conforming": "Conforming", "None": "None", "ProtectingBalls": "Protecting Balls"}
UNSET = -1.0  # a criterion not set in a domain or a table row (the core's std::nullopt)


def material_criteria_rows(materials):
    """The scene's per-material overrides as the flat 7-column table of the MaterialCriteria
    property (material id, then the six criteria, -1 = keep the global value)."""
    rows = []
    for material in sorted(materials, key=int):
        overrides = materials[material]
        unknown = set(overrides) - {key for key, _ in CRITERIA}
        if unknown:
            raise ValueError(f"$.mesh.materials.{material}: unknown criteria {sorted(unknown)}")
        rows += [float(int(material))] + [float(overrides.get(key, UNSET)) for key, _ in CRITERIA]
    return rows


def build_pipeline(scene_file, file_prefix=None):
    """Creates the proxies of the scene (the plugin must be loaded). Data files are named
    os.path.join(file_prefix, file); file_prefix defaults to the scene's folder."""
    from paraview import simple as pv

    with open(scene_file) as f:
        scene = json.load(f)
    if file_prefix is None:
        file_prefix = os.path.dirname(os.path.abspath(scene_file))
    proxies, domains, readers = {}, [], {}
    for d in scene["domains"]:
        name, kind = d["name"], d["type"]
        if kind in ("surface", "labelmap"):
            reader = pv.OpenDataFile(os.path.join(file_prefix, d["file"]))
            if reader is None:
                raise ValueError(f"no ParaView reader for {d['file']!r} (domain {name!r})")
            pv.RenameSource(d["file"], reader)
            proxies[d["file"]] = readers[name] = reader
        if kind == "surface":
            domain = pv.SurfaceDomain(Input=reader)
            if "inside_test" in d:  # else the filter's default (automatic)
                domain.InsideTest = {"automatic": "Automatic", "closed": "Closed",
                                     "winding_number": "Winding Number"}[d["inside_test"]]
            domain.AllowSelfIntersections = int(bool(d.get("allow_self_intersections", False)))
        elif kind == "labelmap":
            domain = pv.LabelMapDomain(Input=reader)
            if "array" in d:
                association = "CELLS" if d.get("association") == "cell" else "POINTS"
                domain.LabelArray = [association, d["array"]]
            else:  # the filter picks the one integer array (and names them when several leave it open)
                domain.LabelArray = ["POINTS", ""]
            if "background" in d:
                domain.BackgroundLabel = int(d["background"])
            if "interpolation" in d:
                domain.Interpolation = {"nearest": "Nearest voxel", "trilinear": "Trilinear"}[d["interpolation"]]
            domain.DomainName = name
            domain.LabelNames = [x for label, text in sorted(d.get("label_names", {}).items())
                                 for x in (str(label), text)]
        elif kind == "sphere":
            domain = pv.SphereDomain(Center=d["center"], Radius=d["radius"])
        elif kind in ("plane", "box", "cylinder"):
            domain = pv.ImplicitDomain()
            domain.Shape = kind.capitalize()
            if kind == "plane":
                domain.Shape.Origin, domain.Shape.Normal = d["origin"], d["normal"]
            elif kind == "box":
                b = d["bounds"]
                domain.Shape.Position = [b[0], b[2], b[4]]
                domain.Shape.Length = [b[1] - b[0], b[3] - b[2], b[5] - b[4]]
            else:
                domain.Shape.Center, domain.Shape.Axis = d["center"], d["axis"]
                domain.Shape.Radius = d["radius"]
                domain.Height = d.get("height", 0.0)
        else:
            raise ValueError(f"domain {name!r}: unknown type {kind!r}")
        if kind != "labelmap":
            if "material" in d:
                domain.MaterialId = int(d["material"])
            domain.MaterialName = name
        if "cut" in d:
            domain.Cut = int(bool(d["cut"]))
        for key, prop in CRITERIA:  # the domain's own criteria (the core merges them)
            if key in d.get("criteria", {}):
                setattr(domain, prop, float(d["criteria"][key]))
        pv.RenameSource(name, domain)
        proxies[name] = domain
        domains.append(domain)

    oracle = pv.HierarchicalOracle(Input=domains)  # connection order = priority
    pv.RenameSource("Oracle", oracle)
    proxies["Oracle"] = oracle

    spec = scene.get("mesh", {})
    mesher = pv.FeaturePreservingTetrahedralizer(Input=oracle)
    features = spec.get("features")
    if features:
        if "feature_angle" in features:  # one angle: the sharp edges below and the creases Automatic finds
            mesher.CreaseAngle = float(features["feature_angle"])
        surfaces = features["from_surface"]
        surfaces = [surfaces] if isinstance(surfaces, str) else surfaces
        parts = [readers[s] for s in surfaces]
        edges = pv.FeatureEdges(Input=parts[0] if len(parts) == 1 else pv.AppendGeometry(Input=parts))
        edges.BoundaryEdges = edges.NonManifoldEdges = edges.ManifoldEdges = 0
        edges.FeatureEdges = 1
        edges.FeatureAngle = mesher.CreaseAngle  # the C++ default when the scene gives none
        pv.RenameSource("Feature Edges", edges)
        proxies["Feature Edges"] = edges
        mesher.FeatureLines = edges
        # as scene files do: sharp edges found on a surface are resampled unless the scene says not to
        mesher.ResampleFeatureLines = int(features.get("resample", True))
    if "strategy" in spec:
        mesher.FeatureStrategy = STRATEGIES[spec["strategy"]]
    criteria = spec.get("criteria", {})
    for key, prop in CRITERIA:
        if key in criteria:
            setattr(mesher, prop, float(criteria[key]))
    mesher.MaterialCriteria = material_criteria_rows(spec.get("materials", {}))
    for key, prop in MESH_PROPERTIES.items():
        if key in spec:
            value = spec[key]
            setattr(mesher, prop, int(value) if isinstance(value, (bool, int)) else float(value))
    pv.RenameSource("Tetrahedralizer", mesher)
    proxies["Tetrahedralizer"] = mesher
    return proxies, scene


def material_names(scene):
    """Material id -> name, from the scene's domains."""
    names = {}
    for d in scene["domains"]:
        if d["type"] == "labelmap":
            names.update({int(k): v for k, v in d.get("label_names", {}).items()})
        elif not d.get("cut", False):
            names[int(d.get("material", 1))] = d["name"]
    return names


def show_demo(proxies, scene):
    """The view of the state: the mesh cut open through the screw (whole tetrahedra), its edges
    drawn, coloured by material with the materials' names."""
    from paraview import simple as pv

    cut = pv.Clip(Input=proxies["Tetrahedralizer"])
    cut.ClipType = "Plane"
    cut.ClipType.Origin = [0.0, -14.0, 0.0]
    cut.ClipType.Normal = [0.0, -1.0, 0.0]
    cut.Crinkleclip = 1
    pv.RenameSource("Cut through the screw", cut)
    view = pv.CreateView("RenderView")
    view.ViewSize = [1000, 750]
    view.OrientationAxesVisibility = 1
    display = pv.Show(cut, view)
    display.SetRepresentationType("Surface With Edges")
    display.EdgeColor = [0.25, 0.25, 0.25]
    pv.ColorBy(display, ("CELLS", "Material"))
    lut = pv.GetColorTransferFunction("Material")
    lut.InterpretValuesAsCategories = 1
    names = material_names(scene)
    lut.Annotations = [x for m in sorted(names) for x in (str(m), f"{m}: {names[m]}")]
    lut.ApplyPreset("Brewer Qualitative Set1", True)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = "Material", ""
    bar.TitleFontSize = bar.LabelFontSize = 12
    view.CameraPosition = [-160.0, -260.0, 140.0]
    view.CameraFocalPoint = [0.0, 0.0, 50.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    pv.AssignViewToLayout(view)
    return view


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    from paraview import simple as pv

    plugin = os.path.abspath(argv[1])
    data = os.path.dirname(os.path.abspath(__file__))
    output = os.path.abspath(argv[2]) if len(argv) > 2 else os.path.join(data, "demo_scene.pvsm")
    pv.LoadPlugin(plugin, remote=False)  # adds the constructors to paraview.simple
    os.chdir(data)  # the state names its files relative to Data/
    proxies, scene = build_pipeline(os.path.join("demo", "scene.json"), file_prefix="demo")
    view = show_demo(proxies, scene)
    view.ResetCamera()  # data bounds from the readers only: the mesh is not computed here
    pv.SaveState(output)
    print(f"wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
