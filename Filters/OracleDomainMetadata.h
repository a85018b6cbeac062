// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <string>
#include <vector>

class vtkFieldData;

/// The description of one oracle domain, carried as field data on the domain's dataset (see
/// docs/REFERENCE.md, "Domain format"). Writing then reading gives back the same values.
struct OracleDomainMetadata
{
  static constexpr int kFormatVersion = 1;
  /// Field-data array names: the kind, on every domain's dataset; the format version, on every
  /// domain's dataset and on what vtkHierarchicalOracle makes (an output without it is no oracle's).
  static constexpr const char* KindArray = "OracleMesh_Kind";
  static constexpr const char* VersionArray = "OracleMesh_FormatVersion";

  std::string Kind; ///< Surface, LabelMap, Sphere, Plane, Box, Cylinder
  std::string Name;
  bool Cut = false;
  int MaterialId = 1;
  std::string MaterialName;
  /// Kind-specific numbers: Sphere cx cy cz r; Plane ox oy oz nx ny nz; Box xmin xmax ymin ymax
  /// zmin zmax; Cylinder cx cy cz ax ay az r height (0 = infinite).
  std::vector<double> Parameters;
  /// Optional world-to-local affine map, 3x4 row-major (the implicit function's VTK transform).
  std::vector<double> Transform;

  /// Surfaces only: what vtkSurfaceDomain welded of the surface's seams (SeamWelding::describe),
  /// empty when nothing; the mesher reports it among the input warnings.
  std::string SeamWeld;

  // Label maps only
  std::string LabelArray;
  bool CellLabels = false;
  int BackgroundLabel = 0;
  /// Optional criteria for this domain's material(s): facet angle, facet size, facet distance,
  /// cell size, cell radius-edge ratio, edge size; negative = not set.
  std::array<double, 6> Criteria{ -1, -1, -1, -1, -1, -1 };
  /// LabelMap: how labels are read between voxel centres: "Nearest", "Trilinear" or "Smooth"
  /// (absent = Nearest).
  std::string LabelInterpolation = "Nearest";
  std::vector<int> LabelValues; ///< labels that have a name, aligned with LabelNames
  std::vector<std::string> LabelNames;

  void WriteTo(vtkFieldData* fd) const;
  /// False when `fd` carries no OracleMesh domain; throws omesh::InputError when it does but the
  /// entries are malformed.
  static bool ReadFrom(vtkFieldData* fd, OracleDomainMetadata& out);
};
