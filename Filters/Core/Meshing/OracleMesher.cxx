// SPDX-License-Identifier: GPL-3.0-or-later
// The mesher: the translation unit that instantiates CGAL Mesh_3 on the sequential triangulation (it
// takes about a minute to compile; ParallelRefinement.cxx has the parallel one). Relies on Mesh_3
// internals of CGAL 5.5 (Mesher_3 stepping, criteria classes, Mesh_3::internal::init_c3t3*); CMake
// warns on other CGAL versions.
#include "OracleMesher.h"

#include "FieldDataKeys.h"
#include "HierarchicalOracle.h"
#include "FeatureEdgeSizes.h"
#include "FeatureNetworkSimplification.h"
#include "InputError.h"
#include "DihedralImprovement.h"
#include "MeshQuality.h"
#include "MeshSizeEstimate.h"
#include "MeshValidity.h"
#include "ComplexSnapshot.h"
#include "ConformingMesher3.h"
#include "MaterialCriteria3.h"
#include "MeshTriangulation3.h"
#include "OracleMeshDomain.h"
#include "ParallelRefinement.h"
#include "SegmentConformation.h"
#include "SegmentState.h"
#include "CentroidLabel.h"
#include "ComplexToTetMesh.h"
#include "FeatureProtection.h"
#include "Optimisers.h"
#include "SequentialTypes.h"

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

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <future>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <unordered_map>

namespace omesh
{
double effectivePickingSliverAngle(const MesherOptions& options)
{
  if (options.pickingSliverAngle >= 0)
    return options.pickingSliverAngle;
  // the tightest radius-edge bound of any material (0 = none: counted as the paper's)
  auto bound = [](const MeshCriteria::Values& v) {
    return v.cellRadiusEdgeRatio > 0 ? v.cellRadiusEdgeRatio : kPickingSliverRadiusEdge;
  };
  double tightest = bound(options.criteria.globalValues());
  for (const auto& entry : options.criteria.perMaterial)
    tightest = std::min(tightest, bound(options.criteria.of(entry.first)));
  if (tightest >= kPickingSliverRadiusEdgeLoose)
    return kPickingSliverAngleLoose;
  return tightest >= kPickingSliverRadiusEdge ? kPickingSliverAngle : 0.0;
}

double effectiveTimeLimit(const MesherOptions& options)
{
  if (options.timeLimit != 0)
    return options.timeLimit > 0 ? options.timeLimit : 0.0;
  return kDefaultTimeLimit;
}

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
using namespace omesh::cgal::sequential;
using Mesher = CGAL::Mesh_3::Mesher_3<C3t3, Criteria, MeshDomain>;
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

/// The vertices of the cells of the complex that `criteria`'s cell criteria call bad (above a
/// size or radius-edge bound, below the sliver angle), each once.
std::vector<Tr::Vertex_handle> verticesOfBadCells(const C3t3& c3t3, const Criteria& criteria)
{
  const auto& cells = criteria.cell_criteria_object();
  std::set<Tr::Vertex_handle> found;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    if (cells(c3t3.triangulation(), c))
      for (int k = 0; k < 4; ++k)
        found.insert(c->vertex(k));
  return { found.begin(), found.end() };
}

/// CGAL's parallel levels refine cells in batches, not worst first; below this radius-edge bound
/// that order cascades (generated bone/implant cases at 1.1: 3-9x the sequential run's vertices,
/// one into the 300k-vertex budget; at 1.2 and 1.3 within 1.3x). The parallel levels refine to
/// this bound at most, the sequential round after them to the material's own.
constexpr double kParallelRadiusEdgeFloor = 1.2;

/// The finishing round after the vertex budget (MeshingRun::finishAfterBudget) may add this share
/// of the budget, at least kFinishOverdraftMin vertices (see the README's "Time limit").
constexpr double kFinishOverdraftShare = 0.1;
constexpr size_t kFinishOverdraftMin = 500;
/// The finishing round refines cells below this angle at least (the default SliverAngle: what
/// removes flat tetrahedra; the picking angle cost 49 % of a 3,000-vertex budget on the demo).
constexpr double kFinishSliverAngle = 1.0;
/// Around a sub-segment missing from the complex, the run's criteria apply within this many times
/// its length (MeshingRun::missingRegion).
constexpr double kFinishRegionFactor = 3.0;

/// `options` with every radius-edge bound below `floor` raised to it (bounds <= 0, none, kept).
MesherOptions withRadiusEdgeAtLeast(MesherOptions options, double floor)
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

}

namespace
{
/// The chord length of the resampling: the edge size, else the facet size, else 1/40 of the diagonal.
double resamplingLength(const MesherOptions& options, const BoundingBox& inner)
{
  const MeshCriteria::Values g = options.criteria.globalValues();
  return g.edgeSize > 0 ? g.edgeSize : g.facetSize > 0 ? g.facetSize : norm(inner.size()) / 40.0;
}

/// Feature lines given as many segments far shorter than the mesh size (a noisy surface's sharp
/// edges at a small feature angle) and not resampled: every point stays a mesh vertex and the mesh
/// grades down to them, which costs orders of magnitude more than resampled lines (figures in
/// docs/journal/2026-12-02-slips.md). A warning naming the numbers and the fix.
std::optional<std::string> denseFeatureLinesWarning(
  const FeatureSegments& given, const MesherOptions& options, const BoundingBox& inner)
{
  constexpr size_t kManySegments = 1000;
  constexpr double kShorter = 10.0;
  if (options.resampleFeatureLines || given.segments.size() < kManySegments)
    return std::nullopt;
  std::vector<double> lengths(given.segments.size());
  for (size_t s = 0; s < lengths.size(); ++s)
    lengths[s] = given.length(s);
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double median = lengths[lengths.size() / 2], h = resamplingLength(options, inner);
  if (!(median * kShorter < h))
    return std::nullopt;
  std::ostringstream o;
  o.precision(3);
  o << "feature lines: " << given.segments.size() << " segments of median length " << median << ", " << h / median
    << " times shorter than the mesh size " << h
    << ": each of their points stays a mesh vertex and the mesh grades down to them (slow, and small "
       "elements); resample them to chords of about that size (ResampleFeatureLines), or raise the feature angle "
       "that found them";
  return o.str();
}

/// The feature lines simplified and resampled as MesherOptions::resampleFeatureLines asks
/// (simplifyFeatureNetwork: chords up to the edge size, else the facet size, else 1/40 of the
/// diagonal, within half the smallest facet distance), or nothing when it does not.
std::optional<FeatureSegments> resampledFeatures(const FeatureSegments& given, const MesherOptions& options,
  const HierarchicalOracle& oracle, const BoundingBox& inner, std::vector<std::string>& warnings,
  FeatureNetworkReport& report)
{
  if (!options.resampleFeatureLines || given.empty())
    return std::nullopt;
  const double distance = options.criteria.finestFacetDistance();
  FeatureNetworkTolerances tolerances;
  tolerances.edgeLength = resamplingLength(options, inner);
  // a line with a finer edge size of its own (or of its materials) keeps its detail: h is the finest
  if (!given.edgeSizes.empty() || hasMaterialEdgeSizes(options.criteria))
    for (double e : resolveFeatureEdgeSizes(given, options.criteria, oracle))
      if (e > 0)
        tolerances.edgeLength = std::min(tolerances.edgeLength, e);
  tolerances.chordTolerance = distance > 0 ? 0.5 * distance : 0.05 * tolerances.edgeLength;
  // merges, snaps and shared trunks keep the lines as near the given ones as the chords do: CAD
  // edges (a small polygonal circle, a corner) keep their shape (Benchmarks/cad_defects item 6)
  tolerances.maxDeviation = tolerances.chordTolerance;
  tolerances.inDomain = [&oracle](const Vec3& p) { return oracle.material(p) != kOutside; };
  FeatureSegments resampled = given;
  // each chord keeps the own edge size of the given segment it came from (its source)
  report = simplifyFeatureNetwork(resampled, tolerances);
  if (resampled.segments.size() != given.segments.size() || resampled.points.size() != given.points.size())
  {
    // How far the lines kept lie from the given ones; apart from that, how far the given ones lie
    // from those kept, which also counts pieces dropped on purpose (outside the domain, spurs): not
    // movement.
    std::ostringstream o;
    o << "feature lines simplified: " << given.segments.size() << " segments became " << resampled.segments.size()
      << " (chords up to " << tolerances.edgeLength << "; points closer than " << tolerances.mergeDistance()
      << " merged, spurs shorter than " << tolerances.spurLength() << " dropped; the lines kept lie within "
      << report.simplifiedToGiven << " of the given ones";
    if (report.givenToSimplified > report.simplifiedToGiven)
      o << ", the given ones within " << report.givenToSimplified << " of those kept (" << report.segmentsOutside
        << " segment(s) outside the domain, " << report.spursDropped << " spur(s), " << report.piecesDropped
        << " short piece(s) dropped, " << report.unmeshableEnds << " unmeshable end(s) bypassed or dropped, "
        << report.pointsSnapped << " snap(s) and shared trunk(s))";
    o << ")";
    warnings.push_back(o.str());
  }
  return resampled;
}

/// Thrown by a run whose parallel refinement reached the vertex budget: CGAL's parallel levels
/// refine depth-first (each task refines the bad elements its insertion made, at once), so a
/// parallel run stopped early holds its vertices in deep clusters where the sequential run, worst
/// element first, spreads them: with criteria far beyond the budget (facet size 1e-5 in a 10 mm
/// box) the clusters were thousands of flat tets. meshOracle then meshes again on one thread.
struct ParallelBudgetReached
{
  double seconds = 0.0; ///< of the run until then
  std::size_t vertices = 0;
};

/// One call of meshOracle, as the paper's chain of phases: the inputs, rule T1 on the segments
/// alone, the initial points, refinement (the segment, facet and cell levels together, rules
/// T1.2, T2, T3), optimisation, then the output mesh with its validity check and statistics.
class MeshingRun
{
public:
  using Segments = SegmentRefinementLevel<C3t3>;
  using Counters = SegmentState<C3t3>::Counters;

  MeshingRun(const HierarchicalOracle& oracle, const FeatureSegments& givenFeatures, const MesherOptions& options)
    : oracle_(oracle)
    , given_(givenFeatures)
    , options_(options)
    , deadline_(effectiveTimeLimit(options))
  {
    deadline_.setMeasure([this](std::map<std::string, double>& st) { measure(st); });
  }

  TetMesh run(const std::vector<Vec3>& seedPoints)
  {
    prepareInputs();
    buildDomainAndCriteria();
    conformSegmentsT1();
    initialPoints(seedPoints);
    refineAllLevels();
    optimise();
    return validatedMesh();
  }

private:
  /// Progress for the caller; throws MeshingAborted when it asks to stop.
  void report(double fraction, const char* phase) const
  {
    if (options_.progress && !options_.progress(fraction, phase))
      throw MeshingAborted();
  }

  /// How far the run got, for the message and statistics of TimeLimitReached.
  void measure(std::map<std::string, double>& st) const
  {
    // during a parallel refinement the sequential complex holds its start: its vertex count is the last seen
    // (after validatedMesh cleared the complex, the output's counts)
    st["vertices"] = std::max({ c3t3_ ? static_cast<double>(c3t3_->triangulation().number_of_vertices()) : 0.0,
      static_cast<double>(parallelVertices_), static_cast<double>(outputVertices_) });
    st["tetrahedra"] = std::max(c3t3_ ? static_cast<double>(c3t3_->number_of_cells_in_complex()) : 0.0,
      static_cast<double>(outputTets_));
    st["feature_points"] =
      static_cast<double>(segments_ ? segments_->segments().points.size() : conformed_.points.size());
    st["refinement_steps"] = static_cast<double>(steps_);
  }

  /// Resampled feature lines (if asked), criteria and feature lines checked.
  void prepareInputs()
  {
    inner_ = oracle_.bounds(); // throws for an empty or unbounded oracle
    given_.checkEdgeSizes();   // named on the lines as given, before resampling moves them
    if (const auto dense = denseFeatureLinesWarning(given_, options_, inner_))
      warnings_.push_back(*dense);
    resampled_ = resampledFeatures(given_, options_, oracle_, inner_, warnings_, network_);
    features_ = resampled_ ? &*resampled_ : &given_;
    deadline_.check("feature-line resampling");
    checkCriteria(options_.criteria, warnings_);
    g_ = options_.criteria.globalValues();
    if (!features_->empty())
    {
      auto w = features_->validate(oracle_, g_.cellRadiusEdgeRatio);
      warnings_.insert(warnings_.end(), w.begin(), w.end());
      deadline_.check("feature-line validation");
    }
    edgeSizes_ = resolveFeatureEdgeSizes(*features_, options_.criteria, oracle_);
    report(0.0, "initialisation");
  }

  /// The oracle as CGAL's mesh domain (with the polylines to protect for ProtectingBalls) and the
  /// criteria: ours per material; CGAL's topology criterion (facet vertices on the surface, T2).
  void buildDomainAndCriteria()
  {
    // A little room around the materials, so the boundary never touches the domain's box.
    box_ = inner_;
    const Vec3 pad = 0.02 * box_.size() + (1e-9 * (1.0 + norm(box_.size()))) * Vec3{ 1, 1, 1 };
    box_.add(box_.min - pad);
    box_.add(box_.max + pad);
    domain_ = std::make_unique<MeshDomain>(oracle_, box_, options_.seed);
    protect_ = options_.strategy == FeatureStrategy::ProtectingBalls && !features_->empty();
    StoppableEdgeSize sizing{ 1.0, &stopProtection_ };
    edgeSize_ = g_.edgeSize;
    if (protect_)
      sizing = protectedFeatures();
    else
      sizing.size = edgeSize_ > 0 ? edgeSize_ : 1.0;
    // before the criteria (the parallel levels take circumcentres at SliverAngle; the sequential
    // round after them picks its points around the slivers they left)
    threads_ = requestedThreads(options_);
    criteria_ = std::make_unique<Criteria>(
      materialMeshCriteria<Tr>(options_, Criteria::Edge_criteria(sizing), pickingRegion().targetAngle, &oracle_));
  }

  /// ProtectingBalls: the polylines added to the domain and the balls' sizes, per polyline when
  /// their edge sizes differ. A line without a bound (0) gets min(diagonal / 50, facet size, cell
  /// size), with a warning.
  StoppableEdgeSize protectedFeatures()
  {
    Polylines lines = toPolylines(*features_, edgeSizes_);
    domain_->add_features(lines.lines.begin(), lines.lines.end());
    double fallback = norm(inner_.size()) / 50.0;
    for (double v : { g_.facetSize, g_.cellSize })
      if (v > 0)
        fallback = std::min(fallback, v);
    const bool unbounded = std::any_of(lines.sizes.begin(), lines.sizes.end(), [](double e) { return e <= 0; });
    if (unbounded)
      warnings_.push_back("EdgeSize not set: protecting balls use " + std::to_string(fallback));
    for (double& e : lines.sizes)
      if (e <= 0)
        e = fallback;
    StoppableEdgeSize sizing{ g_.edgeSize > 0 ? g_.edgeSize : fallback, &stopProtection_ };
    const bool uniform = std::all_of(lines.sizes.begin(), lines.sizes.end(), [&](double e) { return e == sizing.size; });
    edgeSize_ = sizing.size;
    if (uniform)
      return sizing; // one size for every ball, as before per-feature sizes
    auto corners = std::make_shared<std::map<std::array<double, 3>, double>>();
    for (size_t k = 0; k < lines.lines.size(); ++k)
      for (const K::Point_3* p : { &lines.lines[k].front(), &lines.lines[k].back() })
      {
        const auto [it, inserted] = corners->emplace(std::array<double, 3>{ p->x(), p->y(), p->z() }, lines.sizes[k]);
        if (!inserted)
          it->second = std::min(it->second, lines.sizes[k]);
      }
    sizing.domain = domain_.get();
    sizing.size = *std::min_element(lines.sizes.begin(), lines.sizes.end());
    sizing.curveSizes = std::make_shared<const std::vector<double>>(std::move(lines.sizes));
    sizing.cornerSizes = corners;
    edgeSize_ = sizing.size;
    return sizing;
  }

  /// Conforming: rule T1 on the segments alone first (SegmentConformation.h); the domain's
  /// initial points keep away from their points (a near-coincident pair seeds a cluster of micro
  /// tetrahedra).
  void conformSegmentsT1()
  {
    conforming_ = options_.strategy == FeatureStrategy::Conforming && !features_->empty();
    if (!conforming_)
      return;
    const size_t budget = options_.maximumNumberOfVertices ? options_.maximumNumberOfVertices : 1000000;
    conformed_ =
      conformSegments(*features_, edgeSizes_, budget, warnings_, [this] { deadline_.tick("feature-line conformation"); });
    domain_->avoidInitialPointsNear(conformed_.points);
  }

  /// The initial point set: far points, then CGAL's initial points (or its protecting balls), the
  /// caller's seed points, and (Conforming) the conformed segment points.
  void initialPoints(const std::vector<Vec3>& seedPoints)
  {
    CGAL::get_default_random() = CGAL::Random(options_.seed);
    c3t3_ = std::make_unique<C3t3>();
    const auto initStart = Clock::now();
    addFarPoints();
    if (protect_)
    {
      initialPointsAwayFromFeatures();
      protectFeatures();
    }
    else
      CGAL::Mesh_3::internal::init_c3t3(*c3t3_, *domain_, *criteria_, 20);
    insertSeedPoints(seedPoints);
    initTime_ = seconds(initStart);
    insertSegmentPoints();
  }

  /// Far points around the domain keep the triangulation's hull away from the material boundary:
  /// a circumcentre on a convex domain's boundary would otherwise land on the hull (CGAL adds such
  /// points itself only in parallel mode, and not after feature protection).
  void addFarPoints()
  {
    const Vec3 c = 0.5 * (box_.min + box_.max);
    const double r = 2.0 * norm(box_.size());
    for (int i = 0; i < 8; ++i)
    {
      const Vec3 dir{ (i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0 };
      c3t3_->add_far_point(Tr::Point(toPoint(c + (r / std::sqrt(3.0)) * dir)));
    }
  }

  /// ProtectingBalls: the seed chooses the domain's initial surface points, as with the other
  /// strategies (after protection CGAL adds them only where the balls alone give no surface facet:
  /// the seed changed nothing). They go in first, away from the feature lines; the balls then
  /// leave them out, as they leave out the far points.
  void initialPointsAwayFromFeatures()
  {
    std::vector<Vec3> alongFeatures;
    const double spacing = 0.01 * norm(inner_.size());
    const FeatureSegments& f = *features_;
    for (size_t s = 0; s < f.segments.size(); ++s)
    {
      const Vec3 a = f.points[f.segments[s][0]], b = f.points[f.segments[s][1]];
      const int n = static_cast<int>(std::min(1e4, std::ceil(norm(b - a) / spacing)));
      for (int k = 0; k <= n; ++k)
        alongFeatures.push_back(lerp(a, b, static_cast<double>(k) / std::max(n, 1)));
    }
    domain_->avoidInitialPointsNear(std::move(alongFeatures));
    CGAL::Mesh_3::internal::init_c3t3(*c3t3_, *domain_, *criteria_, 20);
  }

  /// ProtectingBalls: CGAL's protection of the polylines. The vertex budget also bounds it (CGAL's
  /// ball refinement can run long on small angles). It reports no progress of its own: it runs in
  /// a worker thread while this one keeps asking the progress callback and the deadline, and stops
  /// through CGAL's stop flag (read between passes) and StoppableEdgeSize (at the next ball).
  void protectFeatures()
  {
    std::atomic<bool>& stop = stopProtection_;
    CGAL::parameters::internal::Mesh_3_options meshOptions;
    meshOptions.maximal_number_of_vertices = options_.maximumNumberOfVertices;
    meshOptions.pointer_to_stop_atomic_boolean = &stop;
    auto protection = std::async(std::launch::async, [&] {
      // CGAL's default random generator is per thread and seeded from the clock: seed this one
      CGAL::get_default_random() = CGAL::Random(options_.seed);
      try
      {
        CGAL::Mesh_3::internal::C3t3_initializer<C3t3, MeshDomain, Criteria, true, MeshDomain::Has_features>()(
          *c3t3_, *domain_, *criteria_, true, meshOptions);
      }
      catch (const ProtectionStopped&) // asked to stop: the calling thread says why
      {
      }
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
      if (deadline_.passed()) // stop the worker first: it writes the complex the message measures
      {
        stop = true;
        protection.wait();
        deadline_.fail("feature protection (protecting balls)");
      }
    }
    protection.get(); // rethrows what the worker threw
  }

  /// The paper's a-priori points, in the material the oracle gives them.
  void insertSeedPoints(const std::vector<Vec3>& seedPoints)
  {
    for (const Vec3& p : seedPoints)
    {
      const int m = oracle_.material(p);
      if (m == kOutside)
      {
        warnings_.push_back("seed point outside every material ignored");
        continue;
      }
      Tr::Vertex_handle v = c3t3_->triangulation().insert(Tr::Point(toPoint(p)));
      if (v != Tr::Vertex_handle())
      {
        c3t3_->set_dimension(v, 3);
        c3t3_->set_index(v, domain_->index_from_subdomain_index(subdomainOf(m)));
      }
    }
  }

  /// Conforming: the segments, conformed by rule T1, enter the triangulation; their points are
  /// mesh vertices of dimension 0 (input points) or 1 (on a segment), which CGAL's perturber never
  /// moves. Refinement then keeps every sub-segment's diametral ball empty (T1.2) and refuses
  /// refinement points inside them (T2.1, T3.1): see SegmentRefinementLevel.
  void insertSegmentPoints()
  {
    if (!conforming_)
      return;
    segments_ = std::make_unique<SegmentState<C3t3>>(*c3t3_, std::move(conformed_));
    // collinear points: an insertion can take milliseconds
    segments_->insertPoints(*domain_, [this] { deadline_.check("inserting the feature-line points"); });
    c3t3_->rescan_after_load_of_triangulation();
  }

  /// Expected number of vertices, for the progress bar only: about one per cell-size cube of each
  /// material (measured on the demo scene), from a coarse sampling of the oracle.
  double expectedVertices() const { return std::max(1000.0, estimateCellVertices(oracle_, options_.criteria)); }


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
        deadline_.check(refinePhase_); // also where steps insert nothing
      // the limit at every step (one load): a budget means that many vertices, not a few hundred more
      const size_t limit = finish_.active ? finish_.limit : options_.maximumNumberOfVertices;
      if (limit && c3t3_->triangulation().number_of_vertices() >= limit)
      {
        (finish_.active ? finish_.overdrawn : budgetHit_) = stopped = true;
        ++steps_;
        break;
      }
      if (++steps_ % 512 == 0)
      {
        const size_t count = c3t3_->triangulation().number_of_vertices();
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
        report(0.05 + 0.4 * std::min(1.0, n / expected_), "refinement");
      }
    }
    if (stopped)
      mesher.fix_c3t3();
  }

  /// A sub-segment missing from the mesh is worth splitting only where a material touches it (not
  /// on a feature line outside every domain).
  bool touchesMaterial(const Vec3& a, const Vec3& b) const { return oracle_.touchesMaterial(a, b); }

  /// Whether the cell level picks its refinement points (SliverAvoidingPoint, ConformingMesher3):
  /// every run but ProtectingBalls' (whose balls' weights CGAL's cells must see as they are); a
  /// parallel refinement takes CGAL's circumcentres, then one thread refines the slivers it left
  /// at picked points.
  bool picks() const
  {
    return options_.strategy != FeatureStrategy::ProtectingBalls && effectivePickingSliverAngle(options_) > 0;
  }

  /// Where the cell level takes its refinement points, and the angle below which any cell is
  /// refined.
  PickingRegion pickingRegion() const
  {
    PickingRegion r;
    r.targetAngle = options_.sliverAngle;
    r.seed = options_.seed;
    if (picks())
    {
      const double angle = effectivePickingSliverAngle(options_);
      r.candidates = kPickingCandidates;
      r.radius = kPickingRadius;
      r.targetAngle = std::max(r.targetAngle, angle);
    }
    return r;
  }

  /// The criteria of the current round: the run's, or in the finishing round after the vertex
  /// budget only what validity needs (validityMeshCriteria).
  const Criteria& roundCriteria() const { return finish_.active ? *finish_.criteria : *criteria_; }

  /// One refinement round: Conforming with the segment level below the facets; without one, the
  /// same mesher with no segments where the cells pick their points; else CGAL's Mesher_3. On
  /// one thread in the finishing round.
  void refineOnce()
  {
    const Criteria& criteria = roundCriteria();
    if (conforming_)
    {
      const auto wanted = [this](const Vec3& a, const Vec3& b) { return touchesMaterial(a, b); };
      Segments level(*c3t3_, *segments_, domain_->index_from_curve_index(1));
      ConformingMesher3<C3t3, Criteria, MeshDomain> mesher(
        *c3t3_, *domain_, criteria, level, CGAL::FACET_VERTICES_ON_SURFACE, pickingRegion());
      mesher.restrictFirstScanTo(std::move(tailRegion_), std::move(sliverRegion_)); // empty but after the parallel phase
      tailRegion_.clear();
      sliverRegion_.clear();
      drive(mesher, [&] { return level.queueMissingFromComplex(wanted) > 0; });
      countPicks(mesher.pickingCounters());
      missing_ = level.missingCensus(wanted);
    }
    else if (threads_ > 1 && !finish_.active)
    {
      parallelPhases_.leftBad.clear(); // this round's refused points only
      refineInParallelOnce();
      // the parallel levels refine at circumcentres, to kParallelRadiusEdgeFloor at most; the
      // cells they leave bad (slivers, tighter radius-edge bounds) and the elements whose points
      // the guard refused are refined here, on one thread, at picked points where picking is on.
      // Not ProtectingBalls: its balls' weights.
      if (options_.strategy != FeatureStrategy::ProtectingBalls && !budgetHit_ && !stalled_)
      {
        auto around = verticesAroundPoints(parallelPhases_.leftBad);
        auto bad = verticesOfBadCells(*c3t3_, *criteria_);
        if (!around.empty() || !bad.empty())
          refineAtPickedPoints(std::move(around), std::move(bad));
      }
    }
    else if (picks())
      refineAtPickedPoints({});
    else
    {
      Mesher mesher(*c3t3_, *domain_, criteria, CGAL::FACET_VERTICES_ON_SURFACE);
      drive(mesher, {});
    }
    ++rounds_;
  }

  /// The mesher without segments, its cells refined at picked points (circumcentres where picking
  /// is off); its first scan only around `region` unless that is empty (after a parallel
  /// refinement: the vertices of the cells left bad, the rest met the criteria when CGAL's queues
  /// ran empty; a scan of every facet would cost an intersection each).
  void refineAtPickedPoints(std::vector<Tr::Vertex_handle> region, std::vector<Tr::Vertex_handle> cellRegion = {})
  {
    SegmentState<C3t3> none(*c3t3_, SegmentSet{});
    Segments level(*c3t3_, none, domain_->index_from_curve_index(1));
    ConformingMesher3<C3t3, Criteria, MeshDomain> mesher(
      *c3t3_, *domain_, roundCriteria(), level, CGAL::FACET_VERTICES_ON_SURFACE, pickingRegion());
    mesher.restrictFirstScanTo(std::move(region), std::move(cellRegion));
    drive(mesher, {});
    countPicks(mesher.pickingCounters());
  }

  void countPicks(const PickingRegion::Counters& picked)
  {
    picking_.cells += picked.cells;
    picking_.moved += picked.moved;
    picking_.unreached += picked.unreached;
  }

  /// CGAL's parallel refinement on threads_ threads, from and back into the sequential complex.
  /// Progress, abort and the deadline are asked from this thread every 50 ms (a throw stops the
  /// refinement); the vertex budget and a stall stop it as they stop drive().
  void refineInParallelOnce(const SegmentSet* protectedSegments = nullptr)
  {
    // the sequential round after the parallel levels finishes what they leave above this bound
    // (not with ProtectingBalls: nothing follows them there)
    const MesherOptions parallelOptions = options_.strategy == FeatureStrategy::ProtectingBalls
      ? options_
      : withRadiusEdgeAtLeast(options_, kParallelRadiusEdgeFloor);
    const ParallelRefinementRun run =
      refineInParallel(*c3t3_, *domain_, parallelOptions, edgeSize_, threads_, [this](size_t n) {
        parallelVertices_ = n;
        deadline_.check(refinePhase_);
        report(0.05 + 0.4 * std::min(1.0, static_cast<double>(n) / expected_), "refinement");
      }, protectedSegments);
    parallelPhases_.leftBad.insert(parallelPhases_.leftBad.end(), run.leftBad.begin(), run.leftBad.end());
    parallelPhases_.repeatsRefused += run.repeatsRefused;
    parallelVertices_ = 0; // the complex holds them again
    if (run.budgetHit) // meshOracle meshes again on one thread: nothing of this run is kept
      throw ParallelBudgetReached{ deadline_.elapsed(), c3t3_->triangulation().number_of_vertices() };
    stalled_ = run.stalled;
    parallelCpu_ += run.cpuSeconds;
    parallelBusiestCpu_ += run.busiestThreadCpu;
    if (stalled_) // the cells the stop left out of the complex, as drive() does
      Mesher(*c3t3_, *domain_, *criteria_, CGAL::FACET_VERTICES_ON_SURFACE).fix_c3t3();
  }

  /// Conforming on threads_ threads, before the sequential round (refineOnce) that finishes it:
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
      Segments level(*c3t3_, *segments_, domain_->index_from_curve_index(1));
      Segments::Visitor none{ [](const Tr::Weighted_point&, Segments::Zone&) {}, [](const Tr::Vertex_handle&) {} };
      level.queueAll();
      for (size_t k = 0; !level.is_algorithm_done(); ++k)
      {
        level.one_step(none);
        if (k % 16 == 0)
          deadline_.check(refinePhase_);
      }
    }
    parallelPhases_.segmentVertices = c3t3_->triangulation().number_of_vertices();
    parallelPhases_.segmentSeconds = seconds(start);
    const auto parallelStart = Clock::now();
    refineInParallelOnce(&segments_->segments());
    segments_->locateVertices(); // the copy back made new vertices
    segments_->reindex();
    parallelPhases_.parallelVertices = c3t3_->triangulation().number_of_vertices();
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
    sliverRegion_ = verticesOfBadCells(*c3t3_, *criteria_);
    return !tailRegion_.empty() || !sliverRegion_.empty();
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
    const auto wanted = [this](const Vec3& a, const Vec3& b) { return touchesMaterial(a, b); };
    for (size_t s = 0; s < segments_->size(); ++s)
      if (segments_->encroached(static_cast<int>(s)) || segments_->missingFromComplex(static_cast<int>(s), wanted))
        for (int k : { 0, 1 })
          region.insert(segments_->vertexOf(segments_->end(static_cast<int>(s), k)));
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
    Tr& tr = c3t3_->triangulation();
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
      warnings_.push_back(when + "refinement stalled (100k steps without a new vertex: a refinement point "
                          "repeats an existing vertex); the criteria are not met everywhere");
    if (finish_.active)
    {
      if (finish_.overdrawn)
        warnings_.push_back(when + "the finishing round after the vertex budget stopped at its overdraft of " +
          std::to_string(finish_.overdraft) + " vertices (10 % of the budget, at least " +
          std::to_string(kFinishOverdraftMin) + "): the mesh may keep feature-line pieces that are no mesh edges, facets with vertices off "
          "the surface or slivers (the validity check names what is left)");
    }
    else if (budgetHit_)
      warnings_.push_back(when + "refinement stopped at MaximumNumberOfVertices = " +
        std::to_string(options_.maximumNumberOfVertices) + ": the criteria are not met everywhere");
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
    const size_t start = c3t3_->triangulation().number_of_vertices();
    finish_.overdraft = finishOverdraft(options_.maximumNumberOfVertices);
    finish_.limit = start + finish_.overdraft;
    auto region = std::make_shared<CriteriaRegion>(missingRegion());
    finish_.regionBalls = region->size();
    const double angle = std::max(options_.sliverAngle, kFinishSliverAngle);
    finish_.criteria = std::make_unique<Criteria>(validityMeshCriteria<Tr>(
      options_, criteria_->edge_criteria_object(), angle, pickingRegion().targetAngle, std::move(region)));
    finish_.active = true;
    const char* phase = refinePhase_;
    refinePhase_ = "refinement (finishing round after the vertex budget)";
    report(0.45, "refinement (finishing round after the vertex budget)");
    refineOnce();
    refinePhase_ = phase;
    finish_.vertices = c3t3_->triangulation().number_of_vertices() - start;
    finish_.completed = !finish_.overdrawn && !stalled_;
    warnIfUnfinished("");
  }

  /// Where the finishing round applies the run's criteria in full: a ball around each wanted
  /// sub-segment that no cell of the complex holds, kFinishRegionFactor times its length.
  CriteriaRegion missingRegion() const
  {
    CriteriaRegion region;
    if (!conforming_)
      return region;
    const SegmentSet& segs = segments_->segments();
    for (size_t i = 0; i < segments_->size(); ++i)
    {
      const int s = static_cast<int>(i);
      const Vec3 a = segs.points[segs.subs[s][0]], b = segs.points[segs.subs[s][1]];
      if (!segments_->inComplex(s) && touchesMaterial(a, b))
        region.add(0.5 * (a + b), kFinishRegionFactor * norm(b - a));
    }
    region.index();
    return region;
  }

  /// The segment, facet and cell levels together (rules T1.2, T2, T3), one step at a time.
  void refineAllLevels()
  {
    const auto refineStart = Clock::now();
    const double refineCpuStart = threadCpu();
    expected_ = expectedVertices();
    if (conforming_ && threads_ > 1)
      refineConformingInParallel();
    const auto tailStart = Clock::now();
    if (conforming_ && threads_ > 1 && (budgetHit_ || stalled_ || !parallelLeftWork()))
    {
      // stopped in the parallel phase, or nothing left for the sequential round: only why
      // sub-segments are missing
      Segments level(*c3t3_, *segments_, domain_->index_from_curve_index(1));
      missing_ = level.missingCensus([this](const Vec3& a, const Vec3& b) { return touchesMaterial(a, b); });
    }
    else
    {
      parallelPhases_.tailRan = conforming_ && threads_ > 1;
      refineOnce();
    }
    if (conforming_ && threads_ > 1)
      parallelPhases_.tailSeconds = seconds(tailStart);
    warnIfUnfinished("");
    finishAfterBudget();
    c3t3_->clear_manifold_info();
    refinedVertices_ = c3t3_->triangulation().number_of_vertices();
    refineTime_ = seconds(refineStart);
    callingThreadRefineCpu_ = threadCpu() - refineCpuStart;
    refineCpu_ = callingThreadRefineCpu_ + parallelCpu_;
  }

  /// Bounded by step budgets that scale with the mesh (deterministic: the same seed gives the same
  /// mesh on any machine); a time limit is optional (< 0: stock CGAL's, the refinement's time).
  static size_t stepBudget(double perUnit, size_t units)
  {
    return perUnit > 0 ? static_cast<size_t>(std::ceil(perUnit * static_cast<double>(units))) + 1000 : 0;
  }
  /// Progress within a phase: the share of its budget, or a creep toward its end without one.
  static double phaseProgress(size_t steps, size_t max)
  {
    return max ? static_cast<double>(steps) / static_cast<double>(max) : 1.0 - 1.0 / (1.0 + 1e-3 * steps / 256.0);
  }

  /// Sliver optimisation: CGAL's perturber, the segments repaired after it, then its exuder.
  void optimise()
  {
    const auto optStart = Clock::now();
    const double optCpuStart = threadCpu();
    minBefore_ = options_.perturb || options_.exude ? complexMinAngle(*c3t3_) : 0.0;
    optLimit_ = options_.optimisationTimeLimit < 0 ? refineTime_ : options_.optimisationTimeLimit;
    if (options_.perturb)
    {
      report(0.45, "perturbation");
      const size_t max = stepBudget(options_.perturbationStepsPerVertex, c3t3_->triangulation().number_of_vertices());
      size_t checks = 0;
      perturbed_ = perturb(*c3t3_, *domain_, optLimit_, max, options_.perturbationFailuresPerBound,
        [&] { report(0.45 + 0.35 * phaseProgress(256 * ++checks, max), "perturbation"); }, deadline_);
      repairSegmentsAfterPerturbation();
    }
    if (options_.exude)
      exudeKeepingSegments();
    if (options_.perturb || options_.exude)
      relabelled_ = relabelCellsAcrossBoundaries(
        *c3t3_, oracle_, [this](int m) { return options_.criteria.of(m).facetDistance; });
    optTime_ = seconds(optStart);
    optCpu_ = threadCpu() - optCpuStart;
    deadline_.check("optimisation");
  }

  /// The perturber never moves segment vertices, but a moved neighbour can land in a diametral
  /// ball and so break a sub-segment: refine again (the segment level splits what was encroached;
  /// weights are still zero here, after the exuder they are not).
  void repairSegmentsAfterPerturbation()
  {
    // after the vertex budget: only when the finishing round made the segments present, with its
    // criteria and what is left of its overdraft
    if (!conforming_ || (budgetHit_ && !finish_.completed) || stalled_)
      return;
    segments_->reindex();
    // The round looks only around the removals and the broken sub-segments (the insertions'
    // stars follow): a scan of every element would also refine the cells the perturber left
    // above a tight radius-edge bound, which a run without repair keeps (at radius-edge 1.1 that
    // doubled the mesh for 79 splits). Nothing to look at: nothing to repair.
    std::set<Tr::Vertex_handle> region;
    if (segments_->removeEncroachersOfShortSubSegments(&region) > 0)
      c3t3_->rescan_after_load_of_triangulation(); // the removals deleted cells of the complex
    addVerticesAtSegmentWork(region);
    if (options_.segmentRepairForTesting && segments_->size() > 0)
      for (int k : { 0, 1 })
        region.insert(segments_->vertexOf(segments_->end(0, k)));
    if (region.empty())
      return;
    tailRegion_.assign(region.begin(), region.end());
    const Counters& count = segments_->counters();
    const size_t before = count.splitsEncroached + count.splitsVetoed;
    refinePhase_ = "refinement after perturbation (segment repair)";
    refineOnce();
    warnIfUnfinished("segment repair after perturbation: ");
    repaired_ = count.splitsEncroached + count.splitsVetoed - before;
    c3t3_->clear_manifold_info();
  }

  /// CGAL's exuder changes weights, which can flip a sub-segment out of the (regular)
  /// triangulation, and stopped at its step budget it can leave a cell flatter than any before it
  /// (a flat tetrahedron on the CAD part at 2M): it is undone when it would break a segment the
  /// refinement kept or lower the smallest dihedral angle. The complex from before it is kept as a
  /// compact record (ComplexSnapshot.h), not as a copy: a copy of the triangulation was the run's
  /// peak memory.
  void exudeKeepingSegments()
  {
    report(0.8, "exudation");
    const size_t missingBefore = conforming_ ? segments_->countNotEdges() : 0;
    const double worstBefore = complexMinAngle(*c3t3_);
    std::optional<ComplexSnapshot<C3t3>> kept(std::in_place, *c3t3_);
    // The budget also ends CGAL's exuder where it cycles (seen next to protecting balls); it stops
    // between two cells, where the mesh is consistent. Without a budget, 10 pumps per cell still
    // end a cycle.
    const size_t max = stepBudget(options_.exudationStepsPerCell > 0 ? options_.exudationStepsPerCell : 10.0,
      c3t3_->number_of_cells_in_complex());
    size_t checks = 0;
    exuded_ = exude(*c3t3_, optLimit_, max, options_.exudationSliverBound,
      [&] { report(0.8 + 0.18 * phaseProgress(256 * ++checks, max), "exudation"); }, deadline_);
    if (conforming_)
      segments_->locateVertices(); // the exuder re-creates vertices: find the segment points again
    const size_t missing = conforming_ ? segments_->countNotEdges() : 0;
    const size_t broken = missing > missingBefore ? missing - missingBefore : 0;
    const double worstAfter = complexMinAngle(*c3t3_);
    if (broken == 0 && worstAfter >= worstBefore && !options_.undoExudationForTesting)
      return;
    const auto lost = kept->restore(*c3t3_);
    kept.reset();
    if (conforming_)
      segments_->locateVertices(); // the restored vertices are new ones
    std::ostringstream why;
    if (broken)
      why << "it would have removed " << broken << " constrained sub-segments from the mesh";
    else
      why << "it would have lowered the smallest dihedral angle from " << worstBefore << " to " << worstAfter
          << " degrees";
    warnings_.push_back("exudation undone: " + why.str());
    if (lost.any()) // not seen: the rebuilt triangulation is the one recorded (ComplexSnapshot.h)
      warnings_.push_back("exudation undone, but the mesh from before it came back incomplete (" +
        std::to_string(lost.vertices) + " vertices, " + std::to_string(lost.cells) + " tetrahedra, " +
        std::to_string(lost.facets) + " interface triangles missing)");
  }

  /// The output mesh, checked on its own (what a finite-element code would reject), with the
  /// statistics of the run.
  TetMesh validatedMesh()
  {
    auto started = Clock::now();
    TetMesh mesh = toTetMesh(
      *c3t3_, oracle_, segments_ ? segments_->cellsAroundEdgesOutsideComplex() : std::vector<Tr::Cell_handle>{});
    outputVertices_ = mesh.points.size();
    outputTets_ = mesh.tets.size();
    // Only the output is needed from here on: the triangulation's memory goes back before the
    // checks build their own tables (else both at once were the run's peak).
    c3t3_->clear();
    outputTime_ = seconds(started);
    started = Clock::now();
    mesh.segments = locateFeatureSegments(mesh, *features_);
    locationTime_ = seconds(started);
    deadline_.check("locating the feature lines in the mesh");
    improveAngles(mesh);
    const double coverage = featureCoverage(mesh.segments, *features_);
    if (!features_->empty() && coverage < 0.9999)
    {
      std::ostringstream o;
      o << "feature lines: " << 100.0 * coverage << "% of their length is present as mesh edges";
      // where: a missing piece on a line the user can find
      const auto first = std::find_if(mesh.segments.begin(), mesh.segments.end(), [](const auto& p) { return !p.present; });
      if (first != mesh.segments.end())
        o << "; the first missing piece lies on " << features_->describe(static_cast<size_t>(first->input));
      warnings_.push_back(o.str());
    }
    // From here on a piece names the segment as given that its resampled one came from: the
    // caller's tags (found or given, materials) are per given segment.
    if (resampled_)
      for (auto& piece : mesh.segments)
        piece.input = resampled_->source[static_cast<size_t>(piece.input)];
    warnMissingPieces();
    started = Clock::now();
    std::vector<unsigned char> defects;
    // Missing feature-line pieces are defects only where the strategy promises them (not None).
    ValidityThresholds thresholds;
    thresholds.segmentsRequired = options_.strategy != FeatureStrategy::None;
    thresholds.facetDistanceOf = [this](int m) { return options_.criteria.of(m).facetDistance; };
    // the check's pass over the tetrahedra also measures them (statistics and the caller's cell
    // arrays), its pass over the faces finds the separating ones (the writers' surface sets)
    ValidityByproducts byproducts;
    byproducts.separatingFaces = &mesh.separatingFaces;
    byproducts.shapes = &shapes_;
    if (options_.shapeArrays)
      byproducts.shapeArrays = options_.shapeArrays(mesh.tets.size());
    const MeshValidity validity = checkMeshValidity(
      mesh,
      [this](const Vec3& p) {
        deadline_.tick("validation");
        return oracle_.material(p);
      },
      thresholds, &defects, byproducts);
    mesh.tetDefects = std::move(defects);
    if (!validity.valid())
      warnings_.push_back("mesh validity: " + validity.describe());
    if (validity.acrossBoundaryTetrahedra > 0)
    {
      std::ostringstream o;
      const bool one = validity.acrossBoundaryTetrahedra == 1;
      o << validity.acrossBoundaryTetrahedra << (one ? " tetrahedron (volume " : " tetrahedra (volume ")
        << validity.acrossBoundaryVolume << (one ? ") lies" : ") lie")
        << " across a boundary: every vertex on an interface or feature line, lying in another "
        << "material by more than the finer facet distance of the two (a thin or acute part loses or "
        << "gains that volume)";
      warnings_.push_back(o.str());
    }
    for (const auto& [name, value] : validity.asStatistics())
      mesh.statistics[name] = value;
    validityTime_ = seconds(started);
    addStatistics(mesh, coverage);
    mesh.warnings = std::move(warnings_);
    report(1.0, "done");
    return mesh;
  }

  /// The quality step (DihedralImprovement.h): the located feature segments are the edges it keeps.
  void improveAngles(TetMesh& mesh)
  {
    if (!options_.improveAngles || mesh.tets.empty())
      return;
    const auto start = Clock::now();
    DihedralImprovementOptions o;
    o.minAngle = options_.improvementMinAngle;
    o.maxAngle = options_.improvementMaxAngle;
    o.cellSizeOf = [this](int material) { return options_.criteria.of(material).cellSize; };
    o.progress = [this](double f) {
      deadline_.check("quality step");
      report(0.98 + 0.02 * f, "quality step");
    };
    improvement_ = improveDihedralAngles(mesh, oracle_, o);
    improvementTime_ = seconds(start);
    outputTets_ = mesh.tets.size();
    outputVertices_ = mesh.points.size();
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
    warnings_.push_back(o.str());
  }

  /// The mesh's size and angles, what each rule did, the optimisers' runs and the times.
  void addStatistics(TetMesh& mesh, double coverage) const
  {
    const ShapeSummary& shapes = shapes_; // measured by the validity check's pass
    auto& st = mesh.statistics;
    shapes.addTo(st);
    st["tetrahedra"] = static_cast<double>(mesh.tets.size());
    st["vertices"] = static_cast<double>(mesh.points.size());
    st["min_dihedral_angle"] = mesh.tets.empty() ? 0.0 : shapes.all.minDihedral;
    st["mean_min_dihedral_angle"] = shapes.all.meanMinDihedral();
    st[keys::FEATURE_COVERAGE] = coverage;
    st["feature_segments"] = static_cast<double>(features_->segments.size());
    if (resampled_)
    {
      st["feature_segments_before_resampling"] = static_cast<double>(given_.segments.size());
      st["feature_network.points_merged"] = static_cast<double>(network_.pointsMerged);
      st["feature_network.points_snapped"] = static_cast<double>(network_.pointsSnapped);
      st["feature_network.spurs_dropped"] = static_cast<double>(network_.spursDropped);
      st["feature_network.pieces_dropped"] = static_cast<double>(network_.piecesDropped);
      st["feature_network.segments_outside_dropped"] = static_cast<double>(network_.segmentsOutside);
      st["feature_network.unmeshable_ends"] = static_cast<double>(network_.unmeshableEnds);
      st["feature_network.short_pieces_length"] = network_.shortPiecesLength;
      st["feature_network.given_to_simplified"] = network_.givenToSimplified;
      st["feature_network.simplified_to_given"] = network_.simplifiedToGiven;
      st["feature_network.smallest_angle"] = network_.smallestAngle;
      st["feature_network.shortest_segment"] = network_.shortestSegment;
    }
    st["refinement_steps"] = static_cast<double>(steps_);
    if (budgetHit_)
    {
      // the finishing round after the vertex budget (finishAfterBudget; not run after a stall)
      st["refinement.finish_vertices"] = static_cast<double>(finish_.vertices);
      st["refinement.finish_overdraft"] = static_cast<double>(finish_.overdraft);
      st["refinement.finish_completed"] = finish_.completed;
      st["refinement.finish_missing_sub_segments"] = static_cast<double>(finish_.regionBalls);
    }
    st["refinement_threads"] = threads_;
    st["refinement_rounds"] = rounds_;
    if (threads_ > 1)
      st["parallel.repeated_vertices_refused"] = static_cast<double>(parallelPhases_.repeatsRefused);
    if (conforming_ && threads_ > 1)
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
    addOptimisationStatistics(st);
    for (const auto& [m, figures] : shapes.materials)
    {
      st["volume.material_" + std::to_string(m)] = figures.volume;
      st["tetrahedra.material_" + std::to_string(m)] = static_cast<double>(figures.tetrahedra);
    }
  }

  void addSegmentStatistics(std::map<std::string, double>& st) const
  {
    const Counters count = segments_ ? segments_->counters() : Counters{};
    const SegmentSet& segs = segments_ ? segments_->segments() : conformed_;
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
    if (pickingRegion().candidates > 0)
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

  void addOptimisationStatistics(std::map<std::string, double>& st) const
  {
    if (options_.perturb || options_.exude)
      st["optimisation.min_dihedral_before"] = minBefore_;
    st["optimisation.perturbation_steps"] = static_cast<double>(perturbed_.steps);
    st["optimisation.perturbation_cut_short"] = perturbed_.cutShort;
    st["optimisation.perturbation_gave_up"] = perturbed_.gaveUp;
    st["optimisation.perturbation_last_bound"] = perturbed_.lastBound;
    st["optimisation.exudation_steps"] = static_cast<double>(exuded_.steps);
    st["optimisation.exudation_cut_short"] = exuded_.cutShort;
    st["optimisation.cells_relabelled_by_centroid"] = static_cast<double>(relabelled_);
    if (options_.improveAngles)
    {
      const auto& r = improvement_;
      st[keys::IMPROVEMENT_MIN_ANGLE] = options_.improvementMinAngle;
      st[keys::IMPROVEMENT_MAX_ANGLE] = options_.improvementMaxAngle;
      st[keys::IMPROVEMENT_OUTSIDE_BEFORE] = static_cast<double>(r.outsideBefore);
      st[keys::IMPROVEMENT_OUTSIDE_AFTER] = static_cast<double>(r.outsideAfter);
      st["improvement.min_dihedral_before"] = r.minBefore;
      st["improvement.max_dihedral_before"] = r.maxBefore;
      st["improvement.edge_removals"] = static_cast<double>(r.edgeRemovals);
      st["improvement.face_removals"] = static_cast<double>(r.faceRemovals);
      st["improvement.interior_moves"] = static_cast<double>(r.interiorMoves);
      st["improvement.edge_splits"] = static_cast<double>(r.edgeSplits);
      st["improvement.peeled"] = static_cast<double>(r.peeled);
      st["improvement.interface_moves"] = static_cast<double>(r.surfaceMoves);
      st["improvement.feature_line_moves"] = static_cast<double>(r.lineMoves);
      st["improvement.rounds"] = r.rounds;
      st[keys::IMPROVEMENT_OUTSIDE_HELD] = static_cast<double>(r.outsideHeld);
      st[keys::IMPROVEMENT_CUT_SHORT] = r.cutShort;
      st[keys::TIME_IMPROVEMENT] = improvementTime_;
    }
    st["time.perturbation"] = perturbed_.seconds;
    st["time.exudation"] = exuded_.seconds;
    st["time.initialisation"] = initTime_;
    st["time.refinement"] = refineTime_;
    st["time.optimisation"] = optTime_;
    st["time.output"] = outputTime_;
    st["time.feature_location"] = locationTime_;
    st["time.validity"] = validityTime_;
    st["time.total"] = seconds(started_);
    st["time_limit"] = deadline_.limit();
    // CPU seconds of the calling thread, and of the refinement's threads for a parallel refinement
    // (the wall times above depend on the machine's load)
    st["cpu.refinement"] = refineCpu_;
    // the refinement's CPU seconds along its critical path (the calling thread's plus the busiest
    // refinement thread's): its time on idle cores, the same as cpu.refinement when sequential
    st["cpu.refinement_critical_path"] = callingThreadRefineCpu_ + parallelBusiestCpu_;
    st["cpu.perturbation"] = perturbed_.cpuSeconds;
    st["cpu.exudation"] = exuded_.cpuSeconds;
    st["cpu.optimisation"] = optCpu_;
  }

  const HierarchicalOracle& oracle_;
  const FeatureSegments& given_;
  const MesherOptions& options_;
  const Clock::time_point started_ = Clock::now();
  MeshingDeadline deadline_; ///< asked by every phase: between steps, and inside the long ones
  /// Stops CGAL's feature protection at its next ball (StoppableEdgeSize), set when the deadline passed.
  std::atomic<bool> stopProtection_{ false };
  const char* refinePhase_ = "refinement"; ///< the deadline's name for the current refinement round
  std::vector<std::string> warnings_;
  BoundingBox inner_, box_;
  std::optional<FeatureSegments> resampled_;
  FeatureNetworkReport network_;
  const FeatureSegments* features_ = nullptr;
  MeshCriteria::Values g_{};
  std::unique_ptr<MeshDomain> domain_;
  std::unique_ptr<Criteria> criteria_;
  bool protect_ = false, conforming_ = false;
  PickingRegion::Counters picking_;
  double edgeSize_ = 0.0; ///< of the protecting balls (0 = none asked; the finest when lines differ)
  std::vector<double> edgeSizes_; ///< each feature segment's edge size (the per-feature level, FeatureEdgeSizes.h)
  int threads_ = 1;       ///< of the refinement (MesherOptions::threads)
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
  std::vector<Tr::Vertex_handle> sliverRegion_; ///< vertices of the cells the threads left bad (cells only), for the next refineOnce
  /// Vertices of a running parallel refinement, as last seen (0 otherwise).
  size_t parallelVertices_ = 0;
  SegmentSet conformed_;                       ///< rule T1's result, until the state owns it
  std::unique_ptr<C3t3> c3t3_;
  std::unique_ptr<SegmentState<C3t3>> segments_; ///< Conforming only
  Segments::MissingCensus missing_;
  double expected_ = 1000.0;
  size_t steps_ = 0, repaired_ = 0;
  size_t outputVertices_ = 0, outputTets_ = 0; ///< of the output, once the complex is cleared
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
  double initTime_ = 0.0, refineTime_ = 0.0, refineCpu_ = 0.0, optTime_ = 0.0, optCpu_ = 0.0;
  double callingThreadRefineCpu_ = 0.0;
  double parallelCpu_ = 0.0, parallelBusiestCpu_ = 0.0; ///< of every refinement thread, of the busiest one
  double minBefore_ = 0.0, optLimit_ = 0.0;
  OptimiserRun perturbed_, exuded_;
  DihedralImprovementReport improvement_;
  double improvementTime_ = 0.0;
  ShapeSummary shapes_; ///< of the output's tetrahedra, from the validity check's pass
  double outputTime_ = 0.0, locationTime_ = 0.0, validityTime_ = 0.0; ///< of validatedMesh's phases
  size_t relabelled_ = 0; ///< cells the optimisers left across a boundary (relabelCellsAcrossBoundaries)
};

TetMesh meshOracleUnguarded(const HierarchicalOracle& oracle, const FeatureSegments& givenFeatures,
  const std::vector<Vec3>& seedPoints, const MesherOptions& options)
{
  try
  {
    return MeshingRun(oracle, givenFeatures, options).run(seedPoints);
  }
  catch (const ParallelBudgetReached& stop)
  {
    // the sequential run's mesh, as a one-thread run gives it, in what is left of the time limit
    MesherOptions one = options;
    one.threads = 1;
    const double limit = effectiveTimeLimit(options);
    if (limit > 0)
      one.timeLimit = std::max(1e-3, limit - stop.seconds);
    TetMesh mesh = MeshingRun(oracle, givenFeatures, one).run(seedPoints);
    mesh.warnings.push_back("Threads = " + std::to_string(requestedThreads(options)) +
      ": the parallel refinement reached MaximumNumberOfVertices = " +
      std::to_string(options.maximumNumberOfVertices) + " (" + std::to_string(stop.vertices) +
      " vertices) and was refined again on one thread: a parallel run stopped early leaves its vertices in deep "
      "clusters (flat tetrahedra), the sequential run spreads them; raise the budget or loosen the criteria");
    mesh.statistics["parallel.budget_retry_seconds"] = stop.seconds;
    return mesh;
  }
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
