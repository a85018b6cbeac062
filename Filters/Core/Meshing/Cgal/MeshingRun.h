// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: one call of meshOracle.
#pragma once

#include "CheckedOutput.h"
#include "InitialComplex.h"
#include "MeshingContext.h"
#include "RefinementRounds.h"
#include "SliverOptimisation.h"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

namespace omesh::cgal::sequential
{
/// One call of meshOracle, as the paper's chain of phases, each a class of its own that records
/// its own statistics: the inputs, rule T1 on the segments alone and the initial points
/// (InitialComplex); refinement, the segment, facet and cell levels together, rules T1.2, T2, T3
/// (RefinementRounds); optimisation (SliverOptimisation); the output mesh with its validity check
/// (CheckedOutput). run() calls them in order; a test can call them one by one.
///
/// @warning Not copyable or movable: the deadline's message measures the run through `this`.
class MeshingRun
{
public:
  MeshingRun(const HierarchicalOracle& oracle, const FeatureSegments& givenFeatures, const MesherOptions& options)
    : context(oracle, givenFeatures, options)
    , initial(context)
    , refinement(context)
    , optimisation(context, refinement)
    , output(context, refinement)
  {
    context.deadline.setMeasure([this](std::map<std::string, double>& st) { measure(st); });
  }
  MeshingRun(const MeshingRun&) = delete;
  MeshingRun& operator=(const MeshingRun&) = delete;

  TetMesh run(const std::vector<Vec3>& seedPoints)
  {
    initial.run(seedPoints);
    refinement.refineAllLevels();
    optimisation.run();
    return finish();
  }

  /// The output mesh with every phase's statistics and the run's warnings.
  TetMesh finish()
  {
    TetMesh mesh = output.mesh();
    auto& st = mesh.statistics;
    output.record(mesh, st);
    refinement.record(st);
    optimisation.record(st);
    initial.record(st);
    st["time.total"] = seconds(context.started);
    st["time_limit"] = context.deadline.limit();
    mesh.warnings = std::move(context.warnings);
    context.report(1.0, "done");
    return mesh;
  }

  MeshingContext context;
  InitialComplex initial;
  RefinementRounds refinement;
  SliverOptimisation optimisation;
  CheckedOutput output;

private:
  /// How far the run got, for the message and statistics of TimeLimitReached.
  void measure(std::map<std::string, double>& st) const
  {
    const C3t3* c3t3 = context.c3t3.get();
    // during a parallel refinement the sequential complex holds its start: its vertex count is the
    // last seen (after the output cleared the complex, the output's counts)
    st["vertices"] = std::max({ c3t3 ? static_cast<double>(c3t3->triangulation().number_of_vertices()) : 0.0,
      static_cast<double>(refinement.parallelVertices()), static_cast<double>(output.outputVertices()) });
    st["tetrahedra"] = std::max(c3t3 ? static_cast<double>(c3t3->number_of_cells_in_complex()) : 0.0,
      static_cast<double>(output.outputTetrahedra()));
    st["feature_points"] = static_cast<double>(
      context.segments ? context.segments->segments().points.size() : context.conformed.points.size());
    st["refinement_steps"] = static_cast<double>(refinement.steps());
  }
};
}
