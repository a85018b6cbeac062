// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). A read-only level below CGAL's parallel facet and cell
// levels (GuardedParallelMesher3.h) that refuses two kinds of refinement points; the element of a
// refused point is dropped (it stays bad) and left to the sequential round that follows:
// - points that repeat a vertex (closer to one than kRepeatRatio of their conflict zone's reach).
//   Threads refine elements that another thread's insertion already made stale; under criteria
//   no facet can meet (facet angle 89) their points land ulps from vertices just inserted:
//   CGAL inserts them as new vertices (duplicates, flat tets around them) or, for an exact repeat,
//   fails ("already inserted"). One thread never sees a stale element.
// - with constrained segments (Conforming): points inside a sub-segment's diametral ball (rules
//   T2.1/T3.1 without the split; the sequential Conforming round splits it). Nothing is inserted
//   into the balls, so the sub-segments stay Gabriel edges and do not change while the threads
//   refine: the level only reads, from any thread.
#pragma once

#include "ExactCoordinates.h"
#include "OracleMeshDomain.h"
#include "SegmentConformation.h"
#include "SegmentRules.h"

#include <CGAL/Mesh_3/Mesher_level.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace omesh
{
namespace cgal
{
class ParallelGuardLevel : public CGAL::Mesh_3::Null_mesher_level
{
public:
  /// A point closer to a vertex than this times the distance to its conflict zone's farthest
  /// vertex repeats that vertex. A fresh element's point is at least its empty ball's radius from
  /// every vertex, a fair fraction of the zone's reach; a stale one's can be anywhere, down to 0.
  static constexpr double kRepeatRatio = 1e-6;

  /// `segments`: the sub-segments as the sequential segment level left them, every point a vertex
  /// (empty without constrained segments).
  explicit ParallelGuardLevel(const SegmentSet& segments)
    : segs_(segments)
    , subsAt_(segments.points.size())
  {
    for (size_t p = 0; p < segs_.points.size(); ++p)
      pointAt_.emplace(key(segs_.points[p]), static_cast<int>(p));
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      for (int k : { 0, 1 })
        subsAt_[segs_.subs[s][k]].push_back(static_cast<int>(s));
  }

  /// The triangulation's infinite vertex, skipped among the zone's vertices (its point is no point).
  void setInfiniteVertex(const void* infinite) { infinite_ = infinite; }

  /// The repeat test, then T2.1/T3.1 on the points of CGAL's facet and cell levels. As in
  /// SegmentRefinementLevel, only sub-segments with an end on the conflict zone can be encroached
  /// (an empty diametral ball holding p gives a smaller empty ball through both ends and p, so p
  /// would connect to them). A point's nearest vertex is a vertex of its zone (the two connect).
  /// The zone is locked by the calling thread; the look-ups are const.
  template <class P, class Zone>
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const P& wp, Zone& zone)
  {
    const Vec3 p = toVec(wp.point());
    double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
    for (const auto& c : zone.cells)
      for (int k = 0; k < 4; ++k)
      {
        const auto v = c->vertex(k);
        if (static_cast<const void*>(&*v) == infinite_)
          continue;
        const Vec3 d = toVec(v->point().point()) - p;
        const double dd = dot(d, d);
        nearest = std::min(nearest, dd);
        farthest = std::max(farthest, dd);
      }
    if (nearest <= kRepeatRatio * kRepeatRatio * farthest)
    {
      countRepeat(p);
      return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
    }
    if (segs_.subs.empty())
      return CGAL::NO_CONFLICT;
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
  /// How many of the dropped points repeated a vertex.
  std::size_t repeats() const { return repeats_; }

private:
  static ExactCoordinates key(const Vec3& p) { return exactCoordinates(p.x, p.y, p.z); }
  void countRepeat(const Vec3& p)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    dropped_.push_back(p);
    ++repeats_;
  }

  const SegmentSet& segs_;
  std::unordered_map<ExactCoordinates, int, ExactCoordinatesHash> pointAt_; ///< segment point by its exact coordinates
  std::vector<std::vector<int>> subsAt_;
  const void* infinite_ = nullptr;
  std::mutex mutex_; ///< drops are rare: a lock is cheap enough
  std::vector<Vec3> dropped_;
  std::size_t repeats_ = 0;
};
}
}
