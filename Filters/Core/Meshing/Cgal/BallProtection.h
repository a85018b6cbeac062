// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: the ProtectingBalls strategy's protection of the feature lines.
#pragma once

#include "FeatureProtection.h"
#include "MeshingContext.h"

#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <map>
#include <memory>

namespace omesh::cgal::sequential
{
/// ProtectingBalls (section 4 of the paper, CGAL's protecting balls): the polylines added to the
/// domain with the balls' sizes, the domain's initial points kept away from them, then CGAL's
/// protection run in a worker thread that the deadline and the caller's abort can stop.
///
/// @sa InitialComplex (which calls it), FeatureProtection.h (the polylines and StoppableEdgeSize)
class BallProtection
{
public:
  explicit BallProtection(MeshingContext& run)
    : run_(run)
  {
  }

  /// ProtectingBalls: the polylines added to the domain and the balls' sizes, per polyline when
  /// their edge sizes differ. A line without a bound (0) gets min(diagonal / 50, facet size, cell
  /// size), with a warning.
  StoppableEdgeSize sizing()
  {
    Polylines lines = toPolylines(*run_.features, run_.edgeSizes);
    run_.domain->add_features(lines.lines.begin(), lines.lines.end());
    double fallback = norm(run_.inner.size()) / 50.0;
    for (double v : { run_.g.facetSize, run_.g.cellSize })
      if (v > 0)
        fallback = std::min(fallback, v);
    const bool unbounded = std::any_of(lines.sizes.begin(), lines.sizes.end(), [](double e) { return e <= 0; });
    if (unbounded)
      run_.warnings.push_back("EdgeSize not set: protecting balls use " + std::to_string(fallback));
    for (double& e : lines.sizes)
      if (e <= 0)
        e = fallback;
    StoppableEdgeSize sizing{ run_.g.edgeSize > 0 ? run_.g.edgeSize : fallback, &run_.stopProtection };
    const bool uniform = std::all_of(lines.sizes.begin(), lines.sizes.end(), [&](double e) { return e == sizing.size; });
    run_.edgeSize = sizing.size;
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
    sizing.domain = run_.domain.get();
    sizing.size = *std::min_element(lines.sizes.begin(), lines.sizes.end());
    sizing.curveSizes = std::make_shared<const std::vector<double>>(std::move(lines.sizes));
    sizing.cornerSizes = corners;
    run_.edgeSize = sizing.size;
    return sizing;
  }


  /// ProtectingBalls: the seed chooses the domain's initial surface points, as with the other
  /// strategies (after protection CGAL adds them only where the balls alone give no surface facet:
  /// the seed changed nothing). They go in first, away from the feature lines; the balls then
  /// leave them out, as they leave out the far points.
  void initialPointsAwayFromFeatures()
  {
    std::vector<Vec3> alongFeatures;
    const double spacing = 0.01 * norm(run_.inner.size());
    const FeatureSegments& f = *run_.features;
    for (size_t s = 0; s < f.segments.size(); ++s)
    {
      const Vec3 a = f.points[f.segments[s][0]], b = f.points[f.segments[s][1]];
      const int n = static_cast<int>(std::min(1e4, std::ceil(norm(b - a) / spacing)));
      for (int k = 0; k <= n; ++k)
        alongFeatures.push_back(lerp(a, b, static_cast<double>(k) / std::max(n, 1)));
    }
    run_.domain->avoidInitialPointsNear(std::move(alongFeatures));
    CGAL::Mesh_3::internal::init_c3t3(*run_.c3t3, *run_.domain, *run_.criteria, 20);
  }

  /// ProtectingBalls: CGAL's protection of the polylines. The vertex budget also bounds it (CGAL's
  /// ball refinement can run long on small angles). It reports no progress of its own: it runs in
  /// a worker thread while this one keeps asking the progress callback and the deadline, and stops
  /// through CGAL's stop flag (read between passes) and StoppableEdgeSize (at the next ball).
  void protect()
  {
    std::atomic<bool>& stop = run_.stopProtection;
    CGAL::parameters::internal::Mesh_3_options meshOptions;
    meshOptions.maximal_number_of_vertices = run_.options.maximumNumberOfVertices;
    meshOptions.pointer_to_stop_atomic_boolean = &stop;
    auto protection = std::async(std::launch::async, [&] {
      // CGAL's default random generator is per thread and seeded from the clock: seed this one
      CGAL::get_default_random() = CGAL::Random(run_.options.seed);
      try
      {
        CGAL::Mesh_3::internal::C3t3_initializer<C3t3, MeshDomain, Criteria, true, MeshDomain::Has_features>()(
          *run_.c3t3, *run_.domain, *run_.criteria, true, meshOptions);
      }
      catch (const ProtectionStopped&) // asked to stop: the calling thread says why
      {
      }
    });
    while (protection.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready)
    {
      try
      {
        run_.report(0.02, "feature protection");
      }
      catch (...)
      {
        stop = true;
        protection.wait();
        throw;
      }
      if (run_.deadline.passed()) // stop the worker first: it writes the complex the message measures
      {
        stop = true;
        protection.wait();
        run_.deadline.fail("feature protection (protecting balls)");
      }
    }
    protection.get(); // rethrows what the worker threw
  }

private:
  MeshingContext& run_;
};
}
