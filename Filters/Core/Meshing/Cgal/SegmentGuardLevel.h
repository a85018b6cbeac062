// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). The constrained segments as a read-only level below
// CGAL's parallel facet and cell levels (GuardedParallelMesher3.h): rules T2.1/T3.1 without the
// split. A refinement point inside a sub-segment's diametral ball is not inserted and its element
// is dropped (it stays bad); the sequential Conforming refinement that follows splits the
// sub-segment for it. Nothing is inserted into the balls, so the sub-segments stay Gabriel edges
// and do not change while the threads refine: the level only reads, from any thread.
#pragma once

#include "ExactCoordinates.h"
#include "OracleMeshDomain.h"
#include "SegmentConformation.h"
#include "SegmentRules.h"

#include <CGAL/Mesh_3/Mesher_level.h>

#include <cstddef>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace omesh
{
namespace cgal
{
class SegmentGuardLevel : public CGAL::Mesh_3::Null_mesher_level
{
public:
  /// `segments`: the sub-segments as the sequential segment level left them, every point a vertex.
  explicit SegmentGuardLevel(const SegmentSet& segments)
    : segs_(segments)
    , subsAt_(segments.points.size())
  {
    for (size_t p = 0; p < segs_.points.size(); ++p)
      pointAt_.emplace(key(segs_.points[p]), static_cast<int>(p));
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      for (int k : { 0, 1 })
        subsAt_[segs_.subs[s][k]].push_back(static_cast<int>(s));
  }

  /// T2.1/T3.1 on the points of CGAL's facet and cell levels. As in SegmentRefinementLevel, only
  /// sub-segments with an end on the conflict zone can be encroached (an empty diametral ball
  /// holding p gives a smaller empty ball through both ends and p, so p would connect to them).
  /// The zone is locked by the calling thread; the look-ups are const.
  template <class P, class Zone>
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const P& wp, Zone& zone)
  {
    const Vec3 p = toVec(wp.point());
    for (const auto& c : zone.cells)
      for (int k = 0; k < 4; ++k)
      {
        const auto v = c->vertex(k);
        if (v->in_dimension() != 0 && v->in_dimension() != 1)
          continue;
        const auto it = pointAt_.find(key(toVec(v->point().point())));
        if (it == pointAt_.end())
          continue;
        for (int s : subsAt_[it->second])
          if (rules::encroaches(segs_.points[segs_.subs[s][0]], segs_.points[segs_.subs[s][1]], p))
          {
            countDrop(p);
            return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
          }
      }
    return CGAL::NO_CONFLICT;
  }
  template <class P, class Zone, class Visitor>
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const P& wp, Zone& zone, Visitor&)
  {
    return test_point_conflict_from_superior(wp, zone);
  }

  /// The refinement points of the elements left bad: refused here, or (FacetsLevelWithGuard) of
  /// cells whose encroached facet's point was. Each element's vertices are nearest vertices of
  /// its point (an empty ball centred there), so the sequential round finds the element among
  /// the cells of the point's conflict zone.
  void countDrop(const Vec3& p)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    dropped_.push_back(p);
  }
  /// Call once the threads are done.
  const std::vector<Vec3>& dropped() const { return dropped_; }

private:
  static ExactCoordinates key(const Vec3& p) { return exactCoordinates(p.x, p.y, p.z); }

  const SegmentSet& segs_;
  std::unordered_map<ExactCoordinates, int, ExactCoordinatesHash> pointAt_; ///< segment point by its exact coordinates
  std::vector<std::vector<int>> subsAt_;
  std::mutex mutex_; ///< drops are rare: a lock is cheap enough
  std::vector<Vec3> dropped_;
};
}
}
