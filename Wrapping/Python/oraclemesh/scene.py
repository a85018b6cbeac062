# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene files: a JSON description of the oracle's domains in priority order, turned into a VTK
pipeline (readers -> domain algorithms -> vtkHierarchicalOracle).

    {"domains": [
       {"name": "implant", "type": "surface", "file": "implant.vtp", "material": 3},
       {"name": "screw", "type": "cylinder", "center": [x, y, z], "axis": [ax, ay, az],
        "radius": 2.5, "height": 34, "material": 4},
       {"name": "resection", "type": "plane", "origin": [...], "normal": [...], "cut": true},
       {"name": "tibia", "type": "labelmap", "file": "labels.vti", "array": "labels",
        "background": 0, "label_names": {"1": "cortical bone"}},
       {"name": "ball", "type": "sphere", "center": [...], "radius": 5, "material": 5},
       {"name": "block", "type": "box", "bounds": [xmin, xmax, ymin, ymax, zmin, zmax], "material": 6}
    ]}

The first domain has the highest priority. Relative file paths resolve against the scene file.
Every problem found is reported at once, each with its JSON path.
"""
import json
import math
import os

from .errors import OracleMeshError
from .readers import label_map_reader, surface_reader

DOMAIN_TYPES = ("surface", "labelmap", "sphere", "plane", "box", "cylinder")


class Scene:
    """The pipeline built from a scene: ``domains`` (algorithms, priority order), ``readers`` and
    ``oracle`` (a vtkHierarchicalOracle)."""

    def __init__(self, description, base_dir):
        self.description = description
        self.base_dir = base_dir
        self.readers = []
        self.domains = []
        self.oracle = None

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


def _number(problems, spec, path, key, positive=False, required=True, default=None, integer=False):
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
    return int(value) if integer else float(value)


def load_scene(path):
    """Reads and validates a scene file; returns a Scene whose pipeline is built but not run.
    Raises OracleMeshError listing every problem with its JSON path."""
    try:
        with open(path) as f:
            description = json.load(f)
    except FileNotFoundError:
        raise OracleMeshError(f"{path}: scene file not found") from None
    except json.JSONDecodeError as e:
        raise OracleMeshError(f"{path}: not valid JSON: {e}") from None
    return build_scene(description, os.path.dirname(os.path.abspath(path)), source=path)


def build_scene(description, base_dir=".", source="scene"):
    from vtkmodules.vtkCommonDataModel import vtkBox, vtkCylinder, vtkPlane

    from . import (vtkHierarchicalOracle, vtkImplicitDomain, vtkLabelMapDomain, vtkSphereDomain,
                   vtkSurfaceDomain)

    problems = _Problems()
    scene = Scene(description, base_dir)
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
        name = spec.get("name", f"{kind}{i}")
        cut = spec.get("cut", False)
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
            full = file if os.path.isabs(file) else os.path.join(base_dir, file)
            try:
                reader = surface_reader(full) if kind == "surface" else label_map_reader(full)
            except OracleMeshError as e:
                problems.add(f"{where}.file", str(e))
                continue
            scene.readers.append(reader)
            if kind == "surface":
                domain = vtkSurfaceDomain()
                domain.SetMaterialId(material)
                domain.SetMaterialName(name)
            else:
                domain = vtkLabelMapDomain()
                domain.SetDomainName(name)
                background = _number(problems, spec, where, "background", required=False, default=0, integer=True)
                domain.SetBackgroundLabel(background if background is not None else 0)
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
                    try:
                        domain.SetLabelName(int(label), str(label_name))
                    except ValueError:
                        problems.add(f"{where}.label_names.{label}", "key must be an integer label")
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
        scene.domains.append(domain)
    if problems.items:
        raise OracleMeshError(f"{source}: " + "; ".join(problems.items))
    oracle = vtkHierarchicalOracle()
    for domain in scene.domains:
        oracle.AddInputConnection(domain.GetOutputPort())
    scene.oracle = oracle
    return scene
