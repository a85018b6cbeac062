// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL): the cell level's refinement point taken from a small
// "picking region" around the circumcentre instead of the circumcentre itself (Li and Teng,
// "Generating well-shaped Delaunay meshes in 3D", SODA 2001), so the cells an insertion makes are
// not slivers. Splitting a sliver at its circumcentre tends to make new slivers next to it.
#pragma once

#include "MeshQuality.h"
#include "OracleMeshDomain.h"

#include <CGAL/number_utils.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace omesh::cgal
{
/// The picking region of the mesher: 16 candidates in a ball of 0.2 x the circumradius (Li and
/// Teng's delta). Measured on the generated bone/implant cases at radius-edge 1.1 (MESHER.md):
/// 0.3 cost up to 2.8x the tetrahedra of circumcentres, 0.4 ran into the vertex budget.
constexpr int kPickingCandidates = 16;
constexpr double kPickingRadius = 0.2;

/// How a cell's refinement point is chosen (from MesherOptions::pickingSliverAngle and the
/// constants above: OracleMesher's pickingRegion).
struct PickingRegion
{
  int candidates = 0;       ///< points tried besides the circumcentre; 0 = the circumcentre (CGAL's)
  double radius = kPickingRadius; ///< of the picking ball, relative to the cell's circumradius
  double targetAngle = 0.0; ///< degrees: the first point whose new cells all reach this is taken
  unsigned seed = 0;

  /// Counters behind the statistics refinement_point_*.
  struct Counters
  {
    size_t cells = 0;     ///< cells whose point was looked at
    size_t moved = 0;     ///< cells that got a point other than their circumcentre
    size_t unreached = 0; ///< cells where no point reached the target (the best one was taken)
  };
};

/// Picks the refinement point of a cell: the circumcentre if the cells its insertion would make
/// (the conflict zone's boundary facets joined to it) all have a minimal dihedral angle of at least
/// `targetAngle`, else the first of `candidates` points drawn in the ball of radius `radius` x the
/// circumradius around it that does, else the best of them. A candidate must lie in the cell's
/// material (the circumcentre's, which gave the cell its material). The draws depend only on the
/// seed and the circumcentre, so the same cell asked again gets the same point (the T3.2 cycle
/// rule in FacetsLevelWithSegments relies on it) and a run is the same for the same seed.
template <class Tr, class Domain>
class SliverAvoidingPoint
{
public:
  using Cell_handle = typename Tr::Cell_handle;
  using Facet = typename Tr::Facet;
  using Point = typename Tr::Bare_point;

  SliverAvoidingPoint(const Tr& tr, const Domain& domain, const PickingRegion& region)
    : tr_(tr)
    , domain_(domain)
    , region_(region)
  {
  }

  bool active() const { return region_.candidates > 0 && region_.targetAngle > 0; }
  const PickingRegion::Counters& counters() const { return counters_; }

  Point pick(const Cell_handle& cell, const Point& centre)
  {
    for (int i = 0; i < 4; ++i)
      if (tr_.point(cell, i).weight() != 0) // weighted vertices: the power sphere, not a ball around it
        return centre;
    ++counters_.cells;
    const Insertion atCentre = evaluate(cell, centre);
    if (atCentre.worstAngle >= region_.targetAngle)
      return centre;
    // An encroaching circumcentre is replaced only by a candidate that reaches the target: else it
    // goes its way (T3.2 splits the facet it encroaches).
    double best = atCentre.encroaches ? -1.0 : atCentre.worstAngle;
    const double radius = region_.radius * std::sqrt(CGAL::to_double(CGAL::squared_distance(centre, tr_.point(cell, 0).point())));
    std::mt19937_64 draw(seedOf(centre));
    auto unit = [&draw] { return static_cast<double>(draw() >> 11) * 0x1.0p-53 * 2.0 - 1.0; };
    Point chosen = centre;
    for (int k = 0; k < region_.candidates; ++k)
    {
      double x, y, z;
      do
      {
        x = unit(), y = unit(), z = unit();
      } while (x * x + y * y + z * z > 1.0);
      const Point p(centre.x() + radius * x, centre.y() + radius * y, centre.z() + radius * z);
      // a candidate that would encroach where the circumcentre does not would split the boundary
      // for nothing but the choice of point
      const Insertion there = evaluate(cell, p);
      if (there.encroaches || there.worstAngle <= best)
        continue;
      const auto material = domain_.is_in_domain_object()(p);
      if (!material || *material != cell->subdomain_index())
        continue;
      best = there.worstAngle;
      chosen = p;
      if (best >= region_.targetAngle)
        break;
    }
    if (best < region_.targetAngle)
    {
      ++counters_.unreached;
      if (atCentre.encroaches)
        chosen = centre;
    }
    if (chosen != centre)
      ++counters_.moved;
    return chosen;
  }

private:
  struct Insertion
  {
    double worstAngle = -1.0; ///< smallest dihedral angle (degrees) of the cells it would make
    bool encroaches = false;  ///< a restricted facet, as the facet level would see it (T3.2)
  };

  /// What inserting p would do: the cells it makes (the conflict zone's boundary facets joined to
  /// p) and whether the facet level would refuse it. Side-effect free, unlike the levels' tests.
  Insertion evaluate(const Cell_handle& cell, const Point& p)
  {
    boundary_.clear();
    internal_.clear();
    Insertion result;
    const typename Tr::Weighted_point wp = tr_.geom_traits().construct_weighted_point_3_object()(p);
    if (tr_.side_of_power_sphere(cell, wp) != CGAL::ON_BOUNDED_SIDE)
      return result;
    tr_.find_conflicts(wp, cell, std::back_inserter(boundary_), CGAL::Emptyset_iterator(), std::back_inserter(internal_));
    for (const Facet& f : internal_)
      result.encroaches = result.encroaches || f.first->is_facet_on_surface(f.second);
    const Vec3 a = toVec(p);
    double worstCosine = -1.0; // one acos at the end, of the largest cosine (acos decreases)
    for (const Facet& f : boundary_)
    {
      const Cell_handle c = f.first;
      const int i = f.second;
      if (tr_.is_infinite(c->vertex((i + 1) & 3)) || tr_.is_infinite(c->vertex((i + 2) & 3)) ||
        tr_.is_infinite(c->vertex((i + 3) & 3)))
        continue;
      const Point& q = tr_.point(c, (i + 1) & 3).point();
      if (c->is_facet_on_surface(i))
      {
        // CGAL's rule (Refine_facets_3::is_facet_encroached): p no farther from the facet's
        // surface centre than its vertices
        const Point& centre = c->get_facet_surface_center(i);
        result.encroaches = result.encroaches || CGAL::squared_distance(centre, p) <= CGAL::squared_distance(centre, q);
      }
      worstCosine = std::max(worstCosine,
        largestDihedralCosine(a, toVec(q), toVec(tr_.point(c, (i + 2) & 3).point()), toVec(tr_.point(c, (i + 3) & 3).point())));
    }
    result.worstAngle = worstCosine > -1.0 ? std::acos(worstCosine) * 180.0 / M_PI : 180.0; // as minDihedralAngle
    return result;
  }

  std::uint64_t seedOf(const Point& centre) const
  {
    std::uint64_t h = 0x9E3779B97F4A7C15ull ^ region_.seed;
    for (const double v : { CGAL::to_double(centre.x()), CGAL::to_double(centre.y()), CGAL::to_double(centre.z()) })
    {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h ^= bits + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    }
    return h;
  }

  const Tr& tr_;
  const Domain& domain_;
  PickingRegion region_;
  PickingRegion::Counters counters_;
  std::vector<Facet> boundary_, internal_;
};
}
