# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene files: a JSON description of the oracle's domains in priority order, turned into a VTK
pipeline (readers -> domain algorithms -> vtkHierarchicalOracle), plus how to mesh it and where to
write the results (the README's "Scene files" section documents every key):

    {"space": "LPS",
     "domains": [
       {"name": "implant", "type": "surface", "file": "implant.vtp", "material": 3,
        "criteria": {"cell_size": 1}},
       {"name": "screw", "type": "cylinder", "center": [x, y, z], "axis": [ax, ay, az],
        "radius": 2.5, "height": 34, "material": 4},
       {"name": "resection", "type": "plane", "origin": [...], "normal": [...], "cut": true},
       {"name": "tibia", "type": "labelmap", "file": "labels.nii.gz", "array": "labels",
        "background": 0, "label_names": {"1": "cortical bone"}},
       {"name": "ball", "type": "sphere", "center": [...], "radius": 5, "material": 5},
       {"name": "block", "type": "box", "bounds": [xmin, xmax, ymin, ymax, zmin, zmax], "material": 6}],
     "mesh": {"strategy": "Conforming", "criteria": {...}, "materials": {"3": {...}},
              "features": {"use": "Both", "from_surface": "implant", "feature_angle": 60, "files": [...]},
              "seed": 1, "maximum_number_of_vertices": 200000, "time_limit": 600, "threads": 1},
     "outputs": {"mesh": ["out.vtu", "out.inp"], "report": "report.txt", "histogram": "dihedral.png"},
     "reference_volumes": {"5": 523.6}}

The first domain has the highest priority. Relative file paths resolve against the scene file.
Every problem found is reported at once, each with its JSON path.

A key left out keeps the VTK filter's default (defaults.py reads them from the C++, their one
source). Criteria merge in the core (MeshCriteria.h): "mesh.criteria" < a domain's "criteria" (for
each material of the domain) < "mesh.materials"; two domains giving one material different values
fail the meshing with the core's error, the same at every door.
"""
import json
import math
import os

from .defaults import CRITERIA_KEYS, FEATURE_SOURCES, STRATEGIES, cut_default  # noqa: F401 (re-exported)
from .errors import OracleMeshError
from .readers import SPACES, label_map_frame, label_map_reader, surface_frame, surface_reader

DOMAIN_TYPES = ("surface", "labelmap", "sphere", "plane", "box", "cylinder")
COMMON_KEYS = {"name", "type", "material", "cut", "criteria", "comment"}
DOMAIN_KEYS = {
    "surface": {"file", "inside_test", "allow_self_intersections", "merge_tolerance"},
    "labelmap": {"file", "array", "association", "background", "label_names", "interpolation"},
    "sphere": {"center", "radius"},
    "plane": {"origin", "normal"},
    "box": {"bounds"},
    "cylinder": {"center", "axis", "radius", "height"},
}
TOP_KEYS = {"description", "comment", "space", "domains", "mesh", "outputs", "reference_volumes"}
MESH_KEYS = {"strategy", "criteria", "materials", "features", "seed", "maximum_number_of_vertices", "comment",
             "perturb", "exude", "sliver_angle", "interface_sliver_angle", "picking_sliver_angle",
             "perturbation_steps_per_vertex",
             "exudation_steps_per_cell", "optimisation_time_limit", "perturbation_failures_per_bound",
             "exudation_sliver_bound", "time_limit", "element_order", "threads",
             "improve_angles", "improvement_min_angle", "improvement_max_angle"}
FEATURE_KEYS = {"use", "from_surface", "feature_angle", "files", "resample", "comment"}
OUTPUT_KEYS = {"mesh", "report", "histogram", "comment"}
INT_MIN, INT_MAX = -2**31, 2**31 - 1  # the C int of material ids, labels and the seed
ID_MAX = 2**63 - 1  # vtkIdType: the vertex budget


class Scene:
    """The pipeline built from a scene: ``domains`` (algorithms, priority order, each with its own
    criteria set), ``readers`` and ``oracle`` (a vtkHierarchicalOracle); ``mesh`` (the validated
    "mesh" block: only the keys the scene gives; criteria, materials {id: {criterion: value}},
    features, ...), ``outputs`` (absolute paths) and ``domain_criteria`` [(domain index,
    {criterion: value})]."""

    def __init__(self, description, base_dir):
        self.description = description
        self.base_dir = base_dir
        self.readers = []
        self.domains = []
        self.oracle = None
        self.mesh = {}
        self.outputs = {}
        self.domain_criteria = []
        self.feature_readers = []
        self.feature_edge_sizes = []  # per feature file: its "edge_size" (None: the lines' own, else the materials')
        self.reference_volumes = {}
        self.source = "scene"
        self.space = "LPS"
        self.frames = []  # (domain name, "surface" or "labelmap", the frame its file declares or None)

    def path(self, file):
        """A scene path: relative ones resolve against the scene file's folder."""
        return file if os.path.isabs(file) else os.path.join(self.base_dir, file)

    def input_warnings(self):
        """Warnings about the inputs' frames that the files make known: a surface whose file declares
        an anatomical frame (3D Slicer's "SPACE=LPS/RAS" header) other than the one the label maps
        with a frame are placed in (the scene's "space"), or surfaces declaring different frames."""
        surfaces = [(name, frame) for name, kind, frame in self.frames if kind == "surface" and frame]
        maps = [(name, frame) for name, kind, frame in self.frames if kind == "labelmap" and frame]
        warnings = []
        if maps:
            placed = ", ".join(f"{name} ({frame} file)" for name, frame in maps)
            for name, frame in surfaces:
                if frame != self.space:
                    warnings.append(f"inputs: surface {name} declares SPACE={frame} in its file, but the label "
                                    f"maps {placed} are placed in the scene's space {self.space}: their "
                                    f"orientations differ (x and y mirrored); set \"space\": \"{frame}\" "
                                    "if the surfaces are right")
        if len({frame for _, frame in surfaces}) > 1:
            listed = ", ".join(f"{name} ({frame})" for name, frame in surfaces)
            warnings.append(f"inputs: the surfaces declare different frames in their files: {listed}; "
                            "surfaces are used as they are, so they are mirrored against each other")
        return warnings

    def material_names(self):
        """{material id: name} from the scene's domains (cut domains have no material)."""
        names = {}
        for spec in self.description["domains"]:
            if spec.get("cut"):
                continue
            if spec["type"] == "labelmap":
                for label, name in spec.get("label_names", {}).items():
                    names.setdefault(int(label), name)
            elif "material" in spec:
                names.setdefault(int(spec["material"]), spec.get("name", spec["type"]))
        return names


class _Problems:
    def __init__(self):
        self.items = []

    def add(self, path, text):
        self.items.append(f"{path}: {text}")


def _vector(problems, spec, path, key, n, required=True, default=None):
    value = spec.get(key, default)
    if value is None:
        if required:
            problems.add(f"{path}.{key}", f"missing (a list of {n} numbers)")
        return None
    if (not isinstance(value, (list, tuple)) or len(value) != n
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)):
        problems.add(f"{path}.{key}", f"must be a list of {n} finite numbers, got {value!r}")
        return None
    return [float(v) for v in value]


def _number(problems, spec, path, key, positive=False, required=True, default=None, integer=False,
            low=INT_MIN, high=INT_MAX):
    """A validated number (None when missing or bad); integers must lie in [low, high]: the C types
    the values go to (int, or vtkIdType for the vertex budget)."""
    value = spec.get(key, default)
    if value is None:
        if required:
            problems.add(f"{path}.{key}", "missing")
        return None
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if ok and integer and int(value) != value:
        ok = False
    if not ok or (positive and value <= 0):
        kind = "integer" if integer else "number"
        article = "a positive" if positive else ("an" if integer else "a")
        problems.add(f"{path}.{key}", f"must be {article} {kind}, got {value!r}")
        return None
    if integer and not low <= value <= high:
        problems.add(f"{path}.{key}", f"{int(value)} is out of range (an integer from {low} to {high})")
        return None
    return int(value) if integer else float(value)


def _integer_key(problems, key, path, low=0, high=INT_MAX, what="material id"):
    """An object key that must be an integer in [low, high] (material ids, labels), or None."""
    try:
        value = int(key)
    except ValueError:
        problems.add(path, f"key must be an integer {what}")
        return None
    if not low <= value <= high:
        problems.add(path, f"{what} {value} is out of range (an integer from {low} to {high})")
        return None
    return value


def set_mesh_keys(description, settings, source="scene"):
    """Sets keys of a scene description's "mesh" block in place: `settings` {dotted key: value},
    e.g. {"criteria.cell_size": 2, "strategy": "None", "materials.3.cell_size": 1} (the command
    line's ``mesh --set``, a study's sweep). The scene's validation then checks the values."""
    if not isinstance(description, dict):
        return description
    for key, value in settings.items():
        parts = [p for p in str(key).split(".")]
        if not all(parts):
            raise OracleMeshError(f"{source}: mesh key {key!r}: empty part (use e.g. criteria.cell_size)")
        if parts[0] not in MESH_KEYS or parts[0] == "comment":
            raise OracleMeshError(f"{source}: mesh key {key!r}: {parts[0]!r} is not a key of the mesh block "
                                  f"(use {', '.join(sorted(MESH_KEYS - {'comment'}))})")
        block = description.setdefault("mesh", {})
        where = "$.mesh"
        for part in parts[:-1]:
            if not isinstance(block, dict):
                raise OracleMeshError(f"{source}: mesh key {key!r}: {where} is not an object")
            if where == "$.mesh" and part == "features" and isinstance(block.get(part), str):
                block[part] = {"use": block[part]}  # the short form "features": "Automatic"
            block = block.setdefault(part, {})
            where += "." + part
        if not isinstance(block, dict):
            raise OracleMeshError(f"{source}: mesh key {key!r}: {where} is not an object")
        block[parts[-1]] = value
    return description


def load_scene(path, mesh_settings=None):
    """Reads and validates a scene file; returns a Scene whose pipeline is built but not run.
    `mesh_settings` {dotted key: value} overrides keys of its "mesh" block (see set_mesh_keys).
    Raises OracleMeshError listing every problem with its JSON path."""
    try:
        with open(path, encoding="utf-8") as f:
            description = json.load(f)
    except FileNotFoundError:
        raise OracleMeshError(f"{path}: scene file not found") from None
    except IsADirectoryError:
        raise OracleMeshError(f"{path}: is a folder, not a scene file (JSON)") from None
    except PermissionError:
        raise OracleMeshError(f"{path}: the scene file cannot be read (permission denied)") from None
    except UnicodeDecodeError as e:
        raise OracleMeshError(f"{path}: not a scene file: a binary file, not UTF-8 JSON text "
                              f"(byte 0x{e.object[e.start]:02x} at offset {e.start})") from None
    except json.JSONDecodeError as e:
        raise OracleMeshError(f"{path}: not valid JSON: {e}") from None
    except RecursionError:
        raise OracleMeshError(f"{path}: not a scene file: JSON nested too deeply") from None
    except OSError as e:
        raise OracleMeshError(f"{path}: the scene file cannot be read ({e.strerror or e})") from None
    if mesh_settings:
        set_mesh_keys(description, mesh_settings, path)
    return build_scene(description, os.path.dirname(os.path.abspath(path)), source=path)


def _criteria(problems, value, path):
    """A validated {criterion: float} from a "criteria" object, or {}."""
    if not isinstance(value, dict):
        problems.add(path, f"must be an object {{criterion: number}} with criteria from {', '.join(CRITERIA_KEYS)}")
        return {}
    out = {}
    for key in value:
        if key not in CRITERIA_KEYS:
            problems.add(f"{path}.{key}", f"unknown criterion (use {', '.join(CRITERIA_KEYS)})")
            continue
        if value[key] is None or (value[key] == -1 and not isinstance(value[key], bool)):
            continue  # not set: the less specific level's value counts (MeshCriteria.h)
        number = _number(problems, value, path, key)
        if number is not None and number < 0:
            problems.add(f"{path}.{key}", f"must be >= 0 (0: no bound; null or -1: not set), got {value[key]!r}")
        elif number is not None:
            out[key] = number
    return out


def _unknown_keys(problems, spec, path, allowed):
    for key in spec:
        if key not in allowed and not str(key).startswith("_"):
            problems.add(f"{path}.{key}", f"unknown key (use {', '.join(sorted(allowed))})")


def _paths(problems, value, path, scene):
    """A list of absolute paths from a string or a list of strings, or []."""
    items = [value] if isinstance(value, str) else value
    if not isinstance(items, list) or not items or not all(isinstance(v, str) and v for v in items):
        problems.add(path, f"must be a file name or a list of file names, got {value!r}")
        return []
    return [scene.path(v) for v in items]


FEATURE_FILE_KEYS = {"file", "edge_size", "comment"}


def _feature_files(problems, value, scene):
    """[(absolute path, edge size or None)] from "features.files": a file name, or a list of file names
    and {"file": name, "edge_size": number} entries (the per-feature level of the edge size: it
    wins over the materials' and the global one, MeshCriteria.h)."""
    path = "$.mesh.features.files"
    items = [value] if isinstance(value, (str, dict)) else value
    if not isinstance(items, list) or not items:
        problems.add(path, f"must be a file name, a {{\"file\": ..., \"edge_size\": ...}} entry or a list of them, "
                           f"got {value!r}")
        return []
    out = []
    for k, item in enumerate(items):
        where = path + (f"[{k}]" if isinstance(value, list) else "")
        if isinstance(item, str) and item:
            out.append((scene.path(item), None))
        elif isinstance(item, dict):
            _unknown_keys(problems, item, where, FEATURE_FILE_KEYS)
            file = item.get("file")
            if not isinstance(file, str) or not file:
                problems.add(f"{where}.file", f"must be a file name, got {file!r}")
                continue
            edge_size = None
            if item.get("edge_size") is not None and item["edge_size"] != -1:
                edge_size = _number(problems, item, where, "edge_size")
                if edge_size is not None and edge_size < 0:
                    problems.add(f"{where}.edge_size",
                                 f"must be a number >= 0 (0: no bound; null or -1: not set), got {item['edge_size']!r}")
                    edge_size = None
            out.append((scene.path(file), edge_size))
        else:
            problems.add(where, f"must be a file name or a {{\"file\": ..., \"edge_size\": ...}} entry, got {item!r}")
    return out


def _mesh_block(problems, spec, scene):
    """Validates the "mesh" block into scene.mesh (feature files are read by scene.feature_readers)."""
    if not isinstance(spec, dict):
        problems.add("$.mesh", "must be an object")
        return
    _unknown_keys(problems, spec, "$.mesh", MESH_KEYS)
    mesh = scene.mesh
    if "strategy" in spec:
        if spec["strategy"] not in STRATEGIES:
            problems.add("$.mesh.strategy", f"must be one of {', '.join(STRATEGIES)}, got {spec['strategy']!r}")
        mesh["strategy"] = spec["strategy"]
    mesh["criteria"] = _criteria(problems, spec.get("criteria", {}), "$.mesh.criteria")
    materials = spec.get("materials", {})
    mesh["materials"] = {}
    if not isinstance(materials, dict):
        problems.add("$.mesh.materials", "must be an object {material id: {criterion: number}}")
        materials = {}
    for key, value in materials.items():
        material = _integer_key(problems, key, f"$.mesh.materials.{key}")
        if material is None:
            continue
        mesh["materials"][material] = _criteria(problems, value, f"$.mesh.materials.{key}")
    seed = _number(problems, spec, "$.mesh", "seed", required=False, integer=True)
    if seed is not None:
        mesh["seed"] = seed
    for flag in ("perturb", "exude", "improve_angles"):
        if flag in spec and not isinstance(spec[flag], bool):
            problems.add(f"$.mesh.{flag}", f"must be true or false, got {spec[flag]!r}")
        elif flag in spec:
            mesh[flag] = spec[flag]
    for key in ("sliver_angle", "interface_sliver_angle"):
        angle = _number(problems, spec, "$.mesh", key, required=False)
        if angle is not None:
            if not 0 <= angle <= 30:
                problems.add(f"$.mesh.{key}", f"must be between 0 and 30 degrees, got {angle}")
            else:
                mesh[key] = angle
    for key, low, high in (("perturbation_steps_per_vertex", 0, 1e6), ("exudation_steps_per_cell", 0, 1e6),
                           ("optimisation_time_limit", -1, 1e6), ("perturbation_failures_per_bound", 0, 1e6),
                           ("exudation_sliver_bound", 0, 90), ("time_limit", -1, 1e9),
                           ("picking_sliver_angle", -1, 30), ("improvement_min_angle", 1, 60),
                           ("improvement_max_angle", 120, 179)):
        value = _number(problems, spec, "$.mesh", key, required=False)
        if value is not None:
            if not low <= value <= high:
                problems.add(f"$.mesh.{key}", f"must be between {low} and {high:g}, got {value}")
            else:
                mesh[key] = value
    order = spec.get("element_order")
    if order is not None:
        if order not in (1, 2) or isinstance(order, bool):
            problems.add("$.mesh.element_order", f"must be 1 (linear) or 2 (quadratic tetrahedra), got {order!r}")
        else:
            mesh["element_order"] = order
    limit = _number(problems, spec, "$.mesh", "maximum_number_of_vertices", positive=True, required=False,
                    integer=True, low=1, high=ID_MAX)
    if limit is not None:
        mesh["maximum_number_of_vertices"] = limit
    # 1 = sequential (identical meshes per seed), N > 1 = parallel refinement, 0 = every core
    threads = _number(problems, spec, "$.mesh", "threads", required=False, integer=True, low=0, high=1024)
    if threads is not None:
        mesh["threads"] = threads
    features = spec.get("features")
    if features is None:
        return
    if isinstance(features, str):  # "features": "Automatic" is short for {"use": "Automatic"}
        features = {"use": features}
    if not isinstance(features, dict):
        problems.add("$.mesh.features", f"must be an object or one of {', '.join(FEATURE_SOURCES)}")
        return
    _unknown_keys(problems, features, "$.mesh.features", FEATURE_KEYS)
    out = {"from_surface": [], "files": []}
    if "use" in features:
        use = features["use"]
        sources = {v.lower(): v for v in FEATURE_SOURCES}
        if not isinstance(use, str) or use.lower() not in sources:
            problems.add("$.mesh.features.use", f"must be one of {', '.join(FEATURE_SOURCES)} (which feature lines "
                                                f"are kept: given, found where the inputs meet, or both), got {use!r}")
        else:
            out["use"] = sources[use.lower()]
    if "from_surface" in features:
        names = features["from_surface"]
        names = [names] if isinstance(names, str) else names
        domains = scene.description["domains"]
        surfaces = {d.get("name"): i for i, d in enumerate(domains) if isinstance(d, dict) and d.get("type") == "surface"}
        if not isinstance(names, list) or not names:
            problems.add("$.mesh.features.from_surface", "must be a surface domain's name or a list of them")
            names = []
        for k, name in enumerate(names):
            if name in surfaces:
                out["from_surface"].append(surfaces[name])
            else:
                where = "$.mesh.features.from_surface" + (f"[{k}]" if isinstance(features["from_surface"], list) else "")
                problems.add(where, f"no surface domain named {name!r} "
                                    f"(surfaces: {', '.join(map(str, surfaces)) or 'none'})")
    # One angle for a surface's sharp edges: from_surface's (vtkFeatureEdges) and the creases that
    # Automatic/Both find (the tetrahedralizer's CreaseAngle, whose default it keeps when left out).
    if "feature_angle" in features:
        angle = _number(problems, features, "$.mesh.features", "feature_angle", positive=True, required=False)
        if angle is not None and angle > 180:
            problems.add("$.mesh.features.feature_angle", f"must be at most 180 degrees (180 = no sharp edges), got {angle}")
        elif angle is not None:
            out["feature_angle"] = angle
    if "files" in features:
        for k, (file, edge_size) in enumerate(_feature_files(problems, features["files"], scene)):
            try:
                scene.feature_readers.append(surface_reader(file))
                scene.feature_edge_sizes.append(edge_size)
            except OracleMeshError as e:
                where = "$.mesh.features.files" + (f"[{k}]" if isinstance(features["files"], list) else "")
                problems.add(where, str(e))
            out["files"].append(file)
    if not {"from_surface", "files", "use", "feature_angle"} & set(features):
        problems.add("$.mesh.features", "give 'use' (which lines: None, Given, Automatic, Both), 'from_surface' "
                                        "(a surface domain's name), 'files' (polylines) and/or 'feature_angle'")
    # Sharp edges found on a surface are often many tiny noisy segments: resampled unless asked not to.
    resample = features.get("resample", bool(out["from_surface"]))
    if not isinstance(resample, bool):
        problems.add("$.mesh.features.resample", f"must be true or false, got {resample!r}")
    else:
        mesh["resample_feature_lines"] = resample
    mesh["features"] = out


def _outputs_block(problems, spec, scene):
    if not isinstance(spec, dict):
        problems.add("$.outputs", "must be an object")
        return
    _unknown_keys(problems, spec, "$.outputs", OUTPUT_KEYS)
    if "mesh" in spec:
        from .writers import MESH_FORMATS

        files = _paths(problems, spec["mesh"], "$.outputs.mesh", scene)
        for k, file in enumerate(files):
            ext = os.path.splitext(file)[1].lower()
            if ext not in MESH_FORMATS:
                where = "$.outputs.mesh" + (f"[{k}]" if isinstance(spec["mesh"], list) else "")
                problems.add(where, f"unknown mesh format '{ext}' (use one of {', '.join(MESH_FORMATS)})")
        scene.outputs["mesh"] = files
    for key in ("report", "histogram"):
        if key in spec:
            if not isinstance(spec[key], str) or not spec[key]:
                problems.add(f"$.outputs.{key}", f"must be a file name, got {spec[key]!r}")
            else:
                scene.outputs[key] = scene.path(spec[key])


def _reference_volumes(problems, spec, scene):
    """{material id: volume}: exact or reference volumes (batch's summary gives the meshes' errors)."""
    if not isinstance(spec, dict):
        problems.add("$.reference_volumes", "must be an object {material id: volume}")
        return
    for key in spec:
        material = _integer_key(problems, key, f"$.reference_volumes.{key}")
        volume = _number(problems, spec, "$.reference_volumes", key, positive=True)
        if material is not None and volume is not None:
            scene.reference_volumes[material] = volume


def build_scene(description, base_dir=".", source="scene"):
    from vtkmodules.vtkCommonDataModel import vtkBox, vtkCylinder, vtkPlane

    from . import (vtkHierarchicalOracle, vtkImplicitDomain, vtkLabelMapDomain, vtkSphereDomain,
                   vtkSurfaceDomain)

    problems = _Problems()
    scene = Scene(description, base_dir)
    scene.source = source
    space = description.get("space", "LPS") if isinstance(description, dict) else "LPS"
    if space not in SPACES:
        problems.add("$.space", f"must be one of {', '.join(SPACES)} (the scene's anatomical frame), got {space!r}")
        space = "LPS"
    scene.space = space
    domains = description.get("domains") if isinstance(description, dict) else None
    if not isinstance(domains, list) or not domains:
        raise OracleMeshError(f"{source}: $.domains: missing or empty (a list of domains, highest priority first)")
    for i, spec in enumerate(domains):
        where = f"$.domains[{i}]"
        if not isinstance(spec, dict):
            problems.add(where, "must be an object")
            continue
        kind = spec.get("type")
        if kind not in DOMAIN_TYPES:
            problems.add(f"{where}.type", f"must be one of {', '.join(DOMAIN_TYPES)}, got {kind!r}")
            continue
        _unknown_keys(problems, spec, where, COMMON_KEYS | DOMAIN_KEYS[kind])
        name = spec.get("name", f"{kind}{i}")
        cut = spec.get("cut", cut_default(kind))
        if kind == "plane" and not cut and "material" not in spec:
            problems.add(f"{where}.cut", "a plane is unbounded, so it can only be a cut: give \"cut\": true "
                                         f"(the default is {str(cut_default(kind)).lower()})")
            cut = True
        if "criteria" in spec:
            if cut:
                problems.add(f"{where}.criteria", "a cut domain has no material to mesh: criteria do not apply")
            else:
                criteria = _criteria(problems, spec["criteria"], f"{where}.criteria")
                if criteria:
                    scene.domain_criteria.append((i, criteria))
        if not isinstance(cut, bool):
            problems.add(f"{where}.cut", f"must be true or false, got {cut!r}")
        material = _number(problems, spec, where, "material", required=not cut and kind != "labelmap",
                           default=None, integer=True)
        if material is not None and material < 0:
            problems.add(f"{where}.material", f"must be >= 0, got {material}")
        material = material if material is not None else 1
        domain = None
        if kind in ("surface", "labelmap"):
            file = spec.get("file")
            if not isinstance(file, str) or not file:
                problems.add(f"{where}.file", "missing (path of the input file)")
                continue
            full = scene.path(file)
            try:
                reader = surface_reader(full) if kind == "surface" else label_map_reader(full, space)
            except OracleMeshError as e:
                problems.add(f"{where}.file", str(e))
                continue
            scene.readers.append(reader)
            scene.frames.append((name, kind, surface_frame(full) if kind == "surface" else label_map_frame(full)))
            if kind == "surface":
                domain = vtkSurfaceDomain()
                domain.SetMaterialId(material)
                domain.SetMaterialName(name)
                inside_test = spec.get("inside_test", "automatic")
                tests = {"automatic": domain.SetInsideTestToAutomatic, "closed": domain.SetInsideTestToClosed,
                         "winding_number": domain.SetInsideTestToWindingNumber}
                if inside_test not in tests:
                    problems.add(f"{where}.inside_test",
                                 f"must be 'automatic', 'closed' or 'winding_number', got {inside_test!r}")
                else:
                    tests[inside_test]()
                merge = _number(problems, spec, where, "merge_tolerance", required=False)
                if merge is not None:
                    if not 0 <= merge <= 1:
                        problems.add(f"{where}.merge_tolerance",
                                     f"must be between 0 and 1 (a fraction of the bounding-box diagonal), got {merge!r}")
                    else:
                        domain.SetMergeTolerance(merge)
                allow = spec.get("allow_self_intersections", False)
                if not isinstance(allow, bool):
                    problems.add(f"{where}.allow_self_intersections", f"must be true or false, got {allow!r}")
                else:
                    domain.SetAllowSelfIntersections(allow)
            else:
                domain = vtkLabelMapDomain()
                domain.SetDomainName(name)
                background = _number(problems, spec, where, "background", required=False, default=0, integer=True)
                domain.SetBackgroundLabel(background if background is not None else 0)
                interpolation = spec.get("interpolation", "smooth")
                modes = {"smooth": domain.SMOOTH, "trilinear": domain.TRILINEAR, "nearest": domain.NEAREST}
                if interpolation not in modes:
                    problems.add(f"{where}.interpolation",
                                 f"must be 'smooth', 'trilinear' or 'nearest', got {interpolation!r}")
                else:
                    domain.SetInterpolation(modes[interpolation])
                array = spec.get("array")
                if array is not None:
                    association = spec.get("association", "point")
                    if association not in ("point", "cell"):
                        problems.add(f"{where}.association", f"must be 'point' or 'cell', got {association!r}")
                    domain.SetInputArrayToProcess(0, 0, 0, 0 if association == "point" else 1, str(array))
                names = spec.get("label_names", {})
                if not isinstance(names, dict):
                    problems.add(f"{where}.label_names", "must be an object {label: name}")
                    names = {}
                for label, label_name in names.items():
                    value = _integer_key(problems, label, f"{where}.label_names.{label}", low=INT_MIN, what="label")
                    if value is not None:
                        domain.SetLabelName(value, str(label_name))
            domain.SetInputConnection(reader.GetOutputPort())
        elif kind == "sphere":
            center = _vector(problems, spec, where, "center", 3)
            radius = _number(problems, spec, where, "radius", positive=True)
            domain = vtkSphereDomain()
            domain.SetMaterialId(material)
            domain.SetMaterialName(name)
            if center:
                domain.SetCenter(center)
            if radius:
                domain.SetRadius(radius)
        else:
            domain = vtkImplicitDomain()
            domain.SetMaterialId(material)
            domain.SetMaterialName(name)
            if kind == "plane":
                function = vtkPlane()
                origin = _vector(problems, spec, where, "origin", 3)
                normal = _vector(problems, spec, where, "normal", 3)
                if normal and not any(normal):
                    problems.add(f"{where}.normal", "must not be zero")
                if origin:
                    function.SetOrigin(origin)
                if normal:
                    function.SetNormal(normal)
            elif kind == "box":
                function = vtkBox()
                bounds = _vector(problems, spec, where, "bounds", 6)
                if bounds:
                    if not (bounds[0] < bounds[1] and bounds[2] < bounds[3] and bounds[4] < bounds[5]):
                        problems.add(f"{where}.bounds", "must be xmin < xmax, ymin < ymax, zmin < zmax")
                    function.SetBounds(bounds)
            else:
                function = vtkCylinder()
                center = _vector(problems, spec, where, "center", 3)
                axis = _vector(problems, spec, where, "axis", 3, required=False, default=[0, 0, 1])
                radius = _number(problems, spec, where, "radius", positive=True)
                height = _number(problems, spec, where, "height", required=False, default=0)
                if height is not None and height < 0:
                    problems.add(f"{where}.height", "must be >= 0 (0 = infinite)")
                if axis and not any(axis):
                    problems.add(f"{where}.axis", "must not be zero")
                if center:
                    function.SetCenter(center)
                if axis:
                    function.SetAxis(axis)
                if radius:
                    function.SetRadius(radius)
                domain.SetHeight(max(height or 0.0, 0.0))
            domain.SetImplicitFunction(function)
        domain.SetCut(bool(cut))
        for index, criteria in scene.domain_criteria:
            if index == i:  # the domain's own criteria: the core merges them (MeshCriteria.h)
                for key, value in criteria.items():
                    getattr(domain, "Set" + CRITERIA_KEYS[key])(value)
        scene.domains.append(domain)
    if isinstance(description, dict):
        _unknown_keys(problems, description, "$", TOP_KEYS)
        _mesh_block(problems, description.get("mesh", {}), scene)
        if "outputs" in description:
            _outputs_block(problems, description["outputs"], scene)
        if "reference_volumes" in description:
            _reference_volumes(problems, description["reference_volumes"], scene)
    if problems.items:
        raise OracleMeshError(f"{source}: " + "; ".join(problems.items))
    oracle = vtkHierarchicalOracle()
    for domain in scene.domains:
        oracle.AddInputConnection(domain.GetOutputPort())
    scene.oracle = oracle
    return scene
