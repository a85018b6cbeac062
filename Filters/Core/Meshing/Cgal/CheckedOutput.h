// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: the output mesh, checked on its own.
#pragma once

#include "ComplexToTetMesh.h"
#include "DihedralImprovement.h"
#include "FieldDataKeys.h"
#include "FreedMemory.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "MeshingContext.h"
#include "RefinementRounds.h"
#include "ShapeSummary.h"
#include "TetMeshOrder.h"

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace omesh::cgal::sequential
{
/// The phases after optimisation: the complex converted to the output mesh (the triangulation's
/// memory given back at once), the feature lines located in it with their coverage, the quality
/// step (DihedralImprovement.h), then the validity check on the mesh alone (what a finite-element
/// code would reject), whose passes also measure the shapes and find the separating faces.
///
/// @sa SliverOptimisation (before it), MeshValidity.h, ShapeSummary.h
class CheckedOutput
{
public:
  CheckedOutput(MeshingContext& run, RefinementRounds& refinement)
    : run_(run)
    , refinement_(refinement)
  {
  }

  /// Every step, in order: the mesh with the validity check's statistics, its warnings in the
  /// run's.
  TetMesh mesh()
  {
    TetMesh mesh = convert();
    locateFeatureLines(mesh);
    improveAngles(mesh);
    warnFeatureCoverage(mesh);
    // From here on a piece names the segment as given that its resampled one came from: the
    // caller's tags (found or given, materials) are per given segment.
    if (run_.resampled)
      for (auto& piece : mesh.segments)
        piece.input = run_.resampled->source[static_cast<size_t>(piece.input)];
    refinement_.warnMissingPieces();
    checkValidity(mesh);
    return mesh;
  }

  /// The complex as a TetMesh; the complex is cleared: only the output is needed from here on,
  /// and the triangulation's memory goes back to the system before the tetrahedra are ordered and
  /// the quality step and the checks build their own tables (else they all stack on it at the
  /// run's peak).
  TetMesh convert()
  {
    const auto started = Clock::now();
    std::vector<int> stampIds; // the output id of each corner's time stamp
    TetMesh mesh = toTetMesh(*run_.c3t3, run_.oracle,
      run_.segments ? run_.segments->cellsAroundEdgesOutsideComplex() : std::vector<Tr::Cell_handle>{}, stampIds);
    outputVertices_ = mesh.points.size();
    outputTets_ = mesh.tets.size();
    run_.c3t3->clear();
    returnFreedMemory();
    orderTetsByPoints(mesh, &stampIds);
    outputTime_ = seconds(started);
    return mesh;
  }

  /// The feature lines as chains of mesh edges (TetMesh::segments).
  void locateFeatureLines(TetMesh& mesh)
  {
    const auto started = Clock::now();
    mesh.segments = locateFeatureSegments(mesh, *run_.features);
    locationTime_ = seconds(started);
    run_.deadline.check("locating the feature lines in the mesh");
  }

  /// The quality step (DihedralImprovement.h): the located feature segments are the edges it keeps.
  void improveAngles(TetMesh& mesh)
  {
    if (!run_.options.improveAngles || mesh.tets.empty())
      return;
    const auto start = Clock::now();
    DihedralImprovementOptions o;
    o.minAngle = run_.options.improvementMinAngle;
    o.maxAngle = run_.options.improvementMaxAngle;
    o.cellSizeOf = [this](int material) { return run_.options.criteria.of(material).cellSize; };
    o.facetDistanceOf = [this](int material) { return run_.options.criteria.of(material).facetDistance; };
    // Stopped at the vertex budget, the mesh is coarse everywhere and its criteria unmet: its long
    // edges make each move's oracle queries dear, many times the refinement's time, so one round.
    if (refinement_.budgetHit())
      o.rounds = std::min(o.rounds, 1);
    o.progress = [this](double f) {
      run_.deadline.check("quality step");
      run_.report(0.98 + 0.02 * f, "quality step");
    };
    improvement_ = improveDihedralAngles(mesh, run_.oracle, o);
    improvementTime_ = seconds(start);
    outputTets_ = mesh.tets.size();
    outputVertices_ = mesh.points.size();
  }

  /// The validity check, its passes also measuring the tetrahedra (statistics and the caller's
  /// cell arrays) and finding the separating faces (the writers' surface sets).
  void checkValidity(TetMesh& mesh)
  {
    const auto started = Clock::now();
    std::vector<unsigned char> defects;
    // Missing feature-line pieces are defects only where the strategy promises them (not None).
    ValidityThresholds thresholds;
    thresholds.segmentsRequired = run_.options.strategy != FeatureStrategy::None;
    thresholds.facetDistanceOf = [this](int m) { return run_.options.criteria.of(m).facetDistance; };
    ValidityByproducts byproducts;
    byproducts.separatingFaces = &mesh.separatingFaces;
    byproducts.shapes = &shapes_;
    if (run_.options.shapeArrays)
      byproducts.shapeArrays = run_.options.shapeArrays(mesh.tets.size());
    const MeshValidity validity = checkMeshValidity(
      mesh,
      [this](const Vec3& p) {
        run_.deadline.tick("validation");
        return run_.oracle.material(p);
      },
      thresholds, &defects, byproducts);
    mesh.tetDefects = std::move(defects);
    if (!validity.valid())
      run_.warnings.push_back("mesh validity: " + validity.describe());
    warnAcrossBoundary(validity);
    for (const auto& [name, value] : validity.asStatistics())
      mesh.statistics[name] = value;
    validityTime_ = seconds(started);
  }

  /// Vertices and tetrahedra of the output so far (0 before it exists), for the time limit's message.
  size_t outputVertices() const { return outputVertices_; }
  size_t outputTetrahedra() const { return outputTets_; }

  /// Its statistics: the mesh's size and shapes (per material too), the feature lines' coverage
  /// and resampling, the quality step, the times of its phases.
  void record(const TetMesh& mesh, std::map<std::string, double>& st) const
  {
    shapes_.addTo(st);
    st["tetrahedra"] = static_cast<double>(mesh.tets.size());
    st["vertices"] = static_cast<double>(mesh.points.size());
    st["min_dihedral_angle"] = mesh.tets.empty() ? 0.0 : shapes_.all.minDihedral;
    st["mean_min_dihedral_angle"] = shapes_.all.meanMinDihedral();
    st[keys::FEATURE_COVERAGE] = coverage_;
    st["feature_segments"] = static_cast<double>(run_.features->segments.size());
    if (run_.resampled)
      recordResampling(st);
    if (run_.options.improveAngles)
      recordImprovement(st);
    st["time.output"] = outputTime_;
    st["time.feature_location"] = locationTime_;
    st["time.validity"] = validityTime_;
    for (const auto& [m, figures] : shapes_.materials)
    {
      st["volume.material_" + std::to_string(m)] = figures.volume;
      st["tetrahedra.material_" + std::to_string(m)] = static_cast<double>(figures.tetrahedra);
    }
  }

private:
  /// The share of the feature lines' length present as mesh edges, with a warning naming a line
  /// where a piece is missing.
  void warnFeatureCoverage(const TetMesh& mesh)
  {
    coverage_ = featureCoverage(mesh.segments, *run_.features);
    if (run_.features->empty() || coverage_ >= 0.9999)
      return;
    std::ostringstream o;
    o << "feature lines: " << 100.0 * coverage_ << "% of their length is present as mesh edges";
    const auto first = std::find_if(mesh.segments.begin(), mesh.segments.end(), [](const auto& p) { return !p.present; });
    if (first != mesh.segments.end())
      o << "; the first missing piece lies on " << run_.features->describe(static_cast<size_t>(first->input));
    run_.warnings.push_back(o.str());
  }

  void warnAcrossBoundary(const MeshValidity& validity)
  {
    if (validity.acrossBoundaryTetrahedra == 0)
      return;
    std::ostringstream o;
    const bool one = validity.acrossBoundaryTetrahedra == 1;
    o << validity.acrossBoundaryTetrahedra << (one ? " tetrahedron (volume " : " tetrahedra (volume ")
      << validity.acrossBoundaryVolume << (one ? ") lies" : ") lie")
      << " across a boundary: every vertex on an interface or feature line, lying in another "
      << "material by more than the finer facet distance of the two (a thin or acute part loses or "
      << "gains that volume)";
    run_.warnings.push_back(o.str());
  }

  void recordResampling(std::map<std::string, double>& st) const
  {
    const FeatureNetworkReport& network = run_.network;
    st["feature_segments_before_resampling"] = static_cast<double>(run_.given.segments.size());
    st["feature_network.points_merged"] = static_cast<double>(network.pointsMerged);
    st["feature_network.points_snapped"] = static_cast<double>(network.pointsSnapped);
    st["feature_network.spurs_dropped"] = static_cast<double>(network.spursDropped);
    st["feature_network.pieces_dropped"] = static_cast<double>(network.piecesDropped);
    st["feature_network.segments_outside_dropped"] = static_cast<double>(network.segmentsOutside);
    st["feature_network.unmeshable_ends"] = static_cast<double>(network.unmeshableEnds);
    st["feature_network.short_pieces_length"] = network.shortPiecesLength;
    st["feature_network.given_to_simplified"] = network.givenToSimplified;
    st["feature_network.simplified_to_given"] = network.simplifiedToGiven;
    st["feature_network.smallest_angle"] = network.smallestAngle;
    st["feature_network.shortest_segment"] = network.shortestSegment;
  }

  void recordImprovement(std::map<std::string, double>& st) const
  {
    const DihedralImprovementReport& r = improvement_;
    st[keys::IMPROVEMENT_MIN_ANGLE] = run_.options.improvementMinAngle;
    st[keys::IMPROVEMENT_MAX_ANGLE] = run_.options.improvementMaxAngle;
    st[keys::IMPROVEMENT_OUTSIDE_BEFORE] = static_cast<double>(r.outsideBefore);
    st[keys::IMPROVEMENT_OUTSIDE_AFTER] = static_cast<double>(r.outsideAfter);
    st["improvement.min_dihedral_before"] = r.minBefore;
    st["improvement.max_dihedral_before"] = r.maxBefore;
    st["improvement.edge_removals"] = static_cast<double>(r.edgeRemovals);
    st["improvement.face_removals"] = static_cast<double>(r.faceRemovals);
    st["improvement.interior_moves"] = static_cast<double>(r.interiorMoves);
    st["improvement.edge_splits"] = static_cast<double>(r.edgeSplits);
    st["improvement.peeled"] = static_cast<double>(r.peeled);
    st["improvement.interface_collapses"] = static_cast<double>(r.interfaceCollapses);
    st["improvement.interface_moves"] = static_cast<double>(r.surfaceMoves);
    st["improvement.feature_line_moves"] = static_cast<double>(r.lineMoves);
    st["improvement.rounds"] = r.rounds;
    st[keys::IMPROVEMENT_OUTSIDE_HELD] = static_cast<double>(r.outsideHeld);
    st[keys::IMPROVEMENT_CUT_SHORT] = r.cutShort;
    st[keys::TIME_IMPROVEMENT] = improvementTime_;
  }

  MeshingContext& run_;
  RefinementRounds& refinement_;
  size_t outputVertices_ = 0, outputTets_ = 0; ///< of the output, once the complex is cleared
  double coverage_ = 0.0;                     ///< of the feature lines (warnFeatureCoverage)
  DihedralImprovementReport improvement_;
  double improvementTime_ = 0.0;
  ShapeSummary shapes_; ///< of the output's tetrahedra, from the validity check's pass
  double outputTime_ = 0.0, locationTime_ = 0.0, validityTime_ = 0.0;
};
}
