// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: CGAL's perturber and exuder on the refined complex.
#pragma once

#include "CentroidLabel.h"
#include "ComplexSnapshot.h"
#include "MeshingContext.h"
#include "Optimisers.h"
#include "RefinementRounds.h"

#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <string>

namespace omesh::cgal::sequential
{
/// Sliver optimisation: CGAL's perturber, the sub-segments it broke repaired by a refinement round
/// around them (RefinementRounds::repairSegmentsAfterPerturbation), then CGAL's exuder, undone
/// when it would break a sub-segment or lower the smallest dihedral angle; last, the cells the
/// optimisers left across a boundary relabelled by their centroid. Both optimisers are bounded
/// by step budgets that scale with the mesh (deterministic: the same seed gives the same mesh on
/// any machine); a time limit is optional (< 0: stock CGAL's, the refinement's time).
///
/// @sa RefinementRounds (before it), CheckedOutput (after it)
class SliverOptimisation
{
public:
  /// Our smallest angle and CGAL's criterion compute the same angle in different ways.
  static constexpr double kAngleSlack = 1e-6;

  /// What the exuder is judged by: the complex from before it, kept as a compact record
  /// (ComplexSnapshot.h; a copy of the triangulation was the run's peak memory), and the
  /// sub-segments missing and the smallest angle before and after it.
  struct Exudation
  {
    std::optional<ComplexSnapshot<C3t3>> before;
    size_t missingBefore = 0, broken = 0;
    double worstBefore = 0.0, worstAfter = 0.0;
  };

  SliverOptimisation(MeshingContext& run, RefinementRounds& refinement)
    : run_(run)
    , refinement_(refinement)
  {
  }

  /// Every step the options ask for, in order.
  void run()
  {
    start();
    if (run_.options.perturb)
      perturbKeepingSegments();
    if (run_.options.exude)
      exudeKeepingSegments();
    finish();
  }

  /// The smallest angle before the optimisers, their time limit, the clocks.
  void start()
  {
    optStart_ = Clock::now();
    optCpuStart_ = threadCpu();
    minBefore_ = run_.options.perturb || run_.options.exude ? complexMinAngle(*run_.c3t3) : 0.0;
    unchangedSinceStart_ = true;
    optLimit_ = run_.options.optimisationTimeLimit < 0 ? refinement_.refinementSeconds() : run_.options.optimisationTimeLimit;
  }

  /// CGAL's perturber, then the repair of the sub-segments it broke (or that short sub-segments'
  /// encroachers leave, perturbed or not). The perturber works on the cells at or below its bound
  /// and on no others: where every cell is above it, it is not called (it would spend a scan of
  /// every cell per degree to find nothing).
  void perturbKeepingSegments()
  {
    run_.report(0.45, "perturbation");
    perturbationSkipped_ = minBefore_ > kPerturbationBound + kAngleSlack;
    if (perturbationSkipped_)
      perturbed_.lastBound = kPerturbationBound;
    else
    {
      const size_t max = stepBudget(run_.options.perturbationStepsPerVertex, run_.c3t3->triangulation().number_of_vertices());
      size_t checks = 0;
      perturbed_ = perturb(*run_.c3t3, *run_.domain, optLimit_, max, run_.options.perturbationFailuresPerBound,
        [&] { run_.report(0.45 + 0.35 * phaseProgress(256 * ++checks, max), "perturbation"); }, run_.deadline);
    }
    const bool repaired = refinement_.repairSegmentsAfterPerturbation();
    unchangedSinceStart_ = perturbationSkipped_ && !repaired;
  }

  /// CGAL's exuder changes weights, which can flip a sub-segment out of the (regular)
  /// triangulation, and stopped at its step budget it can leave a cell flatter than any before it:
  /// it is undone when it would break a segment the refinement kept or lower the smallest
  /// dihedral angle.
  void exudeKeepingSegments()
  {
    Exudation e = exude();
    if (e.broken == 0 && e.worstAfter >= e.worstBefore)
      return;
    std::ostringstream why;
    if (e.broken)
      why << "it would have removed " << e.broken << " constrained sub-segments from the mesh";
    else
      why << "it would have lowered the smallest dihedral angle from " << e.worstBefore << " to " << e.worstAfter
          << " degrees";
    undo(e, why.str());
  }

  /// CGAL's exuder, with the record to judge (and undo) it by.
  Exudation exude()
  {
    run_.report(0.8, "exudation");
    Exudation e;
    e.missingBefore = run_.conforming ? run_.segments->countNotEdges() : 0;
    e.before.emplace(*run_.c3t3);
    undoRecordBytes_ = e.before->bytes();
    // a pass over every cell, unless the complex is the one start() measured
    e.worstBefore = unchangedSinceStart_ ? minBefore_ : complexMinAngle(*run_.c3t3);
    // The budget also ends CGAL's exuder where it cycles (seen next to protecting balls); it stops
    // between two cells, where the mesh is consistent. Without a budget, 10 pumps per cell still
    // end a cycle.
    const size_t max = stepBudget(run_.options.exudationStepsPerCell > 0 ? run_.options.exudationStepsPerCell : 10.0,
      run_.c3t3->number_of_cells_in_complex());
    size_t checks = 0;
    exuded_ = omesh::cgal::sequential::exude(*run_.c3t3, optLimit_, max, run_.options.exudationSliverBound,
      [&] { run_.report(0.8 + 0.18 * phaseProgress(256 * ++checks, max), "exudation"); }, run_.deadline);
    if (run_.conforming)
      run_.segments->locateVertices(); // the exuder re-creates vertices: find the segment points again
    const size_t missing = run_.conforming ? run_.segments->countNotEdges() : 0;
    e.broken = missing > e.missingBefore ? missing - e.missingBefore : 0;
    e.worstAfter = complexMinAngle(*run_.c3t3);
    return e;
  }

  /// The complex from before the exuder back, with a warning saying `why`.
  void undo(Exudation& e, const std::string& why)
  {
    const auto lost = e.before->restore(*run_.c3t3);
    e.before.reset();
    if (run_.conforming)
      run_.segments->locateVertices(); // the restored vertices are new ones
    run_.warnings.push_back("exudation undone: " + why);
    if (lost.any()) // not seen: the rebuilt triangulation is the one recorded (ComplexSnapshot.h)
      run_.warnings.push_back("exudation undone, but the mesh from before it came back incomplete (" +
        std::to_string(lost.vertices) + " vertices, " + std::to_string(lost.cells) + " tetrahedra, " +
        std::to_string(lost.facets) + " interface triangles missing)");
  }

  /// The cells the optimisers left across a boundary relabelled, the clocks stopped.
  void finish()
  {
    if (run_.options.perturb || run_.options.exude)
      relabelled_ = relabelCellsAcrossBoundaries(
        *run_.c3t3, run_.oracle, [this](int m) { return run_.options.criteria.of(m).facetDistance; });
    optTime_ = seconds(optStart_);
    optCpu_ = threadCpu() - optCpuStart_;
    run_.deadline.check("optimisation");
  }

  /// Its statistics: steps, whether each optimiser was cut short or gave up, times.
  void record(std::map<std::string, double>& st) const
  {
    if (run_.options.perturb || run_.options.exude)
      st["optimisation.min_dihedral_before"] = minBefore_;
    st["optimisation.perturbation_steps"] = static_cast<double>(perturbed_.steps);
    st["optimisation.perturbation_cut_short"] = perturbed_.cutShort;
    st["optimisation.perturbation_gave_up"] = perturbed_.gaveUp;
    st["optimisation.perturbation_last_bound"] = perturbed_.lastBound;
    st["optimisation.perturbation_skipped"] = perturbationSkipped_;
    st["optimisation.exudation_steps"] = static_cast<double>(exuded_.steps);
    st["optimisation.exudation_cut_short"] = exuded_.cutShort;
    st["optimisation.undo_record_bytes"] = static_cast<double>(undoRecordBytes_);
    st["optimisation.cells_relabelled_by_centroid"] = static_cast<double>(relabelled_);
    st["time.perturbation"] = perturbed_.seconds;
    st["time.exudation"] = exuded_.seconds;
    st["time.optimisation"] = optTime_;
    st["cpu.perturbation"] = perturbed_.cpuSeconds;
    st["cpu.exudation"] = exuded_.cpuSeconds;
    st["cpu.optimisation"] = optCpu_;
  }

private:
  /// A step budget of `perUnit` steps per vertex or cell (0 = none).
  static size_t stepBudget(double perUnit, size_t units)
  {
    return perUnit > 0 ? static_cast<size_t>(std::ceil(perUnit * static_cast<double>(units))) + 1000 : 0;
  }
  /// Progress within a phase: the share of its budget, or a creep toward its end without one.
  static double phaseProgress(size_t steps, size_t max)
  {
    return max ? static_cast<double>(steps) / static_cast<double>(max) : 1.0 - 1.0 / (1.0 + 1e-3 * steps / 256.0);
  }

  MeshingContext& run_;
  RefinementRounds& refinement_;
  Clock::time_point optStart_{};
  double optCpuStart_ = 0.0, optTime_ = 0.0, optCpu_ = 0.0;
  double minBefore_ = 0.0, optLimit_ = 0.0;
  bool perturbationSkipped_ = false; ///< every cell was above the perturber's bound
  bool unchangedSinceStart_ = false;  ///< perturber skipped and nothing repaired: minBefore_ holds
  std::size_t undoRecordBytes_ = 0; ///< the exuder's undo record (ComplexSnapshot::bytes)
  OptimiserRun perturbed_, exuded_;
  size_t relabelled_ = 0; ///< cells the optimisers left across a boundary (relabelCellsAcrossBoundaries)
};
}
