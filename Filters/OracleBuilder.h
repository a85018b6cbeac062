// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "OracleDomainMetadata.h"
#include "OracleMeshFiltersModule.h"

#include <array>
#include <map>
#include <memory>
#include <string>

#include <vector>

class vtkDataObject;
class vtkImageData;
class vtkPoints;
class vtkPolyData;

namespace omesh
{
class Domain;
class HierarchicalOracle;
class LabelMapDomain;
struct FeatureSegments;
struct TriangleSurface;
}

/// Turns OracleMesh domain datasets (and vtkHierarchicalOracle's output) into core objects. All
/// functions throw omesh::InputError with a message naming the input (`where`) and the problem.
class ORACLEMESHFILTERS_EXPORT OracleBuilder
{
public:
  /// The oracle described by `data`: the multiblock output of vtkHierarchicalOracle (blocks in
  /// priority order) or a single domain dataset.
  static std::shared_ptr<omesh::HierarchicalOracle> BuildOracle(vtkDataObject* data);

  /// The criteria the domains of an oracle (the output of vtkHierarchicalOracle, or one domain)
  /// set for their materials, per material id (6 values, negative = not set); the
  /// higher-priority domain's value counts where two differ. Cut domains set nothing.
  /// `oracle` is BuildOracle(data): it tells each domain's materials.
  static std::map<int, std::array<double, 6>> DomainCriteria(
    vtkDataObject* data, const omesh::HierarchicalOracle& oracle);

  /// Reads the domain metadata of `data` and checks the dataset type fits the kind.
  static OracleDomainMetadata ReadDomain(vtkDataObject* data, const std::string& where);

  /// Builds the core domain of one domain dataset.
  static std::shared_ptr<omesh::Domain> BuildDomain(vtkDataObject* data, const std::string& where);

  /// Core domain of an analytic kind (Sphere, Plane, Box, Cylinder) from its metadata alone.
  static std::shared_ptr<omesh::Domain> BuildImplicit(const OracleDomainMetadata& md);

  /// Triangles of `surface` as a soup; rejects polygons that are not triangles and strips.
  static omesh::TriangleSurface ToTriangleSurface(vtkPolyData* surface, const std::string& who);

  /// The lines of `lines` as constrained segments: polylines split into segments, a point shared
  /// by several polylines one vertex. Null gives no segments.
  static omesh::FeatureSegments ToFeatureSegments(vtkPolyData* lines);

  /// The label map of `image` as described by `md` (array, association, background).
  static std::shared_ptr<omesh::LabelMapDomain> ToLabelMap(
    vtkImageData* image, const OracleDomainMetadata& md, const std::string& who);

  /// Coordinates beyond this magnitude are refused as absurd (no model is that large; squared
  /// distances there lose every digit).
  static constexpr double LargestCoordinate = 1e15;

  /// Throws when a point of `points` has a NaN, infinite or absurd (|x| > LargestCoordinate)
  /// coordinate, naming `who`, `what` ("surface", "feature lines") and the point.
  static void CheckCoordinates(vtkPoints* points, const std::string& who, const std::string& what);

  /// Bytes this process can still allocate: the system's available memory (MemAvailable), capped by
  /// the address-space limit (ulimit -v) when one is set.
  static double AvailableMemory();

  /// Throws before allocating `count` items of `bytesEach` bytes when they would need more than the
  /// available memory: "who: what (count) need X GB (B bytes each); Y GB available".
  static void CheckMemory(const std::string& who, const std::string& what, double count, double bytesEach);

  /// Warnings for the domains no point of which reaches the mesh: every point sampled inside the
  /// domain's bounds (20 x 20 x 20) that the domain contains belongs to a higher-priority domain.
  static std::vector<std::string> HiddenDomainWarnings(const omesh::HierarchicalOracle& oracle);
  /// The domains' own warnings (the holes a winding-number surface closes), then
  /// HiddenDomainWarnings.
  static std::vector<std::string> DomainWarnings(const omesh::HierarchicalOracle& oracle);
};
