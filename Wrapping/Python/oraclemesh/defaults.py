# SPDX-License-Identifier: GPL-3.0-or-later
"""The defaults, read from the C++ (their one source: omesh::MesherOptions and
omesh::MeshCriteria::defaults(), which a fresh vtkFeaturePreservingTetrahedralizer shows through its
getters; a domain's Cut from a fresh domain object). Nothing here repeats a number::

    >>> from oraclemesh.defaults import mesh_defaults
    >>> mesh_defaults()["criteria"]["facet_angle"]
    25.0
    >>> mesh_defaults()["features"]["use"]
    'Given'

The scene loader, ``oraclemesh.mesh``, the command line and the pvpython helpers leave a key out of
the filter when the scene leaves it out, so the filter's default applies; these functions say what
that default is (for help texts, reports and tests).
"""
import functools

# Scene criteria keys -> the VTK property names, in SetMaterialCriteria's order (the core's
# MeshCriteria field order).
CRITERIA_KEYS = {
    "facet_angle": "FacetAngle", "facet_size": "FacetSize", "facet_distance": "FacetDistance",
    "cell_size": "CellSize", "cell_radius_edge_ratio": "CellRadiusEdgeRatio", "edge_size": "EdgeSize",
}
# The tetrahedralizer's FeatureStrategy values, in the C++ enum's order.
STRATEGIES = ("Conforming", "None", "ProtectingBalls")
# The tetrahedralizer's Features values (which feature lines are kept), in the C++ enum's order.
FEATURE_SOURCES = ("None", "Given", "Automatic", "Both")
# Scene "mesh" keys that are plain tetrahedralizer properties.
MESH_PROPERTIES = {
    "perturb": "Perturb", "exude": "Exude", "sliver_angle": "SliverAngle",
    "improve_angles": "ImproveAngles", "improvement_min_angle": "ImprovementMinAngle",
    "improvement_max_angle": "ImprovementMaxAngle",
    "resample_feature_lines": "ResampleFeatureLines",
    "interface_sliver_angle": "InterfaceSliverAngle", "picking_sliver_angle": "PickingSliverAngle",
    "perturbation_failures_per_bound": "PerturbationFailuresPerBound",
    "exudation_sliver_bound": "ExudationSliverBound",
    "perturbation_steps_per_vertex": "PerturbationStepsPerVertex",
    "exudation_steps_per_cell": "ExudationStepsPerCell", "optimisation_time_limit": "OptimisationTimeLimit",
    "seed": "Seed", "maximum_number_of_vertices": "MaximumNumberOfVertices", "time_limit": "TimeLimit",
    "element_order": "ElementOrder", "threads": "Threads",
}
BOOLEAN_PROPERTIES = {"Perturb", "Exude", "ImproveAngles", "ResampleFeatureLines"}
# MESH_PROPERTIES keys that a scene spells inside "mesh.features" ("resample")
SCENE_FEATURE_PROPERTIES = {"resample_feature_lines"}


@functools.lru_cache(maxsize=None)
def _mesh_defaults():
    from . import vtkFeaturePreservingTetrahedralizer

    fresh = vtkFeaturePreservingTetrahedralizer()
    out = {"strategy": STRATEGIES[fresh.GetFeatureStrategy()],
           "criteria": {key: float(getattr(fresh, "Get" + prop)()) for key, prop in CRITERIA_KEYS.items()},
           "features": {"use": FEATURE_SOURCES[fresh.GetFeatures()], "feature_angle": fresh.GetCreaseAngle(),
                        "resample": bool(fresh.GetResampleFeatureLines())}}
    for key, prop in MESH_PROPERTIES.items():
        if key in SCENE_FEATURE_PROPERTIES:
            continue
        value = getattr(fresh, "Get" + prop)()
        out[key] = bool(value) if prop in BOOLEAN_PROPERTIES else value
    return out


def mesh_defaults():
    """The defaults in the shape of a scene's "mesh" block, as a fresh
    vtkFeaturePreservingTetrahedralizer has them: "strategy", "criteria" {criterion: value},
    "features" {"use" (which lines are kept), "feature_angle" (a surface's sharp edges and the
    creases Automatic finds), "resample" (without "from_surface"; with it the scene's default is
    true)} and every other key of MESH_PROPERTIES ("seed", "time_limit", ...). A scene whose "mesh"
    block is this dict meshes as one that leaves every key out."""
    import copy

    return copy.deepcopy(_mesh_defaults())


@functools.lru_cache(maxsize=None)
def cut_default(kind):
    """The "cut" default of a scene domain type, from a fresh VTK domain object of that type."""
    from . import vtkImplicitDomain, vtkLabelMapDomain, vtkSphereDomain, vtkSurfaceDomain

    cls = {"surface": vtkSurfaceDomain, "labelmap": vtkLabelMapDomain, "sphere": vtkSphereDomain}.get(
        kind, vtkImplicitDomain)
    return bool(cls().GetCut())


def domain_criteria_unset():
    """The value a domain's (or a per-material row's) criterion has when not set, as the VTK
    classes spell it (the core's std::nullopt): a fresh domain's FacetAngle."""
    from . import vtkSphereDomain

    return vtkSphereDomain().GetFacetAngle()
