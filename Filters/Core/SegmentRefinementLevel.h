// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). The constrained segments as the lowest level of CGAL
// Mesh_3's chain of refinement levels (segments <- facets <- cells), for the paper's rules:
//  T1.2  a sub-segment whose diametral ball holds a vertex is split at its midpoint;
//  T2.1  a facet refinement point inside a sub-segment's diametral ball is not inserted, the
//        sub-segment is split instead;
//  T3.1  the same for cell refinement points (see FacetsLevelWithSegments).
// Invariant kept: every sub-segment has an empty diametral ball (it is a Gabriel edge), so it is
// an edge of the Delaunay triangulation and no refinement point can destroy it.
// Relies on CGAL 5.5's Mesher_level protocol (duck-typed: the members of Null_mesher_level).
#pragma once

#include "OracleMeshDomain.h"
#include "SegmentConformation.h"

#include <CGAL/Mesh_3/Mesher_level.h>
#include <CGAL/Meshes/Triangulation_mesher_level_traits_3.h>

#include <algorithm>
#include <deque>
#include <functional>
#include <iterator>
#include <string>
#include <unordered_map>
#include <vector>

namespace omesh
{
namespace cgal
{
template <class C3t3>
class SegmentRefinementLevel
{
public:
  using Tr = typename C3t3::Triangulation;
  using Vertex_handle = typename Tr::Vertex_handle;
  using Cell_handle = typename Tr::Cell_handle;
  using Weighted_point = typename Tr::Weighted_point;
  using Bare_point = typename Tr::Bare_point;
  using Zone = typename CGAL::Triangulation_mesher_level_traits_3<Tr>::Zone;
  using Index = typename C3t3::Index;

  /// What the upper levels (facets, cells) must do around the insertion of a segment point.
  struct Visitor
  {
    std::function<void(const Weighted_point&, Zone&)> before;
    std::function<void(const Vertex_handle&)> after;
  };

  struct Counters
  {
    size_t splitsEncroached = 0; ///< T1.2: a vertex in the diametral ball
    size_t splitsVetoed = 0;     ///< T2.1/T3.1: splits for refused refinement points
    size_t vetoes = 0;           ///< T2.1/T3.1: refinement points refused
    size_t dropped = 0;          ///< refinement points refused at sub-segments too short to split
    size_t unsplittable = 0;     ///< encroached sub-segments left alone (too short, or degenerate)
    size_t missingSplits = 0;    ///< splits of sub-segments that were no mesh edge (paper section 5)
    size_t mirrored = 0;         ///< splits that keep the shells of a small-angle cluster
    size_t removedEncroachers = 0; ///< perturbed vertices removed from balls of unsplittable sub-segments
    size_t cyclesBroken = 0;       ///< cell points dropped where T3.2 cycled (FacetsLevelWithSegments)
    size_t missingChecks = 0;      ///< sub-segments looked at by queueMissingFromComplex
  };

  /// `vertexOf[p]` is the mesh vertex of segments.points[p] (all already in the triangulation);
  /// `curveIndex` is the vertex index given to new segment points; sub-segments shorter than
  /// `minLength` are never split.
  SegmentRefinementLevel(C3t3& c3t3, SegmentSet& segments, std::vector<Vertex_handle>& vertexOf,
    Index curveIndex, double minLength, Counters& counters)
    : c3t3_(c3t3)
    , tr_(c3t3.triangulation())
    , segs_(segments)
    , vertexOf_(vertexOf)
    , curveIndex_(curveIndex)
    , minLength_(minLength)
    , count_(counters)
    , subsAt_(segments.points.size())
  {
    for (size_t p = 0; p < vertexOf_.size(); ++p)
      if (vertexOf_[p] != Vertex_handle())
        pointOf_[vertexOf_[p]] = static_cast<int>(p);
    for (size_t s = 0; s < segs_.subs.size(); ++s)
    {
      subsAt_[segs_.subs[s][0]].push_back(static_cast<int>(s));
      subsAt_[segs_.subs[s][1]].push_back(static_cast<int>(s));
    }
    inQueue_.assign(segs_.subs.size(), 0);
    refused_.assign(segs_.subs.size(), 0);
    mustSplit_.assign(segs_.subs.size(), 0);
    changed_.assign(segs_.subs.size(), 1);
    changedList_.resize(segs_.subs.size());
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      changedList_[s] = static_cast<int>(s);
  }

  /// Queues every sub-segment for the encroachment test.
  void queueAll()
  {
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      enqueue(static_cast<int>(s));
  }

  /// Number of sub-segments whose diametral ball holds a vertex.
  size_t countEncroached() const
  {
    size_t n = 0;
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      n += encroached(static_cast<int>(s));
    return n;
  }

  /// The paper's section 5 rule: a sub-segment is also bad when it is no edge of the mesh (no
  /// incident cell in the complex, as on a convex crease of the outer boundary where every
  /// incident circumcentre lies outside). Queues such sub-segments for splitting, where
  /// `wanted(a, b)` (material on at least one side) holds; returns how many were queued.
  /// Looks only at the sub-segments whose cells may have changed since the last call (see
  /// markChangedAround), in index order: the same as scanning all of them, without the cost of
  /// one whole scan per round (rounds grow with the number of segments).
  size_t queueMissingFromComplex(const std::function<bool(const Vec3&, const Vec3&)>& wanted)
  {
    std::sort(changedList_.begin(), changedList_.end());
    size_t queued = 0;
    for (int s : changedList_)
    {
      changed_[s] = 0;
      ++count_.missingChecks;
      if (!refused_[s] && missingFromComplex(s, wanted))
      {
        mustSplit_[s] = 1;
        enqueue(s);
        ++queued;
      }
    }
    changedList_.clear();
    count_.missingSplits += queued;
    return queued;
  }

  /// Number of splittable sub-segments that are no mesh edge where `wanted` (see above).
  size_t countMissingFromComplex(const std::function<bool(const Vec3&, const Vec3&)>& wanted) const
  {
    size_t n = 0;
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      n += missingFromComplex(static_cast<int>(s), wanted);
    return n;
  }

  /// Sub-segments that are no edge of a cell of the complex, by why refinement left them so.
  struct MissingCensus
  {
    size_t refused = 0; ///< a split failed or was refused
    size_t short_ = 0;  ///< too short to split
    size_t outside = 0; ///< no material on either side (not wanted)
    size_t other = 0;   ///< none of these: refinement stopped early
  };
  MissingCensus missingCensus(const std::function<bool(const Vec3&, const Vec3&)>& wanted) const
  {
    MissingCensus c;
    for (size_t s = 0; s < segs_.subs.size(); ++s)
    {
      const int a = segs_.subs[s][0], b = segs_.subs[s][1];
      if (inComplex(vertexOf_[a], vertexOf_[b]))
        continue;
      if (refused_[s])
        ++c.refused;
      else if (!splittable(static_cast<int>(s)))
        ++c.short_;
      else if (!wanted(segs_.points[a], segs_.points[b]))
        ++c.outside;
      else
        ++c.other;
    }
    return c;
  }

  /// After the perturber: a vertex off the segments that it moved into the diametral ball of a
  /// sub-segment too short to split breaks that sub-segment for good (seen at apexes of 1 degree).
  /// Removes such vertices; a refinement pass then fills their holes, refusing points inside the
  /// balls. Returns how many were removed (the complex needs a rescan then).
  size_t removeEncroachersOfShortSubSegments()
  {
    size_t removed = 0;
    for (size_t s = 0; s < segs_.subs.size(); ++s)
    {
      if (splittable(static_cast<int>(s)))
        continue;
      for (int guard = 0; guard < 16; ++guard)
      {
        const Vertex_handle v = encroacher(static_cast<int>(s));
        if (v == Vertex_handle() || pointOf_.count(v) || v->in_dimension() < 2)
          break;
        tr_.remove(v);
        ++removed;
      }
    }
    count_.removedEncroachers += removed;
    return removed;
  }

  // --- the Mesher_level protocol -------------------------------------------------------------
  bool is_algorithm_done() const { return queue_.empty(); }

  template <class V>
  bool one_step(V& visitor)
  {
    while (!queue_.empty())
    {
      const int s = queue_.front();
      queue_.pop_front();
      inQueue_[s] = 0;
      const bool vetoed = mustSplit_[s] != 0;
      mustSplit_[s] = 0;
      if (refused_[s] || !(vetoed || encroached(s)))
        continue;
      if (!splittable(s) || !split(s, visitor))
      {
        refused_[s] = 1;
        ++count_.unsplittable;
        continue;
      }
      ++(vetoed ? count_.splitsVetoed : count_.splitsEncroached);
      return true;
    }
    return false;
  }
  template <class V>
  void refine(V& visitor)
  {
    while (!is_algorithm_done())
      one_step(visitor);
  }
  template <class V>
  bool try_to_insert_one_point(V& visitor)
  {
    return one_step(visitor);
  }

  /// T2.1/T3.1: a refinement point of an upper level inside a sub-segment's diametral ball is
  /// refused and the sub-segment queued for splitting. Only sub-segments with an end on the
  /// conflict zone can be encroached: an empty diametral ball holding p gives a smaller empty ball
  /// through both ends and p, so after insertion p would connect to those ends.
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const Weighted_point& wp, Zone& zone)
  {
    const auto status = encroachedByRefinementPoint(wp.point(), zone);
    if (status == CGAL::NO_CONFLICT)
      markChangedAround(zone); // the point will be inserted (unless a facet refuses it)
    return status;
  }

  Counters& counters() { return count_; }

  std::string debug_info() const { return ""; }
  std::string debug_info_header() const { return ""; }

private:
  CGAL::Mesher_level_conflict_status encroachedByRefinementPoint(const Bare_point& p, Zone& zone)
  {
    for (const Cell_handle& c : zone.cells)
      for (int k = 0; k < 4; ++k)
      {
        const Vertex_handle v = c->vertex(k);
        const int dim = v->in_dimension();
        if (dim != 0 && dim != 1)
          continue;
        const auto it = pointOf_.find(v);
        if (it == pointOf_.end())
          continue;
        for (int s : subsAt_[it->second])
          if (inDiametralBall(s, p))
          {
            if (refused_[s] || !splittable(s))
            {
              ++count_.dropped;
              return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
            }
            ++count_.vetoes;
            mustSplit_[s] = 1;
            enqueue(s);
            return CGAL::CONFLICT_BUT_ELEMENT_CAN_BE_RECONSIDERED;
          }
      }
    return CGAL::NO_CONFLICT;
  }

  /// An insertion changes cells only in its conflict zone and its new star, whose vertices are
  /// the zone's: only sub-segments with an end there can gain or lose an incident cell of the
  /// complex. They are looked at again by the next queueMissingFromComplex.
  void markChangedAround(const Zone& zone)
  {
    for (const Cell_handle& c : zone.cells)
      for (int k = 0; k < 4; ++k)
      {
        const Vertex_handle v = c->vertex(k);
        const int dim = v->in_dimension();
        if (dim != 0 && dim != 1)
          continue;
        const auto it = pointOf_.find(v);
        if (it != pointOf_.end())
          for (int s : subsAt_[it->second])
            markChanged(s);
      }
  }

  void markChanged(int s)
  {
    if (!changed_[s])
    {
      changed_[s] = 1;
      changedList_.push_back(s);
    }
  }

  Bare_point pointAt(int p) const { return toPoint(segs_.points[p]); }

  bool inDiametralBall(int s, const Bare_point& p) const
  {
    const Vec3 a = segs_.points[segs_.subs[s][0]], b = segs_.points[segs_.subs[s][1]];
    const Vec3 d = toVec(p) - 0.5 * (a + b);
    return dot(d, d) < 0.25 * dot(b - a, b - a) * (1.0 - 1e-12);
  }

  bool splittable(int s) const { return segs_.length(s) > 2.0 * minLength_; }

  /// Sub-segment s is splittable, no cell of the complex holds it, and `wanted` it.
  bool missingFromComplex(int s, const std::function<bool(const Vec3&, const Vec3&)>& wanted) const
  {
    const int a = segs_.subs[s][0], b = segs_.subs[s][1];
    return splittable(s) && !inComplex(vertexOf_[a], vertexOf_[b]) && wanted(segs_.points[a], segs_.points[b]);
  }

  /// Edge ab exists and one of its incident cells is in the complex.
  bool inComplex(Vertex_handle a, Vertex_handle b) const
  {
    Cell_handle c;
    int i, j;
    if (!tr_.is_edge(a, b, c, i, j))
      return false;
    auto first = tr_.incident_cells(c, i, j), cell = first;
    do
    {
      if (c3t3_.is_in_complex(cell))
        return true;
    } while (++cell != first);
    return false;
  }

  /// A vertex other than its ends in the diametral ball: then the nearest vertex to the midpoint
  /// is such a vertex (the ends lie on the ball's boundary).
  bool encroached(int s) const { return encroacher(s) != Vertex_handle(); }

  /// That vertex, or a null handle.
  Vertex_handle encroacher(int s) const
  {
    const int a = segs_.subs[s][0], b = segs_.subs[s][1];
    const Vec3 mid = 0.5 * (segs_.points[a] + segs_.points[b]);
    const Vertex_handle v = tr_.nearest_power_vertex(toPoint(mid), vertexOf_[a]->cell());
    if (v == vertexOf_[a] || v == vertexOf_[b] || tr_.is_infinite(v) || !inDiametralBall(s, tr_.point(v).point()))
      return Vertex_handle();
    return v;
  }

  void enqueue(int s)
  {
    if (!inQueue_[s])
    {
      inQueue_[s] = 1;
      queue_.push_back(s);
    }
  }

  /// Splits sub-segment s at its midpoint and keeps the shells of its small-angle cluster (the
  /// same distance from the apex on the cluster's other segments, see SegmentSet).
  template <class V>
  bool split(int s, V& visitor)
  {
    const auto mirrors = segs_.mirrorSplits(static_cast<size_t>(s), 0.5);
    if (!insertSplit(s, 0.5, visitor))
      return false;
    for (const auto& [x, t] : mirrors)
      count_.mirrored += insertSplit(x, t, visitor);
    return true;
  }

  /// Inserts the point at parameter t of sub-segment s, as Mesh_3's levels insert their points:
  /// conflict zone, the upper levels told before and after.
  template <class V>
  bool insertSplit(int s, double t, V& visitor)
  {
    const int a = segs_.subs[s][0];
    // exactly the point SegmentSet::split stores: the exuder check finds segment points by exact location
    const Vec3 mid = lerp(segs_.points[a], segs_.points[segs_.subs[s][1]], t);
    const Weighted_point wp(toPoint(mid));
    Zone zone;
    zone.cell = tr_.locate(wp, zone.locate_type, zone.i, zone.j, vertexOf_[a]->cell());
    if (zone.locate_type == Tr::VERTEX)
      return false; // the midpoint is already a vertex: nothing to insert
    tr_.find_conflicts(wp, zone.cell, std::back_inserter(zone.boundary_facets), std::back_inserter(zone.cells),
      std::back_inserter(zone.internal_facets));
    if (zone.cells.empty() || zone.boundary_facets.empty())
      return false;
    // segment points around the hole: the new point may encroach their sub-segments
    std::vector<int> near;
    for (const Cell_handle& c : zone.cells)
      for (int k = 0; k < 4; ++k)
      {
        const auto it = pointOf_.find(c->vertex(k));
        if (it != pointOf_.end())
          near.push_back(it->second);
      }
    visitor.before(wp, zone);
    const auto& f = zone.boundary_facets.front();
    Vertex_handle v = tr_.insert_in_hole(wp, zone.cells.begin(), zone.cells.end(), f.first, f.second);
    c3t3_.set_dimension(v, 1);
    c3t3_.set_index(v, curveIndex_);

    const int b = segs_.subs[s][1];
    const int m = segs_.split(static_cast<size_t>(s), t);
    const int n = static_cast<int>(segs_.subs.size()) - 1; // (m, b)
    vertexOf_.resize(segs_.points.size());
    vertexOf_[m] = v;
    pointOf_[v] = m;
    subsAt_.resize(segs_.points.size());
    subsAt_[m] = { s, n };
    for (int& x : subsAt_[b])
      if (x == s)
        x = n;
    inQueue_.resize(segs_.subs.size(), 0);
    refused_.resize(segs_.subs.size(), 0);
    mustSplit_.resize(segs_.subs.size(), 0);
    changed_.resize(segs_.subs.size(), 0);
    refused_[s] = 0; // a shorter piece now: judged again
    markChanged(s);
    markChanged(n);
    visitor.after(v);
    enqueue(s);
    enqueue(n);
    for (int p : near)
      for (int x : subsAt_[p])
      {
        enqueue(x);
        markChanged(x);
      }
    return true;
  }

  C3t3& c3t3_;
  Tr& tr_;
  SegmentSet& segs_;
  std::vector<Vertex_handle>& vertexOf_;
  Index curveIndex_;
  double minLength_;
  Counters& count_;
  std::unordered_map<Vertex_handle, int> pointOf_;
  std::vector<std::vector<int>> subsAt_;
  std::deque<int> queue_;
  std::vector<char> inQueue_;
  std::vector<char> refused_;
  std::vector<char> mustSplit_; ///< queued by a refused refinement point
  std::vector<char> changed_;   ///< cells around it may have changed since the last missing-edge scan
  std::vector<int> changedList_;
};
}
}
