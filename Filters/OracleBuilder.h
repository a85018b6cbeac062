// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "MeshCriteria.h"
#include "OracleDomainMetadata.h"
#include "OracleMeshFiltersModule.h"

#include <array>
#include <functional>
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
  /// Fraction done of a long step (a label map's smoothing); returning false stops it (the step
  /// throws its own Aborted exception, e.g. omesh::LabelSmoothingAborted).
  using Progress = std::function<bool(double)>;

  /// The oracle described by `data`: the multiblock output of vtkHierarchicalOracle (blocks in
  /// priority order) or a single domain dataset. `progress` hears each Smooth label map's smoothing.
  static std::shared_ptr<omesh::HierarchicalOracle> BuildOracle(vtkDataObject* data, const Progress& progress = {});

  /// The criteria the domains of an oracle (the output of vtkHierarchicalOracle, or one domain)
  /// set for their materials (each of a label map's labels), as one level of the merge rule.
  /// Throws InputError where two domains give one material different values, naming both, or a
  /// value is NaN or infinite. Cut domains set nothing.
  /// `oracle` is BuildOracle(data): it tells each domain's materials.
  static omesh::CriteriaLevel DomainCriteria(
    vtkDataObject* data, const omesh::HierarchicalOracle& oracle);

  /// Reads the domain metadata of `data` and checks the dataset type fits the kind.
  static OracleDomainMetadata ReadDomain(vtkDataObject* data, const std::string& where);

  /// Builds the core domain of one domain dataset.
  static std::shared_ptr<omesh::Domain> BuildDomain(
    vtkDataObject* data, const std::string& where, const Progress& progress = {});

  /// Core domain of an analytic kind (Sphere, Plane, Box, Cylinder) from its metadata alone.
  static std::shared_ptr<omesh::Domain> BuildImplicit(const OracleDomainMetadata& md);

  /// Triangles of `surface` as a soup; rejects polygons that are not triangles and strips.
  static omesh::TriangleSurface ToTriangleSurface(vtkPolyData* surface, const std::string& who);

  /// The lines of `lines` as constrained segments: polylines split into segments, a point shared
  /// by several polylines one vertex. Null gives no segments. A cell array "EdgeSize" gives each
  /// line its own edge size (FeatureSegments::edgeSizes; -1 = none, the materials' or global counts).
  /// `owners`, when given, gets one entry per segment from the integer cell array "EdgesOfDomain"
  /// (keys::EDGES_OF_DOMAIN): the index, in the oracle's priority order, of the input whose sharp
  /// edges the line is (scene `features.from_surface`), -1 (omesh::kUserLine) for a user's own line
  /// and for every line when the array is missing (clipFeatureSegments).
  static omesh::FeatureSegments ToFeatureSegments(vtkPolyData* lines, std::vector<int>* owners = nullptr);

  /// The label map of `image` as described by `md` (array, association, background, interpolation).
  static std::shared_ptr<omesh::LabelMapDomain> ToLabelMap(
    vtkImageData* image, const OracleDomainMetadata& md, const std::string& who, const Progress& progress = {});

  /// Coordinates beyond this magnitude are refused as absurd (no model is that large; squared
  /// distances there lose every digit).
  static constexpr double LargestCoordinate = 1e15;

  /// Throws when a point of `points` has a NaN, infinite or absurd (|x| > LargestCoordinate)
  /// coordinate, naming `who`, `what` ("surface", "feature lines") and the point.
  static void CheckCoordinates(vtkPoints* points, const std::string& who, const std::string& what);

  /// Warnings for names and criteria given to materials no domain has: a label map's label names
  /// (read from the domains in `data`, BuildOracle's input) for labels its image lacks, and
  /// `criteriaMaterials` (the per-material table's ids) that no domain of `oracle` gives.
  static std::vector<std::string> UnknownMaterialWarnings(
    vtkDataObject* data, const omesh::HierarchicalOracle& oracle, const std::vector<int>& criteriaMaterials);
};
