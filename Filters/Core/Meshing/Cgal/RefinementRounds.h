// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: refinement, the rules T1.2, T2 and T3 in Mesh_3's levels.
#pragma once

#include "ConformingMesher3.h"
#include "MaterialCriteria3.h"
#include "MeshSizeEstimate.h"
#include "MeshingContext.h"
#include "ParallelRefinement.h"
#include "SegmentRefinementLevel.h"
#include "ShapeSummary.h"
#include "WorkerThreads.h"

#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace omesh::cgal::sequential
{
/// CGAL's parallel levels refine cells in batches, not worst first; below this radius-edge bound
/// that order cascades (3-9x the sequential run's vertices at 1.1 on bone/implant scenes; within
/// 1.3x at 1.2 and 1.3). The parallel levels refine to this bound at most, the sequential round
/// after them to the material's own.
constexpr double kParallelRadiusEdgeFloor = 1.2;

/// The finishing round after the vertex budget (RefinementRounds::finishAfterBudget) may add this
/// share of the budget, at least kFinishOverdraftMin vertices (see REFERENCE.md, "Time limit").
constexpr double kFinishOverdraftShare = 0.1;
constexpr size_t kFinishOverdraftMin = 500;
/// The finishing round refines cells below this angle at least (the default SliverAngle: what
/// removes flat tetrahedra; the picking angle would spend half of a small budget on it).
constexpr double kFinishSliverAngle = 1.0;
/// Around a sub-segment missing from the complex, the run's criteria apply within this many times
/// its length (RefinementRounds::missingRegion).
constexpr double kFinishRegionFactor = 3.0;

/// Thrown by a run whose parallel refinement reached the vertex budget: CGAL's parallel levels
/// refine depth-first (each task refines the bad elements its insertion made, at once), so a
/// parallel run stopped early holds its vertices in deep clusters where the sequential run, worst
/// element first, spreads them (with criteria far beyond the budget: thousands of flat
/// tetrahedra). meshOracle then meshes again on one thread.
struct ParallelBudgetReached
{
  double seconds = 0.0; ///< of the run until then
  std::size_t vertices = 0;
};

/// The cells of the complex that `criteria`'s cell criteria call bad (above a size or radius-edge
/// bound, below the sliver angle), sorted by handle. The criteria are read-only (the parallel
/// refinement evaluates them on its threads), so the cells are judged in chunks on the threads
/// runOnThreads allows.
inline std::vector<Tr::Cell_handle> badCellsOf(const C3t3& c3t3, const Criteria& criteria)
{
  const auto& judge = criteria.cell_criteria_object();
  std::vector<Tr::Cell_handle> cells;
  cells.reserve(c3t3.number_of_cells_in_complex());
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    cells.push_back(c);
  const std::size_t chunks = chunkCount(cells.size(), kTetsPerChunk);
  std::vector<std::vector<Tr::Cell_handle>> found(chunks);
  forEachChunk(cells.size(), chunks, [&](std::size_t k, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (judge(c3t3.triangulation(), cells[i]))
        found[k].push_back(cells[i]);
  });
  std::vector<Tr::Cell_handle> bad;
  for (const auto& part : found)
    bad.insert(bad.end(), part.begin(), part.end());
  std::sort(bad.begin(), bad.end());
  return bad;
}

/// `options` with every radius-edge bound below `floor` raised to it (bounds <= 0, none, kept).
inline MesherOptions withRadiusEdgeAtLeast(MesherOptions options, double floor)
{
  auto raise = [floor](std::optional<double>& bound) {
    if (bound && *bound > 0 && *bound < floor)
      bound = floor;
  };
  raise(options.criteria.global.cellRadiusEdgeRatio);
  for (auto& entry : options.criteria.perMaterial)
    raise(entry.second.cellRadiusEdgeRatio);
  return options;
}

/// Refinement (section 5 of the paper): the segment, facet and cell levels together (rules T1.2,
/// T2, T3), one step at a time, with progress, abort, the deadline and the vertex budget in our
/// hands: Conforming with the segment level below CGAL's facets and cells (ConformingMesher3),
/// the cells at picked points (SliverAvoidingPoint), on several threads where asked
/// (ParallelRefinement.h, then one sequential round where they left work); after the vertex
/// budget, a finishing round with only what validity needs; after perturbation, a repair round
/// around the sub-segments it broke.
///
/// @warning A parallel refinement that reaches the vertex budget throws ParallelBudgetReached.
/// @sa InitialComplex (before it), SliverOptimisation (after it)
class RefinementRounds
{
public:
  using Segments = SegmentRefinementLevel<C3t3>;
  using Counters = SegmentState<C3t3>::Counters;
  using Mesher = CGAL::Mesh_3::Mesher_3<C3t3, Criteria, MeshDomain>;

  explicit RefinementRounds(MeshingContext& run)
    : run_(run)
  {
  }

  /// The segment, facet and cell levels together (rules T1.2, T2, T3), one step at a time.
  void refineAllLevels()
  {
    const auto refineStart = Clock::now();
    const double refineCpuStart = threadCpu();
    expected_ = expectedVertices();
    if (run_.conforming && run_.threads > 1)
      refineConformingInParallel();
    const auto tailStart = Clock::now();
    if (run_.conforming && run_.threads > 1 && (budgetHit_ || stalled_ || !parallelLeftWork()))
    {
      // stopped in the parallel phase, or nothing left for the sequential round: only why
      // sub-segments are missing
      Segments level(*run_.c3t3, *run_.segments, run_.domain->index_from_curve_index(1));
      missing_ = level.missingCensus([this](const Vec3& a, const Vec3& b) { return run_.touchesMaterial(a, b); });
    }
    else
    {
      parallelPhases_.tailRan = run_.conforming && run_.threads > 1;
      refineOnce();
    }
    if (run_.conforming && run_.threads > 1)
      parallelPhases_.tailSeconds = seconds(tailStart);
    warnIfUnfinished("");
    finishAfterBudget();
    run_.c3t3->clear_manifold_info();
    refinedVertices_ = run_.c3t3->triangulation().number_of_vertices();
    refineTime_ = seconds(refineStart);
    callingThreadRefineCpu_ = threadCpu() - refineCpuStart;
    refineCpu_ = callingThreadRefineCpu_ + parallelCpu_;
  }

  /// The perturber never moves segment vertices, but a moved neighbour can land in a diametral
  /// ball and so break a sub-segment: refine again (the segment level splits what was encroached;
  /// weights are still zero here, after the exuder they are not).
  /// Returns whether it may have changed the complex (false: nothing to repair, nothing touched).
  bool repairSegmentsAfterPerturbation()
  {
    // after the vertex budget: only when the finishing round made the segments present, with its
    // criteria and what is left of its overdraft
    if (!run_.conforming || (budgetHit_ && !finish_.completed) || stalled_)
      return false;
    run_.segments->reindex();
    // The round looks only around the removals and the broken sub-segments (the insertions'
    // stars follow): a scan of every element would also refine the cells the perturber left
    // above a tight radius-edge bound, which a run without repair keeps (at radius-edge 1.1 that
    // doubled the mesh for 79 splits). Nothing to look at: nothing to repair.
    std::set<Tr::Vertex_handle> region;
    const bool removed = run_.segments->removeEncroachersOfShortSubSegments(&region) > 0;
    if (removed)
      run_.c3t3->rescan_after_load_of_triangulation(); // the removals deleted cells of the complex
    addVerticesAtSegmentWork(region);
    repairAround(region);
    return removed || !region.empty();
  }

  /// The repair round after perturbation, its first scan only around `region` (nothing to do
  /// when it is empty).
  void repairAround(const std::set<Tr::Vertex_handle>& region)
  {
    if (region.empty())
      return;
    tailRegion_.assign(region.begin(), region.end());
    const Counters& count = run_.segments->counters();
    const size_t before = count.splitsEncroached + count.splitsVetoed;
    refinePhase_ = "refinement after perturbation (segment repair)";
    refineOnce();
    warnIfUnfinished("segment repair after perturbation: ");
    repaired_ = count.splitsEncroached + count.splitsVetoed - before;
    run_.c3t3->clear_manifold_info();
  }

  /// Never silent: pieces the segment level could not make mesh edges, how many, why and where.
  void warnMissingPieces()
  {
    if (!missing_.short_ && !missing_.refused)
      return;
    std::ostringstream o;
    o << "segment level: " << missing_.short_ + missing_.refused << " feature-line piece(s) are no mesh edges";
    if (missing_.short_)
      o << "; " << missing_.short_ << " shorter than the split floor (shortest " << missing_.shortest
        << ", first at (" << missing_.firstShort.x << ", " << missing_.firstShort.y << ", " << missing_.firstShort.z
        << "))";
    if (missing_.refused)
      o << "; " << missing_.refused << " whose split failed or was refused";
    run_.warnings.push_back(o.str());
  }

  /// Refinement steps so far, and the vertices of a running parallel refinement as last seen (0
  /// when none runs), for the time limit's message.
  size_t steps() const { return steps_; }
  /// Whether refinement stopped at the vertex budget (the criteria not met everywhere).
  bool budgetHit() const { return budgetHit_; }
  size_t parallelVertices() const { return parallelVertices_; }
  /// Wall seconds of the refinement (the optimisers' default time limit).
  double refinementSeconds() const { return refineTime_; }

  /// Its statistics: steps, rounds, threads, what each rule did, the finishing round, times.
  void record(std::map<std::string, double>& st) const
  {
    st["refinement_steps"] = static_cast<double>(steps_);
    if (budgetHit_)
    {
      // the finishing round after the vertex budget (finishAfterBudget; not run after a stall)
      st["refinement.finish_vertices"] = static_cast<double>(finish_.vertices);
      st["refinement.finish_overdraft"] = static_cast<double>(finish_.overdraft);
      st["refinement.finish_completed"] = finish_.completed;
      st["refinement.finish_missing_sub_segments"] = static_cast<double>(finish_.regionBalls);
    }
    st["refinement_threads"] = run_.threads;
    st["refinement_rounds"] = rounds_;
    if (run_.threads > 1)
      st["parallel.repeated_vertices_refused"] = static_cast<double>(parallelPhases_.repeatsRefused);
    if (run_.conforming && run_.threads > 1)
    {
      // the three phases of refineConformingInParallel: vertices after each, wall seconds of each
      const ParallelPhases& ph = parallelPhases_;
      st["parallel_conforming.vertices_after_segments"] = static_cast<double>(ph.segmentVertices);
      st["parallel_conforming.vertices_after_parallel"] = static_cast<double>(ph.parallelVertices);
      st["parallel_conforming.vertices_after_sequential_tail"] = static_cast<double>(refinedVertices_);
      st["parallel_conforming.time_segments"] = ph.segmentSeconds;
      st["parallel_conforming.time_parallel"] = ph.parallelSeconds;
      st["parallel_conforming.time_sequential_tail"] = ph.tailSeconds;
      st["parallel_conforming.elements_left_to_sequential_tail"] = static_cast<double>(ph.leftBad.size());
      st["parallel_conforming.sequential_tail_ran"] = ph.tailRan;
    }
    addSegmentStatistics(st);
    st["time.refinement"] = refineTime_;
    // CPU seconds of the calling thread and of the refinement's threads (the wall time depends on
    // the machine's load)
    st["cpu.refinement"] = refineCpu_;
    // along the critical path (the calling thread's plus the busiest refinement thread's): its
    // time on idle cores, the same as cpu.refinement when sequential
    st["cpu.refinement_critical_path"] = callingThreadRefineCpu_ + parallelBusiestCpu_;
  }

private:
  /// Expected number of vertices, for the progress bar only: about one per cell-size cube of each
  /// material (measured on the demo scene), from a coarse sampling of the oracle.
  double expectedVertices() const { return std::max(1000.0, estimateCellVertices(run_.oracle, run_.options.criteria)); }

  /// Steps `mesher` until it is done and `more` (asked when it is) queues nothing more: progress,
  /// abort and the vertex budget in our hands. The vertex limit is asked at every step: in the
  /// finishing round (finish_.active) the finishing round's (its overdraft), else the vertex budget.
  template <class M>
  void drive(M& mesher, const std::function<bool()>& more)
  {
    mesher.initialize();
    size_t lastCount = 0, idleChecks = 0;
    bool stopped = false;
    while (!mesher.is_algorithm_done() || (more && more()))
    {
      mesher.one_step();
      if (steps_ % 16 == 0)
        run_.deadline.check(refinePhase_); // also where steps insert nothing
      // the limit at every step (one load): a budget means that many vertices, not a few hundred more
      const size_t limit = finish_.active ? finish_.limit : run_.options.maximumNumberOfVertices;
      if (limit && run_.c3t3->triangulation().number_of_vertices() >= limit)
      {
        (finish_.active ? finish_.overdrawn : budgetHit_) = stopped = true;
        ++steps_;
        break;
      }
      if (++steps_ % 512 == 0)
      {
        const size_t count = run_.c3t3->triangulation().number_of_vertices();
        // A refinement point that repeats an existing vertex inserts nothing and is tried again
        // forever (seen with protecting balls): stop after ~100k idle steps instead of hanging.
        idleChecks = count == lastCount ? idleChecks + 1 : 0;
        lastCount = count;
        if (idleChecks >= 200)
        {
          stalled_ = true;
          mesher.fix_c3t3();
          break;
        }
        const double n = static_cast<double>(count);
        run_.report(0.05 + 0.4 * std::min(1.0, n / expected_), "refinement");
      }
    }
    if (stopped)
      mesher.fix_c3t3();
  }

  /// The criteria of the current round: the run's, or in the finishing round after the vertex
  /// budget only what validity needs (validityMeshCriteria).
  const Criteria& roundCriteria() const { return finish_.active ? *finish_.criteria : *run_.criteria; }

  /// One refinement round: Conforming with the segment level below the facets; without one, the
  /// same mesher with no segments where the cells pick their points; else CGAL's Mesher_3. On
  /// one thread in the finishing round.
  void refineOnce()
  {
    const Criteria& criteria = roundCriteria();
    if (run_.conforming)
    {
      const auto wanted = [this](const Vec3& a, const Vec3& b) { return run_.touchesMaterial(a, b); };
      Segments level(*run_.c3t3, *run_.segments, run_.domain->index_from_curve_index(1));
      ConformingMesher3<C3t3, Criteria, MeshDomain> mesher(
        *run_.c3t3, *run_.domain, criteria, level, CGAL::FACET_VERTICES_ON_SURFACE, pickingRegionOf(run_.options));
      mesher.restrictFirstScanTo(std::move(tailRegion_), std::move(badCells_)); // empty but after the parallel phase
      tailRegion_.clear();
      badCells_.clear();
      drive(mesher, [&] { return level.queueMissingFromComplex(wanted) > 0; });
      countPicks(mesher.pickingCounters());
      missing_ = level.missingCensus(wanted);
    }
    else if (run_.threads > 1 && !finish_.active)
    {
      parallelPhases_.leftBad.clear(); // this round's refused points only
      refineInParallelOnce();
      // the parallel levels refine at circumcentres, to kParallelRadiusEdgeFloor at most; the
      // cells they leave bad (slivers, tighter radius-edge bounds) and the elements whose points
      // the guard refused are refined here, on one thread, at picked points where picking is on.
      // Not ProtectingBalls: its balls' weights.
      if (run_.options.strategy != FeatureStrategy::ProtectingBalls && !budgetHit_ && !stalled_)
      {
        auto around = verticesAroundPoints(parallelPhases_.leftBad);
        auto bad = badCellsOf(*run_.c3t3, *run_.criteria);
        if (!around.empty() || !bad.empty())
          refineAtPickedPoints(std::move(around), std::move(bad));
      }
    }
    else if (picksRefinementPoints(run_.options))
      refineAtPickedPoints({});
    else
    {
      Mesher mesher(*run_.c3t3, *run_.domain, criteria, CGAL::FACET_VERTICES_ON_SURFACE);
      drive(mesher, {});
    }
    ++rounds_;
  }

  /// The mesher without segments, its cells refined at picked points (circumcentres where picking
  /// is off); its first scan only around `region` and at `badCells` unless both are empty (after
  /// a parallel refinement: around the points the guard refused, and the cells left bad; the rest
  /// met the criteria when CGAL's queues ran empty, and a scan of every facet would cost an
  /// intersection each).
  void refineAtPickedPoints(std::vector<Tr::Vertex_handle> region, std::vector<Tr::Cell_handle> badCells = {})
  {
    SegmentState<C3t3> none(*run_.c3t3, SegmentSet{});
    Segments level(*run_.c3t3, none, run_.domain->index_from_curve_index(1));
    ConformingMesher3<C3t3, Criteria, MeshDomain> mesher(
      *run_.c3t3, *run_.domain, roundCriteria(), level, CGAL::FACET_VERTICES_ON_SURFACE, pickingRegionOf(run_.options));
    mesher.restrictFirstScanTo(std::move(region), std::move(badCells));
    drive(mesher, {});
    countPicks(mesher.pickingCounters());
  }

  void countPicks(const PickingRegion::Counters& picked)
  {
    picking_.cells += picked.cells;
    picking_.moved += picked.moved;
    picking_.unreached += picked.unreached;
  }

  /// CGAL's parallel refinement on run_.threads threads, from and back into the sequential complex.
  /// Progress, abort and the deadline are asked from this thread every 50 ms (a throw stops the
  /// refinement); the vertex budget and a stall stop it as they stop drive().
  void refineInParallelOnce(const SegmentSet* protectedSegments = nullptr)
  {
    // the sequential round after the parallel levels finishes what they leave above this bound
    // (not with ProtectingBalls: nothing follows them there)
    const MesherOptions parallelOptions = run_.options.strategy == FeatureStrategy::ProtectingBalls
      ? run_.options
      : withRadiusEdgeAtLeast(run_.options, kParallelRadiusEdgeFloor);
    const ParallelRefinementRun run =
      refineInParallel(*run_.c3t3, *run_.domain, parallelOptions, run_.edgeSize, run_.threads, [this](size_t n) {
        parallelVertices_ = n;
        run_.deadline.check(refinePhase_);
        run_.report(0.05 + 0.4 * std::min(1.0, static_cast<double>(n) / expected_), "refinement");
      }, protectedSegments);
    parallelPhases_.leftBad.insert(parallelPhases_.leftBad.end(), run.leftBad.begin(), run.leftBad.end());
    parallelPhases_.repeatsRefused += run.repeatsRefused;
    parallelVertices_ = 0; // the complex holds them again
    if (run.budgetHit) // meshOracle meshes again on one thread: nothing of this run is kept
      throw ParallelBudgetReached{ run_.deadline.elapsed(), run_.c3t3->triangulation().number_of_vertices() };
    stalled_ = run.stalled;
    parallelCpu_ += run.cpuSeconds;
    parallelBusiestCpu_ += run.busiestThreadCpu;
    if (stalled_) // the cells the stop left out of the complex, as drive() does
      Mesher(*run_.c3t3, *run_.domain, *run_.criteria, CGAL::FACET_VERTICES_ON_SURFACE).fix_c3t3();
  }

  /// Conforming on run_.threads threads, before the sequential round (refineOnce) that finishes it:
  /// 1. the segment level alone (T1.2 against the initial points), sequential: every sub-segment
  ///    gets an empty diametral ball;
  /// 2. CGAL's parallel facet and cell levels above a read-only guard of those balls
  ///    (refineInParallel with the sub-segments): a point inside a ball is not inserted and its
  ///    element stays bad, so the sub-segments do not change while the threads refine;
  /// 3. (the caller) the sequential Conforming round on the copied-back complex, where work was
  ///    left (verticesAroundLeftWork; a full scan of every facet and cell would cost a third of a
  ///    sequential refinement): it splits the sub-segments the refused points encroached
  ///    (T2.1/T3.1) and ends as a sequential run ends, with its guarantees. Skipped when nothing
  ///    was left.
  void refineConformingInParallel()
  {
    const auto start = Clock::now();
    {
      Segments level(*run_.c3t3, *run_.segments, run_.domain->index_from_curve_index(1));
      Segments::Visitor none{ [](const Tr::Weighted_point&, Segments::Zone&) {}, [](const Tr::Vertex_handle&) {} };
      level.queueAll();
      for (size_t k = 0; !level.is_algorithm_done(); ++k)
      {
        level.one_step(none);
        if (k % 16 == 0)
          run_.deadline.check(refinePhase_);
      }
    }
    parallelPhases_.segmentVertices = run_.c3t3->triangulation().number_of_vertices();
    parallelPhases_.segmentSeconds = seconds(start);
    const auto parallelStart = Clock::now();
    refineInParallelOnce(&run_.segments->segments());
    run_.segments->locateVertices(); // the copy back made new vertices
    run_.segments->reindex();
    parallelPhases_.parallelVertices = run_.c3t3->triangulation().number_of_vertices();
    parallelPhases_.parallelSeconds = seconds(parallelStart);
  }

  /// After the parallel phase: whether the sequential round has anything to do (and where: sets
  /// tailRegion_). It has not when the guard left no element bad (CGAL's levels ended with empty
  /// queues: the criteria hold), no vertex lies in a sub-segment's diametral ball (T1.2) and every
  /// wanted sub-segment is an edge of the complex (section 5).
  bool parallelLeftWork()
  {
    tailRegion_ = verticesAroundLeftWork();
    // the cells the threads left bad: slivers below the picking angle (they refine at
    // circumcentres), radius-edge bounds tighter than kParallelRadiusEdgeFloor
    badCells_ = badCellsOf(*run_.c3t3, *run_.criteria);
    return !tailRegion_.empty() || !badCells_.empty();
  }

  /// Where the sequential round after the parallel phase looks (ConformingMesher3::
  /// restrictFirstScanTo): the vertices of the conflict zone of each point the guard refused
  /// (the elements left bad are among their cells), and the ends of every sub-segment that is
  /// encroached or missing from the complex.
  std::vector<Tr::Vertex_handle> verticesAroundLeftWork() const
  {
    std::set<Tr::Vertex_handle> region;
    addVerticesAround(parallelPhases_.leftBad, region);
    addVerticesAtSegmentWork(region);
    return { region.begin(), region.end() };
  }

  /// Adds the ends of every sub-segment that is encroached or missing from the complex.
  void addVerticesAtSegmentWork(std::set<Tr::Vertex_handle>& region) const
  {
    const auto wanted = [this](const Vec3& a, const Vec3& b) { return run_.touchesMaterial(a, b); };
    for (size_t s = 0; s < run_.segments->size(); ++s)
      if (run_.segments->encroached(static_cast<int>(s)) || run_.segments->missingFromComplex(static_cast<int>(s), wanted))
        for (int k : { 0, 1 })
          region.insert(run_.segments->vertexOf(run_.segments->end(static_cast<int>(s), k)));
  }

  /// The vertices of the conflict zones of `points` (a point on a vertex has none), each once.
  std::vector<Tr::Vertex_handle> verticesAroundPoints(const std::vector<Vec3>& points) const
  {
    std::set<Tr::Vertex_handle> region;
    addVerticesAround(points, region);
    return { region.begin(), region.end() };
  }

  void addVerticesAround(const std::vector<Vec3>& points, std::set<Tr::Vertex_handle>& region) const
  {
    Tr& tr = run_.c3t3->triangulation();
    std::vector<Tr::Cell_handle> zone;
    Tr::Cell_handle hint;
    for (const Vec3& p : points)
    {
      const Tr::Weighted_point wp(toPoint(p));
      Tr::Locate_type lt;
      int li, lj;
      hint = tr.locate(wp, lt, li, lj, hint);
      if (lt == Tr::VERTEX)
        continue;
      zone.clear();
      tr.find_conflicts(wp, hint, CGAL::Emptyset_iterator(), std::back_inserter(zone), CGAL::Emptyset_iterator());
      for (const auto& c : zone)
        for (int k = 0; k < 4; ++k)
          if (!tr.is_infinite(c->vertex(k)))
            region.insert(c->vertex(k));
    }
  }

  /// A refinement round that ended at the vertex budget, at the finishing round's overdraft or
  /// stalled says so (`when`: which round).
  void warnIfUnfinished(const std::string& when)
  {
    if (stalled_)
      run_.warnings.push_back(when + "refinement stalled (100k steps without a new vertex: a refinement point "
                          "repeats an existing vertex); the criteria are not met everywhere");
    if (finish_.active)
    {
      if (finish_.overdrawn)
        run_.warnings.push_back(when + "the finishing round after the vertex budget stopped at its overdraft of " +
          std::to_string(finish_.overdraft) + " vertices (10 % of the budget, at least " +
          std::to_string(kFinishOverdraftMin) + "): the mesh may keep feature-line pieces that are no mesh edges, facets with vertices off "
          "the surface or slivers (the validity check names what is left)");
    }
    else if (budgetHit_)
      run_.warnings.push_back(when + "refinement stopped at MaximumNumberOfVertices = " +
        std::to_string(run_.options.maximumNumberOfVertices) + ": the criteria are not met everywhere");
  }

  /// The overdraft of the finishing round: 10 % of the vertex budget, at least kFinishOverdraftMin.
  static size_t finishOverdraft(size_t budget)
  {
    return std::max(kFinishOverdraftMin, static_cast<size_t>(std::ceil(kFinishOverdraftShare * static_cast<double>(budget))));
  }

  /// After refinement stopped at the vertex budget: the partial mesh made valid. The same levels
  /// (segments, facets, cells at picked points; CGAL's Mesher_3 for ProtectingBalls) run once
  /// more, on one thread, with only what validity needs (validityMeshCriteria: sub-segments
  /// present as mesh edges, restricted facets' vertices on the surface, no cell below
  /// max(SliverAngle, kFinishSliverAngle); no size, distance, facet-angle or radius-edge bound but
  /// around the sub-segments missing from the complex, missingRegion), until they are met or the
  /// round has added finishOverdraft vertices. The time limit and abort apply as in any round.
  /// Not after a stall (a point repeating a vertex would stall it again).
  void finishAfterBudget()
  {
    if (!budgetHit_ || stalled_)
      return;
    const size_t start = run_.c3t3->triangulation().number_of_vertices();
    finish_.overdraft = finishOverdraft(run_.options.maximumNumberOfVertices);
    finish_.limit = start + finish_.overdraft;
    auto region = std::make_shared<CriteriaRegion>(missingRegion());
    finish_.regionBalls = region->size();
    const double angle = std::max(run_.options.sliverAngle, kFinishSliverAngle);
    finish_.criteria = std::make_unique<Criteria>(validityMeshCriteria<Tr>(
      run_.options, run_.criteria->edge_criteria_object(), angle, pickingRegionOf(run_.options).targetAngle, std::move(region)));
    finish_.active = true;
    const char* phase = refinePhase_;
    refinePhase_ = "refinement (finishing round after the vertex budget)";
    run_.report(0.45, "refinement (finishing round after the vertex budget)");
    refineOnce();
    refinePhase_ = phase;
    finish_.vertices = run_.c3t3->triangulation().number_of_vertices() - start;
    finish_.completed = !finish_.overdrawn && !stalled_;
    warnIfUnfinished("");
  }

  /// Where the finishing round applies the run's criteria in full: a ball around each wanted
  /// sub-segment that no cell of the complex holds, kFinishRegionFactor times its length.
  CriteriaRegion missingRegion() const
  {
    CriteriaRegion region;
    if (!run_.conforming)
      return region;
    const SegmentSet& segs = run_.segments->segments();
    for (size_t i = 0; i < run_.segments->size(); ++i)
    {
      const int s = static_cast<int>(i);
      const Vec3 a = segs.points[segs.subs[s][0]], b = segs.points[segs.subs[s][1]];
      if (!run_.segments->inComplex(s) && run_.touchesMaterial(a, b))
        region.add(0.5 * (a + b), kFinishRegionFactor * norm(b - a));
    }
    region.index();
    return region;
  }

  void addSegmentStatistics(std::map<std::string, double>& st) const
  {
    const Counters count = run_.segments ? run_.segments->counters() : Counters{};
    const SegmentSet& segs = run_.segments ? run_.segments->segments() : run_.conformed;
    st["segment_trims_T1.1"] = static_cast<double>(segs.trims);
    st["segment_splits_T1.2"] = static_cast<double>(segs.splits);
    st["segment_splits_encroached"] = static_cast<double>(count.splitsEncroached);
    st["segment_splits_for_refused_points_T2.1_T3.1"] = static_cast<double>(count.splitsVetoed);
    st["refinement_points_refused_T2.1_T3.1"] = static_cast<double>(count.vetoes);
    st["refinement_points_dropped_at_short_segments"] = static_cast<double>(count.dropped);
    st["segment_splits_missing_from_mesh"] = static_cast<double>(count.missingSplits);
    st["segment_splits_mirrored_in_small_angle_clusters"] = static_cast<double>(segs.mirrored + count.mirrored);
    st["segment_splits_after_optimisation"] = static_cast<double>(repaired_);
    st["vertices_removed_from_segment_balls_after_perturbation"] = static_cast<double>(count.removedEncroachers);
    st["cell_points_dropped_in_facet_cycles"] = static_cast<double>(count.cyclesBroken);
    // the picking region (SliverAvoidingPoint): cells looked at, moved off their circumcentre, and
    // those where no candidate reached the sliver bound
    if (pickingRegionOf(run_.options).candidates > 0)
    {
      st["refinement_point_picks"] = static_cast<double>(picking_.cells);
      st["refinement_point_moved"] = static_cast<double>(picking_.moved);
      st["refinement_point_below_target"] = static_cast<double>(picking_.unreached);
    }
    st["segment_missing_edge_checks"] = static_cast<double>(count.missingChecks);
    // why refinement left sub-segments out of the complex (before optimisation)
    st["segment_pieces_missing_too_short"] = static_cast<double>(missing_.short_);
    st["segment_pieces_missing_refused"] = static_cast<double>(missing_.refused);
    st["segment_pieces_missing_outside"] = static_cast<double>(missing_.outside);
    st["segment_pieces_missing_unfinished"] = static_cast<double>(missing_.other);
  }

  MeshingContext& run_;
  const char* refinePhase_ = "refinement"; ///< the deadline's name for the current refinement round
  PickingRegion::Counters picking_;
  /// Conforming on several threads (refineConformingInParallel): vertices after, seconds of each phase.
  struct ParallelPhases
  {
    size_t segmentVertices = 0, parallelVertices = 0;
    std::vector<Vec3> leftBad; ///< refinement points the guard refused (ParallelGuardLevel)
    size_t repeatsRefused = 0; ///< of them, points that repeated a vertex
    double segmentSeconds = 0.0, parallelSeconds = 0.0, tailSeconds = 0.0;
    bool tailRan = false;
  } parallelPhases_;
  size_t refinedVertices_ = 0; ///< at the end of the first refinement (all rounds)
  std::vector<Tr::Vertex_handle> tailRegion_; ///< verticesAroundLeftWork, for the next refineOnce
  std::vector<Tr::Cell_handle> badCells_; ///< the cells the threads left bad, for the next refineOnce
  /// Vertices of a running parallel refinement, as last seen (0 otherwise).
  size_t parallelVertices_ = 0;
  Segments::MissingCensus missing_;
  double expected_ = 1000.0;
  size_t steps_ = 0, repaired_ = 0;
  int rounds_ = 0;
  bool budgetHit_ = false, stalled_ = false;
  /// The finishing round after the vertex budget (finishAfterBudget).
  struct Finish
  {
    bool active = false;    ///< rounds use its criteria and limit (from the finishing round on)
    bool overdrawn = false; ///< a round of it stopped at its limit
    bool completed = false; ///< it ended with its criteria met (no overdraft, no stall)
    size_t overdraft = 0, limit = 0, vertices = 0; ///< allowed, vertex count to stop at, added by the round
    size_t regionBalls = 0; ///< sub-segments missing from the complex when it started (missingRegion)
    std::unique_ptr<Criteria> criteria; ///< validityMeshCriteria
  } finish_;
  double refineTime_ = 0.0, refineCpu_ = 0.0, callingThreadRefineCpu_ = 0.0;
  double parallelCpu_ = 0.0, parallelBusiestCpu_ = 0.0; ///< of every refinement thread, of the busiest one
};
}
