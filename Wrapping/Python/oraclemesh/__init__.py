# SPDX-License-Identifier: GPL-3.0-or-later
"""OracleMesh: multi-material tetrahedral meshing with hierarchical oracles.

The VTK classes are the wrapped C++ module; ``update`` runs a pipeline and turns the filters'
VTK errors into a Python exception (``OracleMeshError``)::

    import oraclemesh as om
    sphere = om.vtkSphereDomain()
    sphere.SetRadius(5)
    oracle = om.vtkHierarchicalOracle()
    oracle.AddInputConnection(sphere.GetOutputPort())
    sampler = om.vtkOracleSampler()
    sampler.SetInputConnection(oracle.GetOutputPort())
    image = om.update(sampler)   # raises om.OracleMeshError on bad input

``mesh`` meshes a whole scene (a JSON scene file or the same as a dict) in one call::

    result = om.mesh("scene.json")
    print(result.report)
    result.save("mesh.inp")      # .vtu .inp .msh .mesh, with boundary and interface sets
"""
# The wrapped module's base classes live in these VTK modules: import them first.
from vtkmodules import vtkCommonCore, vtkCommonDataModel, vtkCommonExecutionModel  # noqa: F401

from .OracleMeshFilters import (  # noqa: F401
    vtkFeaturePreservingTetrahedralizer,
    vtkHierarchicalOracle,
    vtkImplicitDomain,
    vtkLabelMapDomain,
    vtkMeshValidityCheck,
    vtkOracleFeatureLines,
    vtkOracleSampler,
    vtkSphereDomain,
    vtkSurfaceDomain,
)
from .errors import MeshingError, OracleMeshError, update  # noqa: F401
from .meshing import MeshResult, mesh  # noqa: F401

__all__ = [
    "MeshResult",
    "MeshingError",
    "OracleMeshError",
    "mesh",
    "update",
    "vtkFeaturePreservingTetrahedralizer",
    "vtkHierarchicalOracle",
    "vtkImplicitDomain",
    "vtkLabelMapDomain",
    "vtkMeshValidityCheck",
    "vtkOracleFeatureLines",
    "vtkOracleSampler",
    "vtkSphereDomain",
    "vtkSurfaceDomain",
]
