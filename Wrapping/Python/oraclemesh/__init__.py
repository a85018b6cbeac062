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
"""
# The wrapped module's base classes live in these VTK modules: import them first.
from vtkmodules import vtkCommonCore, vtkCommonDataModel, vtkCommonExecutionModel  # noqa: F401

from .OracleMeshFilters import (  # noqa: F401
    vtkFeaturePreservingTetrahedralizer,
    vtkHierarchicalOracle,
    vtkImplicitDomain,
    vtkLabelMapDomain,
    vtkMeshValidityCheck,
    vtkOracleSampler,
    vtkSphereDomain,
    vtkSurfaceDomain,
)
from .errors import MeshingError, OracleMeshError, update  # noqa: F401

__all__ = [
    "MeshingError",
    "OracleMeshError",
    "update",
    "vtkFeaturePreservingTetrahedralizer",
    "vtkHierarchicalOracle",
    "vtkImplicitDomain",
    "vtkLabelMapDomain",
    "vtkMeshValidityCheck",
    "vtkOracleSampler",
    "vtkSphereDomain",
    "vtkSurfaceDomain",
]
