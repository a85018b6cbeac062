// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL's parallel Mesh_3 refinement: Mesher_3's levels above a read-only guard level (repeated
// vertices; the constrained segments' balls for Conforming; see ParallelRefinement.h). The
// second Mesh_3 translation unit: it instantiates the meshers on the Parallel_tag triangulation only.

// The vertex budget with Parallel_tag needs the containers' approximate size (CGAL: about 3%
// slower). Only this translation unit instantiates the concurrent containers.
#define CGAL_CONCURRENT_COMPACT_CONTAINER_APPROXIMATE_SIZE 1

#include "ParallelRefinement.h"

#include "FeatureEdgesOfComplex.h"
#include "GuardedParallelMesher3.h"
#include "InputError.h"
#include "MaterialCriteria3.h"
#include "FreedMemory.h"
#include "PackedComplex.h"

#include <CGAL/Mesh_3/Dump_c3t3.h>

#include <tbb/scalable_allocator.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <future>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>
#include <vector>

#ifndef CGAL_LINKED_WITH_TBB
#error "the parallel refinement needs CGAL with TBB (CGAL::TBB_support)"
#endif

namespace omesh::cgal
{
namespace
{
using Parallel = MeshTriangulation3<CGAL::Parallel_tag>;
}
}

namespace CGAL
{
// As for the sequential complex (SequentialTypes.h): CGAL never writes dump files into a user's folder.
template <>
struct Dump_c3t3<omesh::cgal::Parallel::C3t3, true>
{
  void dump_c3t3(const omesh::cgal::Parallel::C3t3&, std::string) const {}
};
template <>
struct Dump_c3t3<omesh::cgal::Parallel::C3t3, false>
{
  void dump_c3t3(const omesh::cgal::Parallel::C3t3&, std::string) const {}
};
}

namespace omesh::cgal
{
namespace
{
using Clock = std::chrono::steady_clock;

/// A parallel refinement that adds no vertex for this long is stopped as stalled (the sequential
/// one counts steps; the parallel one has no step to count). Long enough for CGAL's scan of the
/// cells of a 2M-vertex mesh on a loaded machine.
constexpr auto kStallTime = std::chrono::minutes(5);

double cpuSeconds(clockid_t clock)
{
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// CPU seconds of the process but the calling thread.
double otherThreadsCpu()
{
  return cpuSeconds(CLOCK_PROCESS_CPUTIME_ID) - cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
}

/// CPU seconds of each thread in a TBB arena (entries and exits of a thread add up): the busiest
/// thread's bounds the arena's work on idle cores, whatever the machine's load.
class ArenaThreadCpu : public tbb::task_scheduler_observer
{
public:
  explicit ArenaThreadCpu(tbb::task_arena& arena)
    : tbb::task_scheduler_observer(arena)
  {
    observe(true);
  }
  ~ArenaThreadCpu() override { observe(false); }
  void on_scheduler_entry(bool) override
  {
    std::lock_guard<std::mutex> lock(mutex_);
    entered_[std::this_thread::get_id()] = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
  }
  void on_scheduler_exit(bool) override
  {
    const double now = cpuSeconds(CLOCK_THREAD_CPUTIME_ID);
    std::lock_guard<std::mutex> lock(mutex_);
    const auto entry = entered_.find(std::this_thread::get_id());
    if (entry != entered_.end())
      spent_[entry->first] += now - entry->second;
  }
  /// Call after the arena's work ended (observe(false) first: threads may still be leaving).
  double busiest()
  {
    observe(false);
    std::lock_guard<std::mutex> lock(mutex_);
    double most = 0.0;
    for (const auto& [id, seconds] : spent_)
      most = std::max(most, seconds);
    return most;
  }

private:
  std::mutex mutex_;
  std::map<std::thread::id, double> entered_, spent_;
};

/// copy_tds's vertex copier for copyComplex: a new vertex with the point (the container gives the
/// time stamp), then its Mesh_3 data, remembering where each went.
template <class SrcVertex, class DstVertex>
struct CopyVertex
{
  std::unordered_map<const SrcVertex*, DstVertex*>* copied;
  DstVertex operator()(const SrcVertex& s) const
  {
    DstVertex v;
    v.set_point(s.point());
    v.set_time_stamp(std::size_t(-1)); // the container gives a new one (the default is not set)
    return v;
  }
  void operator()(const SrcVertex& s, DstVertex& d) const
  {
    d.set_point(s.point());
    d.set_dimension(s.in_dimension());
    d.set_index(s.index());
    d.set_meshing_info(s.meshing_info());
    (*copied)[&s] = &d;
  }
};

/// copy_tds's cell copier for copyComplex: subdomain, surface patches and centres, visited facets.
template <class SrcCell, class DstCell>
struct CopyCell
{
  DstCell operator()(const SrcCell&) const
  {
    DstCell c;
    c.set_time_stamp(std::size_t(-1)); // as for the vertices
    return c;
  }
  void operator()(const SrcCell& s, DstCell& d) const
  {
    d.set_subdomain_index(s.subdomain_index());
    for (int i = 0; i < 4; ++i)
    {
      d.set_surface_patch_index(i, s.surface_patch_index(i));
      d.set_facet_surface_center(i, s.get_facet_surface_center(i));
      d.set_facet_surface_center_index(i, s.get_facet_surface_center_index(i));
      if (s.is_facet_visited(i))
        d.set_facet_visited(i);
      else
        d.reset_visited(i);
    }
  }
};

/// Copies a complex between the sequential and the parallel triangulation types (same traits, same
/// vertex and cell bases): the triangulation with the Mesh_3 data of its vertices (dimension, index,
/// ball size) and cells (subdomain, surface patches and centres, visited facets), then the complex:
/// facets and cells in it (from the cells' data), corners, feature edges and far points (the
/// vertices of dimension -1 other than the infinite one). Time stamps are the target's own.
template <class Src, class Dst>
void copyComplex(const Src& src, Dst& dst)
{
  using SrcTr = typename Src::Triangulation;
  using DstTr = typename Dst::Triangulation;
  using SrcVertex = typename SrcTr::Vertex;
  using DstVertex = typename DstTr::Vertex;
  using SrcCell = typename SrcTr::Cell;
  using DstCell = typename DstTr::Cell;
  std::unordered_map<const SrcVertex*, DstVertex*> copied;
  copied.reserve(src.triangulation().number_of_vertices() + 1);
  dst.clear();
  const SrcTr& from = src.triangulation();
  DstTr& to = dst.triangulation();
  to.tds().copy_tds(from.tds(), typename SrcTr::Vertex_handle(), CopyVertex<SrcVertex, DstVertex>{ &copied }, CopyCell<SrcCell, DstCell>{});
  auto handle = [&](typename SrcTr::Vertex_handle v) { return to.tds().vertices().iterator_to(*copied.at(&*v)); };
  to.set_infinite_vertex(handle(from.infinite_vertex()));
  dst.rescan_after_load_of_triangulation(); // facets and cells of the complex; corners get index 1
  for (auto v = src.vertices_in_complex_begin(); v != src.vertices_in_complex_end(); ++v)
  {
    const typename SrcTr::Vertex_handle corner = v;
    dst.remove_from_complex(handle(corner));
    dst.add_to_complex(handle(corner), src.corner_index(corner));
  }
  forEachFeatureEdge(src, [&](auto v, auto w, auto curve) { dst.add_to_complex(handle(v), handle(w), curve); });
  for (auto v = from.finite_vertices_begin(); v != from.finite_vertices_end(); ++v)
    if (v->in_dimension() == -1)
      dst.add_far_point(handle(v));
}
}

int requestedThreads(const MesherOptions& options)
{
  if (options.threads < 0)
    throw InputError("Threads = " + std::to_string(options.threads) +
      ": use 1 (sequential), N > 1 threads, or 0 for every core");
  if (options.threads > 0)
    return options.threads;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

ParallelRefinementRun refineInParallel(SequentialC3t3& c3t3, const MeshDomain& domain, const MesherOptions& options,
  double edgeSize, int threads, const std::function<void(std::size_t)>& progress, const SegmentSet* protectedSegments)
{
  const double cpuStart = otherThreadsCpu();
  ParallelRefinementRun run;
  std::optional<Parallel::C3t3> parallel(std::in_place);
  Parallel::C3t3& par = *parallel;
  copyComplex(c3t3, par);
  const Parallel::Criteria criteria =
    materialMeshCriteria<Parallel::Tr>(options, Parallel::Criteria::Edge_criteria(edgeSize > 0 ? edgeSize : 1.0),
      options.sliverAngle, &domain.oracle());
  std::atomic<bool> stop{ false };
  {
    const SegmentSet noSegments;
    ParallelGuardLevel guard(protectedSegments ? *protectedSegments : noSegments);
    GuardedParallelMesher3<Parallel::C3t3, Parallel::Criteria, MeshDomain> mesher(
      par, domain, criteria, guard, CGAL::FACET_VERTICES_ON_SURFACE, options.maximumNumberOfVertices, &stop);
    // TBB's tasks of this refinement run in an arena of `threads` slots, whatever the machine has.
    tbb::task_arena arena(threads);
    arena.initialize();
    ArenaThreadCpu threadCpu(arena);
    auto refinement = std::async(std::launch::async, [&] {
      arena.execute([&] { mesher.refine(); });
    });
    const auto vertices = [&] { return par.triangulation().tds().vertices().approximate_size(); };
    std::size_t last = 0;
    auto lastChange = Clock::now();
    while (refinement.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready)
    {
      const std::size_t n = vertices();
      try
      {
        progress(n);
      }
      catch (...)
      {
        stop = true;
        refinement.wait();
        throw;
      }
      // CGAL's parallel levels look at the vertex budget only while queueing a batch: checked here too
      if (options.maximumNumberOfVertices && n >= options.maximumNumberOfVertices && !stop)
      {
        run.budgetHit = true;
        stop = true;
      }
      if (n != last)
      {
        last = n;
        lastChange = Clock::now();
      }
      else if (!stop && Clock::now() - lastChange > kStallTime)
      {
        run.stalled = true;
        stop = true;
      }
    }
    refinement.get(); // rethrows what the refinement threw
    run.busiestThreadCpu = threadCpu.busiest();
    run.budgetHit = run.budgetHit || (options.maximumNumberOfVertices && vertices() >= options.maximumNumberOfVertices);
    run.leftBad = guard.dropped();
    run.repeatsRefused = guard.repeats();
  }
  if (par.triangulation().dimension() == 3)
  {
    // packed first and freed before the sequential complex is built: never both at once
    const PackedComplex<Parallel::C3t3, SequentialC3t3> packed(par);
    parallel.reset();
    // TBB's allocator keeps what the concurrent containers freed for its next use, which does
    // not come in the sequential phases that follow: it goes back to the system here
    scalable_allocation_command(TBBMALLOC_CLEAN_ALL_BUFFERS, nullptr);
    // and so do the threads' malloc arenas (the cells' circumcentres and surface centres)
    returnFreedMemory();
    packed.unpackInto(c3t3);
  }
  else
    copyComplex(par, c3t3);
  run.cpuSeconds = otherThreadsCpu() - cpuStart;
  return run;
}
}
