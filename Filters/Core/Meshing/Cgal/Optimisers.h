// SPDX-License-Identifier: GPL-3.0-or-later
// Private to Meshing/OracleMesher.cxx (the sequential Mesh_3 translation unit): CGAL's perturber
// and exuder, abortable, with step budgets and a deadline.
#pragma once

#include "MeshQuality.h"
#include "MeshingDeadline.h"
#include "SequentialTypes.h"
#include "ShapeSummary.h"
#include "WorkerThreads.h"

#include <CGAL/exude_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace omesh::cgal::sequential
{
/// Thrown by OptimiserVisitor when its phase has used its step budget (between two steps, where
/// the mesh is consistent).
struct BudgetReached
{
};

/// Thrown by OptimiserVisitor when the perturber gives up at a bound it cannot reach.
struct GaveUp
{
};

/// The perturber's current bound. CGAL's perturber raises a bound on the smallest dihedral angle
/// one degree at a time (up to 12); at each it moves the vertices of the cells below it. At a bound
/// it cannot reach, every vertex that none of its perturbations improves has cost all of them (40
/// gradient steps each of three kinds and 100 random moves): measured, the last bound took 40-75%
/// of the perturbation time for a few tenths of a degree. It gives up there after `allowed` such
/// vertices plus `perStep` per attempt at that bound (deterministic, unlike a time limit).
struct PerturbationBound
{
  double allowed = 0.0; ///< 0 = never give up (CGAL's behaviour)
  double perStep = 0.0;
  std::size_t failures = 0; ///< vertices no perturbation moved, at this bound
  std::size_t steps = 0;    ///< attempts at this bound
  double done = 0.0;        ///< last bound worked through to the end (reached or not)
  void step()
  {
    ++steps;
    if (allowed > 0 && static_cast<double>(failures) > allowed + perStep * static_cast<double>(steps))
      throw GaveUp{};
  }
};

/// CGAL's optimiser visitors: count the steps (a perturbation attempt on one vertex, or one cell
/// pumped), stop at `budget` steps (0 = none), ask the deadline at every step and `check` (which
/// may throw MeshingAborted) every 256 steps. Copied by CGAL: the counts live outside.
struct OptimiserVisitor
{
  std::function<void()> check;
  std::size_t* steps;
  std::size_t budget;
  const MeshingDeadline* deadline;
  const char* phase;
  PerturbationBound* bound = nullptr; ///< the perturber's
  void step()
  {
    deadline->check(phase);
    if (++*steps % 256 == 0)
      check();
    if (budget && *steps >= budget)
      throw BudgetReached{};
  }
  void bound_reached(double b)
  {
    if (bound)
      *bound = PerturbationBound{ bound->allowed, bound->perStep, 0, 0, b };
  }
  void end_of_perturbation_iteration(std::size_t)
  {
    step();
    if (bound)
      bound->step();
  }
  void after_cell_pumped(std::size_t) { step(); }
};

/// CGAL's sliver criterion of the optimisers (smallest dihedral angle), which also asks the
/// deadline: one perturbation or one pump evaluates the whole star of a vertex, with no visitor
/// call in between, and next to a cluster of tiny facets (refinement stopped at the vertex budget)
/// such a star took minutes.
class WatchedDihedralCriterion : public CGAL::Mesh_3::Min_dihedral_angle_criterion<Tr>
{
  using Base = CGAL::Mesh_3::Min_dihedral_angle_criterion<Tr>;

public:
  WatchedDihedralCriterion(double bound, const Tr& tr, const MeshingDeadline& deadline, const char* phase)
    : Base(bound, tr)
    , deadline_(&deadline)
    , phase_(phase)
  {
  }
  using Base::operator();
  double operator()(const typename Base::Tetrahedron_3& t) const override
  {
    deadline_->tick(phase_);
    return Base::operator()(t);
  }

private:
  const MeshingDeadline* deadline_;
  const char* phase_;
};

/// Smallest dihedral angle (degrees) of the cells given to it: the minimum of minDihedralAngle
/// over them, but a cell whose angles are certainly at least the smallest so far
/// (dihedralAnglesCertainlyAtLeast: no square root, no acos) is not measured. The result does not
/// depend on the order of the cells.
class SmallestCellAngle
{
public:
  template <class Cell_handle>
  void add(const Cell_handle& c)
  {
    const Vec3 a = toVec(c->vertex(0)->point().point()), b = toVec(c->vertex(1)->point().point()),
               d = toVec(c->vertex(2)->point().point()), e = toVec(c->vertex(3)->point().point());
    if (smallest_ < 90.0 && dihedralAnglesCertainlyAtLeast(a, b, d, e, cosSmallest_))
      return;
    const double angle = minDihedralAngle(a, b, d, e);
    if (angle < smallest_)
    {
      smallest_ = angle;
      cosSmallest_ = std::cos(smallest_ * M_PI / 180.0);
    }
  }
  double degrees() const { return smallest_; }

private:
  double smallest_ = 180.0, cosSmallest_ = -1.0;
};

/// Smallest dihedral angle (degrees) of the cells of the complex (SmallestCellAngle), in chunks
/// of the cells on the threads runOnThreads allows (reading the triangulation only; the minimum
/// is the same in any order).
inline double complexMinAngle(const C3t3& c3t3)
{
  std::vector<typename C3t3::Cell_handle> cells;
  cells.reserve(c3t3.number_of_cells_in_complex());
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    cells.push_back(c);
  const std::size_t chunks = chunkCount(cells.size(), kTetsPerChunk);
  std::vector<double> smallest(chunks, 180.0);
  forEachChunk(cells.size(), chunks, [&](std::size_t k, std::size_t begin, std::size_t end) {
    SmallestCellAngle part;
    for (std::size_t i = begin; i < end; ++i)
      part.add(cells[i]);
    smallest[k] = part.degrees();
  });
  return *std::min_element(smallest.begin(), smallest.end());
}

/// How one optimiser ended.
struct OptimiserRun
{
  std::size_t steps = 0;
  bool cutShort = false; ///< stopped by its step budget or time limit, not by its own bound
  bool gaveUp = false;   ///< the perturber gave up at a bound it could not reach
  double lastBound = 0.0; ///< the perturber's last bound (degrees) worked through to the end
  double seconds = 0.0;
  double cpuSeconds = 0.0; ///< of the calling thread
};

/// Runs a CGAL optimiser (perturber or exuder) with an OptimiserVisitor and its budget.
template <class Optimiser>
OptimiserRun runOptimiser(C3t3& c3t3, Optimiser& optimiser, std::size_t budget, std::function<void()> check,
  const MeshingDeadline& deadline, const char* phase, PerturbationBound* bound = nullptr)
{
  const auto started = Clock::now();
  const double cpuStart = threadCpu();
  OptimiserRun run;
  auto stopped = [&] {
    // the optimisers cache sliver values in the cells and clear them only when they end normally
    for (auto c = c3t3.triangulation().finite_cells_begin(); c != c3t3.triangulation().finite_cells_end(); ++c)
      c->reset_cache_validity();
  };
  try
  {
    run.cutShort =
      optimiser(OptimiserVisitor{ std::move(check), &run.steps, budget, &deadline, phase, bound }) == CGAL::TIME_LIMIT_REACHED;
  }
  catch (const BudgetReached&)
  {
    run.cutShort = true;
    stopped();
  }
  catch (const GaveUp&)
  {
    run.gaveUp = true;
    stopped();
  }
  if (bound)
    run.lastBound = bound->done;
  run.seconds = seconds(started);
  run.cpuSeconds = threadCpu() - cpuStart;
  return run;
}

/// The last of CGAL's perturbations for a vertex: when it fails too, no perturbation moved the
/// vertex, which counts as a failure at the current bound.
template <class Base, class Criterion>
struct LastPerturbation : Base
{
  using Base::Base;
  PerturbationBound* bound = nullptr;

protected:
  std::pair<bool, typename Base::Vertex_handle> do_perturb(const typename Base::Vertex_handle& v,
    const std::vector<typename Base::Cell_handle>& slivers, C3t3& c3t3, const MeshDomain& domain,
    const Criterion& criterion, const typename Base::FT& sliverBound, std::vector<typename Base::Vertex_handle>& modified,
    bool* couldLock) const override
  {
    auto r = Base::do_perturb(v, slivers, c3t3, domain, criterion, sliverBound, modified, couldLock);
    if (!r.first)
      ++bound->failures;
    return r;
  }
};

/// The perturber's last bound (degrees): CGAL's default (perturb_mesh_3 takes 0 for the sliver
/// criterion's default value, 12).
constexpr double kPerturbationBound = 12.0;

/// As CGAL::perturb_mesh_3 with its defaults (bounds up to kPerturbationBound, CGAL's perturbations),
/// abortable, stopped after `budget` steps (0 = none) or `timeLimit` seconds (0 = none), giving up
/// at a bound after `failuresPerBound` vertices it could not move plus 1% of its attempts there
/// (0 = never).
inline OptimiserRun perturb(C3t3& c3t3, const MeshDomain& domain, double timeLimit, std::size_t budget,
  double failuresPerBound, std::function<void()> check, const MeshingDeadline& deadline)
{
  // as CGAL's default_sliver_criterion, watched
  using Criterion = WatchedDihedralCriterion;
  const Criterion criterion(kPerturbationBound, c3t3.triangulation(), deadline, "perturbation");
  CGAL::Mesh_3::Sliver_perturber<C3t3, MeshDomain, Criterion, OptimiserVisitor> perturber(c3t3, domain, criterion);
  PerturbationBound bound;
  bound.allowed = failuresPerBound;
  bound.perStep = failuresPerBound > 0 ? 0.01 : 0.0;
  // CGAL's default_perturbation_vector (same kinds, same parameters), the last one watched
  perturber.add_perturbation(new CGAL::Mesh_3::Sq_radius_perturbation<C3t3, MeshDomain, Criterion>(40, 0.05));
  perturber.add_perturbation(new CGAL::Mesh_3::Volume_perturbation<C3t3, MeshDomain, Criterion>(40, 0.05));
  perturber.add_perturbation(new CGAL::Mesh_3::Dihedral_angle_perturbation<C3t3, MeshDomain, Criterion>(40, 0.05));
  auto* last = new LastPerturbation<CGAL::Mesh_3::Li_random_perturbation<C3t3, MeshDomain, Criterion>, Criterion>(100, 0.15);
  last->bound = &bound;
  perturber.add_perturbation(last);
  perturber.set_time_limit(timeLimit);
  return runOptimiser(c3t3, perturber, budget, std::move(check), deadline, "perturbation", &bound);
}

/// Caches `criterion`'s value in every cell of the complex as CGAL's sliver criteria cache it
/// (Sliver_criterion::operator()(Cell_handle): the same value, forced to a double), in chunks on
/// the threads runOnThreads allows: CGAL's exuder starts with the value of every cell, on one
/// thread, and takes the cached ones. Each cell is written by one thread.
template <class Criterion>
void cacheSliverValues(const C3t3& c3t3, const Criterion& criterion)
{
  std::vector<typename C3t3::Cell_handle> cells;
  cells.reserve(c3t3.number_of_cells_in_complex());
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    cells.push_back(c);
  const Tr& tr = c3t3.triangulation();
  forEachChunk(cells.size(), chunkCount(cells.size(), kTetsPerChunk), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      cells[i]->set_sliver_value(CGAL::IA_force_to_double(criterion(tr.tetrahedron(cells[i]))));
  });
}

/// As CGAL::exude_mesh_3, pumping the cells below `sliverBound` degrees (0 = every cell, CGAL's
/// default), abortable, stopped as perturb().
inline OptimiserRun exude(C3t3& c3t3, double timeLimit, std::size_t budget, double sliverBound, std::function<void()> check,
  const MeshingDeadline& deadline)
{
  using Criterion = WatchedDihedralCriterion;
  Criterion criterion(sliverBound, c3t3.triangulation(), deadline, "exudation");
  cacheSliverValues(c3t3, criterion);
  CGAL::Mesh_3::Slivers_exuder<C3t3, Criterion, OptimiserVisitor> exuder(c3t3, criterion);
  exuder.set_time_limit(timeLimit);
  return runOptimiser(c3t3, exuder, budget, std::move(check), deadline, "exudation");
}
}
