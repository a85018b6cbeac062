// SPDX-License-Identifier: GPL-3.0-or-later
// The mesher: the translation unit that instantiates CGAL Mesh_3 on the sequential triangulation (it
// takes about a minute to compile; ParallelRefinement.cxx has the parallel one). Relies on Mesh_3
// internals of CGAL 5.5 (Mesher_3 stepping, criteria classes, Mesh_3::internal::init_c3t3*); CMake
// warns on other CGAL versions.
#include "OracleMesher.h"

#include "HierarchicalOracle.h"
#include "InputError.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "ConformingMesher3.h"
#include "MaterialCriteria3.h"
#include "MeshTriangulation3.h"
#include "OracleMeshDomain.h"
#include "ParallelRefinement.h"
#include "SegmentConformation.h"

#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_3/Dump_c3t3.h>
#include <CGAL/assertions_behaviour.h>
#include <CGAL/Mesh_domain_with_polyline_features_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <CGAL/refine_mesh_3.h>
#include <optional>

#include <array>
#include <atomic>
#include <chrono>
#include <future>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <unordered_map>

namespace omesh
{
const char* toString(FeatureStrategy s)
{
  switch (s)
  {
    case FeatureStrategy::Conforming:
      return "Conforming";
    case FeatureStrategy::None:
      return "None";
    case FeatureStrategy::ProtectingBalls:
      return "ProtectingBalls";
  }
  return "?";
}

namespace
{
using namespace omesh::cgal;
using Types = MeshTriangulation3<CGAL::Sequential_tag>;
using Tr = Types::Tr;
using C3t3 = Types::C3t3;
using Criteria = Types::Criteria;
using Mesher = CGAL::Mesh_3::Mesher_3<C3t3, Criteria, MeshDomain>;
using Clock = std::chrono::steady_clock;
}
}

namespace CGAL
{
// Before some errors CGAL dumps the complex into the working directory (dump-bug.mesh,
// dump-bug.binary.cgal): never into a user's.
template <>
struct Dump_c3t3<omesh::C3t3, true>
{
  void dump_c3t3(const omesh::C3t3&, std::string) const {}
};
template <>
struct Dump_c3t3<omesh::C3t3, false>
{
  void dump_c3t3(const omesh::C3t3&, std::string) const {}
};
}

namespace omesh
{
namespace
{
/// CGAL reports a failed assertion by printing its text to stderr, then throwing. For the time of
/// one meshing call it only throws; meshOracle turns the exception into its own message.
class QuietCgalErrors
{
public:
  QuietCgalErrors()
    : error_(CGAL::set_error_handler(&quiet))
    , warning_(CGAL::set_warning_handler(&quiet))
  {
  }
  ~QuietCgalErrors()
  {
    CGAL::set_error_handler(error_);
    CGAL::set_warning_handler(warning_);
  }
  QuietCgalErrors(const QuietCgalErrors&) = delete;
  QuietCgalErrors& operator=(const QuietCgalErrors&) = delete;

private:
  static void quiet(const char*, const char*, const char*, int, const char*) {}
  CGAL::Failure_function error_, warning_;
};

double seconds(Clock::time_point since)
{
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// CPU seconds of the calling thread.
double threadCpu()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Maximal polylines through the segments, broken at points of degree != 2 and at bends sharper
/// than kPolylineCorner: CGAL protects a polyline as one smooth curve, and through a sharp bend
/// (the 38-degree bends of a chamfered stem's edges) its balls left 8 pieces out of every
/// generated bone/implant mesh; as a polyline's end the bend becomes a protected corner.
constexpr double kPolylineCorner = 20.0; // degrees of turn

std::vector<std::vector<K::Point_3>> toPolylines(const FeatureSegments& f)
{
  std::vector<std::vector<size_t>> inc(f.points.size());
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    inc[f.segments[s][0]].push_back(s);
    inc[f.segments[s][1]].push_back(s);
  }
  auto other = [&](size_t s, size_t p) { return f.segments[s][0] == static_cast<int>(p) ? f.segments[s][1] : f.segments[s][0]; };
  std::vector<char> breaks(f.points.size(), 0);
  const double cosCorner = std::cos(kPolylineCorner * M_PI / 180.0);
  for (size_t p = 0; p < f.points.size(); ++p)
  {
    if (inc[p].size() != 2)
    {
      breaks[p] = 1;
      continue;
    }
    const Vec3 in = f.points[p] - f.points[other(inc[p][0], p)], out = f.points[other(inc[p][1], p)] - f.points[p];
    breaks[p] = dot(in, out) < cosCorner * norm(in) * norm(out);
  }
  std::vector<char> used(f.segments.size(), 0);
  std::vector<std::vector<K::Point_3>> lines;
  auto walk = [&](int start, size_t first) {
    std::vector<K::Point_3> line{ toPoint(f.points[start]) };
    int at = start;
    size_t s = first;
    while (true)
    {
      used[s] = 1;
      at = other(s, static_cast<size_t>(at));
      line.push_back(toPoint(f.points[at]));
      if (breaks[at])
        break;
      const size_t next = inc[at][0] == s ? inc[at][1] : inc[at][0];
      if (used[next])
        break;
      s = next;
    }
    lines.push_back(std::move(line));
  };
  for (size_t p = 0; p < f.points.size(); ++p)
    if (breaks[p])
      for (size_t s : inc[p])
        if (!used[s])
          walk(static_cast<int>(p), s);
  for (size_t s = 0; s < f.segments.size(); ++s) // closed loops without a break
    if (!used[s])
      walk(f.segments[s][0], s);
  return lines;
}

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
/// pumped), stop at `budget` steps (0 = none) and ask `check` (which may throw MeshingAborted)
/// every 256 steps. Copied by CGAL: the counts live outside.
struct OptimiserVisitor
{
  std::function<void()> check;
  std::size_t* steps;
  std::size_t budget;
  PerturbationBound* bound = nullptr; ///< the perturber's
  void step()
  {
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

/// Smallest dihedral angle (degrees) of the cells of the complex.
double complexMinAngle(const C3t3& c3t3)
{
  double m = 180.0;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    m = std::min(m, minDihedralAngle(toVec(c->vertex(0)->point().point()), toVec(c->vertex(1)->point().point()),
      toVec(c->vertex(2)->point().point()), toVec(c->vertex(3)->point().point())));
  return m;
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
  PerturbationBound* bound = nullptr)
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
    run.cutShort = optimiser(OptimiserVisitor{ std::move(check), &run.steps, budget, bound }) == CGAL::TIME_LIMIT_REACHED;
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

/// As CGAL::perturb_mesh_3 with its defaults (bounds up to 12 degrees, CGAL's perturbations),
/// abortable, stopped after `budget` steps (0 = none) or `timeLimit` seconds (0 = none), giving up
/// at a bound after `failuresPerBound` vertices it could not move plus 1% of its attempts there
/// (0 = never).
OptimiserRun perturb(C3t3& c3t3, const MeshDomain& domain, double timeLimit, std::size_t budget,
  double failuresPerBound, std::function<void()> check)
{
  const auto criterion = CGAL::parameters::default_values_for_mesh_3::default_sliver_criterion(
    c3t3, CGAL::parameters::default_values_for_mesh_3::perturb_sliver_bound);
  using Criterion = std::remove_const_t<decltype(criterion)>;
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
  return runOptimiser(c3t3, perturber, budget, std::move(check), &bound);
}

/// As CGAL::exude_mesh_3, pumping the cells below `sliverBound` degrees (0 = every cell, CGAL's
/// default), abortable, stopped as perturb().
OptimiserRun exude(C3t3& c3t3, double timeLimit, std::size_t budget, double sliverBound, std::function<void()> check)
{
  using Criterion = CGAL::Mesh_3::Min_dihedral_angle_criterion<Tr>;
  Criterion criterion(sliverBound, c3t3.triangulation());
  CGAL::Mesh_3::Slivers_exuder<C3t3, Criterion, OptimiserVisitor> exuder(c3t3, criterion);
  exuder.set_time_limit(timeLimit);
  return runOptimiser(c3t3, exuder, budget, std::move(check));
}

/// Sub-segments of `segs` that are not edges of the triangulation, minus `missingBefore`; the
/// segment points are located anew (the exuder re-creates the vertices it pumps).
size_t brokenByExudation(const C3t3& c3t3, const SegmentSet& segs, size_t missingBefore)
{
  const Tr& tr = c3t3.triangulation();
  std::vector<Tr::Vertex_handle> vertex(segs.points.size());
  Tr::Cell_handle hint;
  for (size_t p = 0; p < segs.points.size(); ++p)
  {
    Tr::Locate_type lt;
    int i, j;
    hint = tr.locate(Tr::Point(toPoint(segs.points[p])), lt, i, j, hint);
    if (lt == Tr::VERTEX)
      vertex[p] = hint->vertex(i);
  }
  size_t missing = 0;
  for (const auto& sub : segs.subs)
  {
    Tr::Cell_handle c;
    int i, j;
    const auto a = vertex[sub[0]], b = vertex[sub[1]];
    missing += a == Tr::Vertex_handle() || b == Tr::Vertex_handle() || !tr.is_edge(a, b, c, i, j);
  }
  return missing > missingBefore ? missing - missingBefore : 0;
}

/// Converts the complex to the output mesh.
TetMesh toTetMesh(const C3t3& c3t3)
{
  TetMesh out;
  std::unordered_map<Tr::Vertex_handle, int> ids;
  auto id = [&](Tr::Vertex_handle v) {
    auto [it, inserted] = ids.emplace(v, static_cast<int>(out.points.size()));
    if (inserted)
    {
      out.points.push_back(toVec(v->point().point()));
      const int dim = c3t3.in_dimension(v);
      out.pointDimension.push_back(dim < 0 ? 3 : dim);
    }
    return it->second;
  };
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
  {
    std::array<int, 4> t{ id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3)) };
    out.tets.push_back(t);
    out.tetMaterial.push_back(materialOf(c3t3.subdomain_index(c)));
  }
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f)
  {
    const auto patch = c3t3.surface_patch_index(*f);
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k)
      tri[k] = id(f->first->vertex((f->second + 1 + k) & 3));
    out.interfaceTriangles.push_back(tri);
    out.interfaceMaterials.push_back({ materialOf(patch.first), materialOf(patch.second) });
  }
  return out;
}
}


namespace
{
/// The feature lines resampled as MesherOptions::resampleFeatureLines asks (chords up to the edge
/// size, else the facet size, else 1/40 of the diagonal, within half the smallest facet distance),
/// or nothing when it does not.
std::optional<FeatureSegments> resampledFeatures(const FeatureSegments& given, const MesherOptions& options,
  const BoundingBox& inner, std::vector<std::string>& warnings)
{
  if (!options.resampleFeatureLines || given.empty())
    return std::nullopt;
  const MeshCriteria::Values g = options.criteria.globalValues();
  double distance = g.facetDistance;
  for (const auto& [m, unused] : options.criteria.perMaterial)
    if (const double d = options.criteria.of(m).facetDistance; d > 0 && (distance <= 0 || d < distance))
      distance = d;
  const double length = g.edgeSize > 0 ? g.edgeSize : g.facetSize > 0 ? g.facetSize : norm(inner.size()) / 40.0;
  FeatureSegments resampled = given;
  if (resampleFeatureLines(resampled, length, distance > 0 ? 0.5 * distance : 0.05 * length) > 0)
    warnings.push_back("feature lines resampled: " + std::to_string(given.segments.size()) + " segments became " +
      std::to_string(resampled.segments.size()) + " (chords up to " + std::to_string(length) + ")");
  return resampled;
}

TetMesh meshOracleUnguarded(const HierarchicalOracle& oracle, const FeatureSegments& givenFeatures,
  const std::vector<Vec3>& seedPoints, const MesherOptions& options)
{
  const auto started = Clock::now();
  std::vector<std::string> warnings;
  const BoundingBox inner = oracle.bounds(); // throws for an empty or unbounded oracle
  const std::optional<FeatureSegments> resampled = resampledFeatures(givenFeatures, options, inner, warnings);
  const FeatureSegments& features = resampled ? *resampled : givenFeatures;
  checkCriteria(options.criteria, warnings);
  const MeshCriteria::Values g = options.criteria.globalValues();
  if (!features.empty())
  {
    auto w = features.validate(oracle, g.cellRadiusEdgeRatio);
    warnings.insert(warnings.end(), w.begin(), w.end());
  }
  auto report = [&](double fraction, const char* phase) {
    if (options.progress && !options.progress(fraction, phase))
      throw MeshingAborted();
  };
  report(0.0, "initialisation");

  // A little room around the materials, so the boundary never touches the domain's box.
  BoundingBox box = inner;
  const Vec3 pad = 0.02 * box.size() + (1e-9 * (1.0 + norm(box.size()))) * Vec3{ 1, 1, 1 };
  box.add(box.min - pad);
  box.add(box.max + pad);
  MeshDomain domain(oracle, box, options.seed);
  const bool protect = options.strategy == FeatureStrategy::ProtectingBalls && !features.empty();
  if (protect)
  {
    auto lines = toPolylines(features);
    domain.add_features(lines.begin(), lines.end());
  }

  // Criteria: ours per material; CGAL's topology criterion (facet vertices on the surface, T2).
  double edgeSize = g.edgeSize;
  if (protect && edgeSize <= 0)
  {
    edgeSize = norm(inner.size()) / 50.0;
    for (double v : { g.facetSize, g.cellSize })
      if (v > 0)
        edgeSize = std::min(edgeSize, v);
    warnings.push_back("EdgeSize not set: protecting balls use " + std::to_string(edgeSize));
  }
  Criteria criteria = materialMeshCriteria<Tr>(options, edgeSize);

  // Conforming: rule T1 on the segments alone first; the domain's initial points keep away from
  // their points (a near-coincident pair seeds a cluster of micro tetrahedra).
  const bool conforming = options.strategy == FeatureStrategy::Conforming && !features.empty();
  // CGAL's parallel refinement (ParallelRefinement.h) serves every strategy but Conforming with
  // feature lines, whose segment level is ours and sequential.
  const int threads = conforming ? 1 : requestedThreads(options);
  if (conforming && requestedThreads(options) > 1)
    warnings.push_back("Threads = " + std::to_string(options.threads) + ": the Conforming strategy with feature "
      "lines refines on one thread (None and ProtectingBalls refine in parallel)");
  SegmentSet segs;
  if (conforming)
  {
    const size_t budget = options.maximumNumberOfVertices ? options.maximumNumberOfVertices : 1000000;
    segs = conformSegments(features, g.edgeSize, budget, warnings);
    domain.avoidInitialPointsNear(segs.points);
  }

  CGAL::get_default_random() = CGAL::Random(options.seed);
  C3t3 c3t3;
  const auto initStart = Clock::now();
  // First, far points around the domain keep the triangulation's hull away from the material boundary:
  // a circumcentre on a convex domain's boundary would otherwise land on the hull (CGAL adds such
  // points itself only in parallel mode, and not after feature protection).
  {
    const Vec3 c = 0.5 * (box.min + box.max);
    const double r = 2.0 * norm(box.size());
    for (int i = 0; i < 8; ++i)
    {
      const Vec3 dir{ (i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0 };
      c3t3.add_far_point(Tr::Point(toPoint(c + (r / std::sqrt(3.0)) * dir)));
    }
  }
  if (protect)
  {
    // The vertex budget also bounds the protection of the features (CGAL's ball refinement can
    // run long on small angles). It reports no progress of its own: it runs in a worker thread
    // while this one keeps asking the progress callback, and stops through CGAL's stop flag.
    std::atomic<bool> stop{ false };
    CGAL::parameters::internal::Mesh_3_options meshOptions;
    meshOptions.maximal_number_of_vertices = options.maximumNumberOfVertices;
    meshOptions.pointer_to_stop_atomic_boolean = &stop;
    auto protection = std::async(std::launch::async, [&] {
      // CGAL's default random generator is per thread and seeded from the clock: seed this one
      CGAL::get_default_random() = CGAL::Random(options.seed);
      CGAL::Mesh_3::internal::C3t3_initializer<C3t3, MeshDomain, Criteria, true, MeshDomain::Has_features>()(
        c3t3, domain, criteria, true, meshOptions);
    });
    while (protection.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready)
    {
      try
      {
        report(0.02, "feature protection");
      }
      catch (...)
      {
        stop = true;
        protection.wait();
        throw;
      }
    }
    protection.get(); // rethrows what the worker threw
  }
  else
    CGAL::Mesh_3::internal::init_c3t3(c3t3, domain, criteria, 20);
  for (const Vec3& p : seedPoints)
  {
    const int m = oracle.material(p);
    if (m == kOutside)
    {
      warnings.push_back("seed point outside every material ignored");
      continue;
    }
    Tr::Vertex_handle v = c3t3.triangulation().insert(Tr::Point(toPoint(p)));
    if (v != Tr::Vertex_handle())
    {
      c3t3.set_dimension(v, 3);
      c3t3.set_index(v, domain.index_from_subdomain_index(subdomainOf(m)));
    }
  }
  const double initTime = seconds(initStart);

  // Conforming: the segments, conformed by rule T1, enter the triangulation first; their points
  // are mesh vertices of dimension 0 (input points) or 1 (on a segment), which CGAL's perturber
  // never moves. Refinement then keeps every sub-segment's diametral ball empty (T1.2) and refuses
  // refinement points inside them (T2.1, T3.1): see SegmentRefinementLevel.
  using Segments = SegmentRefinementLevel<C3t3>;
  std::vector<Tr::Vertex_handle> segVertex;
  typename Segments::Counters segCount;
  double minSubSegment = 0.0;
  if (conforming)
  {
    segVertex.resize(segs.points.size());
    for (size_t p = 0; p < segs.points.size(); ++p)
    {
      Tr::Vertex_handle v = c3t3.triangulation().insert(Tr::Point(toPoint(segs.points[p])));
      c3t3.set_dimension(v, segs.corner[p] ? 0 : 1);
      c3t3.set_index(v, segs.corner[p] ? domain.index_from_corner_index(static_cast<int>(p) + 1)
                                       : domain.index_from_curve_index(1));
      segVertex[p] = v;
    }
    c3t3.rescan_after_load_of_triangulation();
    // Sub-segments are never split below 1/64 of the shortest conformed one: a surface or a
    // segment meeting a segment at a tiny angle would otherwise split it without end.
    minSubSegment = std::numeric_limits<double>::infinity();
    for (size_t s = 0; s < segs.subs.size(); ++s)
      minSubSegment = std::min(minSubSegment, segs.length(s) / 64.0);
  }

  // Refinement, one step at a time: progress, abort and the vertex budget in our hands.
  const auto refineStart = Clock::now();
  const double refineCpuStart = threadCpu();
  double parallelCpu = 0.0, parallelBusiestCpu = 0.0; // of every thread, of the busiest one
  size_t steps = 0;
  int rounds = 0;
  bool budgetHit = false;
  // Expected number of vertices, for the progress bar only: about one per cell-size cube of each
  // material (measured on the demo scene), from a coarse sampling of the oracle.
  const double expected = [&] {
    std::map<int, double> volume;
    const int n = 24;
    const Vec3 step = (1.0 / n) * inner.size();
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
        {
          const int m = oracle.material(inner.min + Vec3{ (i + 0.5) * step.x, (j + 0.5) * step.y, (k + 0.5) * step.z });
          if (m != kOutside)
            volume[m] += step.x * step.y * step.z;
        }
    double sum = 0.0;
    for (const auto& [m, v] : volume)
    {
      const MeshCriteria::Values c = options.criteria.of(m);
      const double size = c.cellSize > 0 ? c.cellSize : norm(inner.size()) / 20.0;
      sum += v / (size * size * size);
    }
    return std::max(1000.0, sum);
  }();

  bool stalled = false;
  // `more` (after the mesher is done) may queue more work: then refinement goes on.
  auto drive = [&](auto& mesher, const std::function<bool()>& more) {
    mesher.initialize();
    size_t lastCount = 0, idleChecks = 0;
    while (!mesher.is_algorithm_done() || (more && more()))
    {
      mesher.one_step();
      if (++steps % 512 == 0)
      {
        const size_t count = c3t3.triangulation().number_of_vertices();
        // A refinement point that repeats an existing vertex inserts nothing and is tried again
        // forever (seen with protecting balls): stop after ~100k idle steps instead of hanging.
        idleChecks = count == lastCount ? idleChecks + 1 : 0;
        lastCount = count;
        if (idleChecks >= 200)
        {
          stalled = true;
          mesher.fix_c3t3();
          break;
        }
        const double n = static_cast<double>(count);
        report(0.05 + 0.4 * std::min(1.0, n / expected), "refinement");
        if (options.maximumNumberOfVertices && n >= options.maximumNumberOfVertices)
        {
          budgetHit = true;
          break;
        }
      }
    }
    if (budgetHit)
      mesher.fix_c3t3();
  };
  // A sub-segment missing from the mesh is worth splitting only where a material touches it (not
  // on a feature line outside every domain): probes around its midpoint.
  auto touchesMaterial = [&oracle](const Vec3& a, const Vec3& b) {
    const Vec3 m = 0.5 * (a + b);
    const double h = 1e-3 * norm(b - a);
    for (int axis = 0; axis < 3; ++axis)
      for (double sign : { -1.0, 1.0 })
      {
        Vec3 p = m;
        p[axis] += sign * h;
        if (oracle.material(p) != kOutside)
          return true;
      }
    return false;
  };
  auto refine = [&]() {
    if (conforming)
    {
      Segments level(c3t3, segs, segVertex, domain.index_from_curve_index(1), minSubSegment, segCount);
      ConformingMesher3<C3t3, Criteria, MeshDomain> mesher(c3t3, domain, criteria, level, CGAL::FACET_VERTICES_ON_SURFACE);
      drive(mesher, [&] { return level.queueMissingFromComplex(touchesMaterial) > 0; });
    }
    else if (threads > 1)
    {
      const ParallelRefinementRun run = refineInParallel(c3t3, domain, options, edgeSize, threads,
        [&](size_t n) { report(0.05 + 0.4 * std::min(1.0, static_cast<double>(n) / expected), "refinement"); });
      budgetHit = run.budgetHit;
      stalled = run.stalled;
      parallelCpu += run.cpuSeconds;
      parallelBusiestCpu += run.busiestThreadCpu;
      if (budgetHit || stalled) // the cells a stop left out of the complex, as drive() does
        Mesher(c3t3, domain, criteria, CGAL::FACET_VERTICES_ON_SURFACE).fix_c3t3();
    }
    else
    {
      Mesher mesher(c3t3, domain, criteria, CGAL::FACET_VERTICES_ON_SURFACE);
      drive(mesher, {});
    }
    ++rounds;
  };
  // Sub-segments that are no longer Delaunay edges of the mesh.
  auto missingSubSegments = [&]() {
    size_t missing = 0;
    for (const auto& sub : segs.subs)
    {
      Tr::Cell_handle c;
      int i, j;
      missing += !c3t3.triangulation().is_edge(segVertex[sub[0]], segVertex[sub[1]], c, i, j);
    }
    return missing;
  };
  refine();
  if (stalled)
    warnings.push_back("refinement stalled (100k steps without a new vertex: a refinement point "
                       "repeats an existing vertex); the criteria are not met everywhere");
  if (budgetHit)
  {
    warnings.push_back("refinement stopped at MaximumNumberOfVertices = " +
      std::to_string(options.maximumNumberOfVertices) + ": the criteria are not met everywhere");
  }
  c3t3.clear_manifold_info();
  const double refineTime = seconds(refineStart);
  const double callingThreadRefineCpu = threadCpu() - refineCpuStart;
  const double refineCpu = callingThreadRefineCpu + parallelCpu;

  const auto optStart = Clock::now();
  const double optCpuStart = threadCpu();
  const double minBefore = options.perturb || options.exude ? complexMinAngle(c3t3) : 0.0;
  // Bounded by step budgets that scale with the mesh (deterministic: the same seed gives the same
  // mesh on any machine); a time limit is optional (< 0: stock CGAL's, the refinement's time).
  const double optLimit = options.optimisationTimeLimit < 0 ? refineTime : options.optimisationTimeLimit;
  size_t repaired = 0;
  OptimiserRun perturbed, exuded;
  auto budget = [](double perUnit, size_t units) {
    return perUnit > 0 ? static_cast<size_t>(std::ceil(perUnit * static_cast<double>(units))) + 1000 : 0;
  };
  // progress within a phase: the share of its budget, or a creep toward its end without one
  auto phaseProgress = [](size_t steps, size_t max) {
    return max ? static_cast<double>(steps) / static_cast<double>(max) : 1.0 - 1.0 / (1.0 + 1e-3 * steps / 256.0);
  };
  if (options.perturb)
  {
    report(0.45, "perturbation");
    const size_t max = budget(options.perturbationStepsPerVertex, c3t3.triangulation().number_of_vertices());
    size_t checks = 0;
    perturbed = perturb(c3t3, domain, optLimit, max, options.perturbationFailuresPerBound,
      [&] { report(0.45 + 0.35 * phaseProgress(256 * ++checks, max), "perturbation"); });
    // The perturber never moves segment vertices, but a moved neighbour can land in a diametral
    // ball and so break a sub-segment: refine again (the segment level splits what was
    // encroached; weights are still zero here, after the exuder they are not).
    const bool encroached = conforming && !budgetHit && !stalled && [&] {
      Segments level(c3t3, segs, segVertex, domain.index_from_curve_index(1), minSubSegment, segCount);
      if (level.removeEncroachersOfShortSubSegments() > 0)
      {
        c3t3.rescan_after_load_of_triangulation(); // the removals deleted cells of the complex
        return true;
      }
      return level.countEncroached() > 0 || level.countMissingFromComplex(touchesMaterial) > 0;
    }();
    if (encroached)
    {
      const size_t before = segCount.splitsEncroached + segCount.splitsVetoed;
      refine();
      repaired = segCount.splitsEncroached + segCount.splitsVetoed - before;
      c3t3.clear_manifold_info();
    }
  }
  if (options.exude)
  {
    report(0.8, "exudation");
    // The exuder changes weights, which can flip a sub-segment out of the (regular) triangulation.
    // It is undone when it would break a segment the refinement kept.
    std::unique_ptr<C3t3> kept;
    const size_t missingBefore = conforming ? missingSubSegments() : 0;
    if (conforming)
      kept = std::make_unique<C3t3>(c3t3);
    // The budget also ends CGAL's exuder where it cycles (seen next to protecting balls); it stops
    // between two cells, where the mesh is consistent. Without a budget, 10 pumps per cell still
    // end a cycle.
    const size_t max = budget(options.exudationStepsPerCell > 0 ? options.exudationStepsPerCell : 10.0,
      c3t3.number_of_cells_in_complex());
    size_t checks = 0;
    exuded = exude(c3t3, optLimit, max, options.exudationSliverBound, [&] { report(0.8 + 0.18 * phaseProgress(256 * ++checks, max), "exudation"); });
    if (conforming)
    {
      segVertex.clear(); // the exuder re-creates vertices: find the segment points again
      if (const size_t broken = brokenByExudation(c3t3, segs, missingBefore))
      {
        c3t3.swap(*kept);
        warnings.push_back("exudation undone: it would have removed " + std::to_string(broken) +
          " constrained sub-segments from the mesh");
      }
    }
  }
  const double optTime = seconds(optStart);
  const double optCpu = threadCpu() - optCpuStart;


  TetMesh mesh = toTetMesh(c3t3);
  mesh.segments = locateFeatureSegments(mesh, features);
  const double coverage = featureCoverage(mesh.segments, features);
  if (!features.empty() && coverage < 0.9999)
  {
    std::ostringstream o;
    o << "feature lines: " << 100.0 * coverage << "% of their length is present as mesh edges";
    warnings.push_back(o.str());
  }
  double minAngle = 180.0, sumAngle = 0.0;
  for (const auto& t : mesh.tets)
  {
    const double a = minDihedralAngle(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
    minAngle = std::min(minAngle, a);
    sumAngle += a;
  }
  // Independent of how the mesh was made: what a finite-element code would reject.
  std::vector<unsigned char> defects;
  // Missing feature-line pieces are defects only where the strategy promises them (not None).
  ValidityThresholds thresholds;
  thresholds.segmentsRequired = options.strategy != FeatureStrategy::None;
  const MeshValidity validity =
    checkMeshValidity(mesh, [&oracle](const Vec3& p) { return oracle.material(p); }, thresholds, &defects);
  mesh.tetDefects = std::move(defects);
  if (!validity.valid())
    warnings.push_back("mesh validity: " + validity.describe());
  auto& st = mesh.statistics;
  for (const auto& [name, value] : validity.asStatistics())
    st[name] = value;
  st["tetrahedra"] = static_cast<double>(mesh.tets.size());
  st["vertices"] = static_cast<double>(mesh.points.size());
  st["min_dihedral_angle"] = mesh.tets.empty() ? 0.0 : minAngle;
  st["mean_min_dihedral_angle"] = mesh.tets.empty() ? 0.0 : sumAngle / mesh.tets.size();
  st["feature_coverage"] = coverage;
  if (resampled)
    st["feature_segments_before_resampling"] = static_cast<double>(givenFeatures.segments.size());
  st["refinement_steps"] = static_cast<double>(steps);
  st["refinement_threads"] = threads;
  st["refinement_rounds"] = rounds;
  st["segment_trims_T1.1"] = static_cast<double>(segs.trims);
  st["segment_splits_T1.2"] = static_cast<double>(segs.splits);
  st["segment_splits_encroached"] = static_cast<double>(segCount.splitsEncroached);
  st["segment_splits_for_refused_points_T2.1_T3.1"] = static_cast<double>(segCount.splitsVetoed);
  st["refinement_points_refused_T2.1_T3.1"] = static_cast<double>(segCount.vetoes);
  st["refinement_points_dropped_at_short_segments"] = static_cast<double>(segCount.dropped);
  st["segment_splits_missing_from_mesh"] = static_cast<double>(segCount.missingSplits);
  st["segment_splits_mirrored_in_small_angle_clusters"] = static_cast<double>(segs.mirrored + segCount.mirrored);
  st["segment_splits_after_optimisation"] = static_cast<double>(repaired);
  st["vertices_removed_from_segment_balls_after_perturbation"] = static_cast<double>(segCount.removedEncroachers);
  if (options.perturb || options.exude)
    st["optimisation.min_dihedral_before"] = minBefore;
  st["optimisation.perturbation_steps"] = static_cast<double>(perturbed.steps);
  st["optimisation.perturbation_cut_short"] = perturbed.cutShort;
  st["optimisation.perturbation_gave_up"] = perturbed.gaveUp;
  st["optimisation.perturbation_last_bound"] = perturbed.lastBound;
  st["optimisation.exudation_steps"] = static_cast<double>(exuded.steps);
  st["optimisation.exudation_cut_short"] = exuded.cutShort;
  st["time.perturbation"] = perturbed.seconds;
  st["time.exudation"] = exuded.seconds;
  st["time.initialisation"] = initTime;
  st["time.refinement"] = refineTime;
  st["time.optimisation"] = optTime;
  st["time.total"] = seconds(started);
  // CPU seconds of the calling thread, and of the refinement's threads for a parallel refinement
  // (the wall times above depend on the machine's load)
  st["cpu.refinement"] = refineCpu;
  // the refinement's CPU seconds along its critical path (the calling thread's plus the busiest
  // refinement thread's): its time on idle cores, the same as cpu.refinement when sequential
  st["cpu.refinement_critical_path"] = callingThreadRefineCpu + parallelBusiestCpu;
  st["cpu.perturbation"] = perturbed.cpuSeconds;
  st["cpu.exudation"] = exuded.cpuSeconds;
  st["cpu.optimisation"] = optCpu;
  for (const auto& [m, v] : materialVolumes(mesh))
    st["volume.material_" + std::to_string(m)] = v;
  for (int m : mesh.tetMaterial)
    st["tetrahedra.material_" + std::to_string(m)] += 1.0;
  mesh.warnings = std::move(warnings);
  report(1.0, "done");
  return mesh;
}
}

TetMesh meshOracle(const HierarchicalOracle& oracle, const FeatureSegments& features,
  const std::vector<Vec3>& seedPoints, const MesherOptions& options)
{
  QuietCgalErrors quiet;
  try
  {
    return meshOracleUnguarded(oracle, features, seedPoints, options);
  }
  catch (const CGAL::Failure_exception& e)
  {
    std::string where = e.filename();
    where = where.substr(where.find_last_of('/') + 1) + ":" + std::to_string(e.line_number());
    std::string why;
    if (e.message().find("already inserted") != std::string::npos)
      why = ": a refinement point repeats an existing vertex";
    throw MeshingFailed("meshing failed inside CGAL Mesh_3 (" + where + ")" + why +
      "; please report it with the scene (the seed reproduces it)");
  }
}
}
