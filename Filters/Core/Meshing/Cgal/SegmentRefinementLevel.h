// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). The constrained segments as the lowest level of CGAL
// Mesh_3's chain of refinement levels (segments <- facets <- cells), for the paper's rules
// (SegmentRules.h):
//  T1.2  a sub-segment whose diametral ball holds a vertex is split at its midpoint;
//  T2.1  a facet refinement point inside a sub-segment's diametral ball is not inserted, the
//        sub-segment is split instead;
//  T3.1  the same for cell refinement points (see FacetsLevelWithSegments).
// Invariant kept: every sub-segment has an empty diametral ball (it is a Gabriel edge), so it is
// an edge of the Delaunay triangulation and no refinement point can destroy it.
// The segments themselves (points, splits, vertices, queries) live in SegmentState; this level
// keeps only its queue. Relies on CGAL 5.5's Mesher_level protocol (duck-typed: the members of
// Null_mesher_level).
#pragma once

#include "SegmentState.h"

#include <CGAL/Mesh_3/Mesher_level.h>
#include <CGAL/Meshes/Triangulation_mesher_level_traits_3.h>

#include <algorithm>
#include <deque>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

namespace omesh
{
namespace cgal
{
template <class C3t3>
class SegmentRefinementLevel
{
public:
  using State = SegmentState<C3t3>;
  using Tr = typename C3t3::Triangulation;
  using Vertex_handle = typename Tr::Vertex_handle;
  using Cell_handle = typename Tr::Cell_handle;
  using Weighted_point = typename Tr::Weighted_point;
  using Bare_point = typename Tr::Bare_point;
  using Zone = typename CGAL::Triangulation_mesher_level_traits_3<Tr>::Zone;
  using Index = typename C3t3::Index;
  using Counters = typename State::Counters;

  /// What the upper levels (facets, cells) must do around the insertion of a segment point.
  struct Visitor
  {
    std::function<void(const Weighted_point&, Zone&)> before;
    std::function<void(const Vertex_handle&)> after;
  };

  /// Sub-segments that are no edge of a cell of the complex, by why refinement left them so.
  struct MissingCensus
  {
    size_t refused = 0; ///< a split failed or was refused
    size_t short_ = 0;  ///< too short to split
    size_t outside = 0; ///< no material on either side (not wanted)
    size_t other = 0;   ///< none of these: refinement stopped early
    Vec3 firstShort;       ///< midpoint of the first one too short to split (when short_ > 0)
    double shortest = 0.0; ///< length of the shortest one too short to split
  };

  /// Every segment point is a vertex of the triangulation (SegmentState::insertPoints);
  /// `curveIndex` is the vertex index given to new segment points.
  SegmentRefinementLevel(C3t3& c3t3, State& state, Index curveIndex)
    : c3t3_(c3t3)
    , tr_(c3t3.triangulation())
    , state_(state)
    , curveIndex_(curveIndex)
  {
    state_.reindex();
    inQueue_.assign(state_.size(), 0);
    refused_.assign(state_.size(), 0);
    mustSplit_.assign(state_.size(), 0);
    changed_.assign(state_.size(), 1);
    changedList_.resize(state_.size());
    for (size_t s = 0; s < state_.size(); ++s)
      changedList_[s] = static_cast<int>(s);
  }

  /// Queues every sub-segment for the encroachment test.
  void queueAll()
  {
    for (size_t s = 0; s < state_.size(); ++s)
      enqueue(static_cast<int>(s));
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
      ++state_.counters().missingChecks;
      if (!refused_[s] && state_.missingFromComplex(s, wanted))
      {
        mustSplit_[s] = 1;
        enqueue(s);
        ++queued;
      }
    }
    changedList_.clear();
    state_.counters().missingSplits += queued;
    return queued;
  }

  MissingCensus missingCensus(const std::function<bool(const Vec3&, const Vec3&)>& wanted) const
  {
    MissingCensus c;
    for (size_t i = 0; i < state_.size(); ++i)
    {
      const int s = static_cast<int>(i);
      if (state_.inComplex(s))
        continue;
      const SegmentSet& segs = state_.segments();
      if (refused_[s])
        ++c.refused;
      else if (!state_.splittable(s))
      {
        const auto& a = segs.points[segs.subs[s][0]];
        const auto& b = segs.points[segs.subs[s][1]];
        const double length = norm(b - a);
        if (c.short_++ == 0 || length < c.shortest)
          c.shortest = length;
        if (c.short_ == 1)
          c.firstShort = lerp(a, b, 0.5);
      }
      else if (!wanted(segs.points[segs.subs[s][0]], segs.points[segs.subs[s][1]]))
        ++c.outside;
      else
        ++c.other;
    }
    return c;
  }

  // --- the Mesher_level protocol -------------------------------------------------------------
  bool is_algorithm_done() const { return queue_.empty(); }

  /// T1.2 (and the splits T2.1/T3.1 asked for): the next queued sub-segment that is still bad.
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
      if (refused_[s])
        continue;
      const bool bad = vetoed || state_.encroached(s);
      const std::optional<double> t = state_.splitT12(s, bad); // rules::splitEncroachedT12
      if (!t && !bad)
        continue;
      if (!t || !split(s, *t, visitor)) // bad but at the floor, or its point already a vertex
      {
        refused_[s] = 1;
        ++state_.counters().unsplittable;
        continue;
      }
      ++(vetoed ? state_.counters().splitsVetoed : state_.counters().splitsEncroached);
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

  /// T2.1/T3.1 for a refinement point of an upper level (rules::refinementPointT21T31). Only
  /// sub-segments with an end on the conflict zone can be encroached: an empty diametral ball
  /// holding p gives a smaller empty ball through both ends and p, so after insertion p would
  /// connect to those ends.
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const Weighted_point& wp, Zone& zone)
  {
    const auto status = refinementPointT21T31(wp.point(), zone);
    if (status == CGAL::NO_CONFLICT)
      markChangedAround(zone); // the point will be inserted (unless a facet refuses it)
    return status;
  }

  Counters& counters() { return state_.counters(); }

  std::string debug_info() const { return ""; }
  std::string debug_info_header() const { return ""; }

private:
  CGAL::Mesher_level_conflict_status refinementPointT21T31(const Bare_point& p, Zone& zone)
  {
    std::vector<int> subs;
    std::vector<rules::NearSegment> near;
    const SegmentSet& segs = state_.segments();
    for (int point : segmentPointsOf(zone, true))
      for (int s : state_.subsAt(point))
      {
        subs.push_back(s);
        near.push_back({ segs.points[segs.subs[s][0]], segs.points[segs.subs[s][1]], !refused_[s] && state_.splittable(s) });
      }
    size_t k = 0;
    switch (rules::refinementPointT21T31(toVec(p), near, &k))
    {
      case rules::RefinementPointFate::Insert:
        return CGAL::NO_CONFLICT;
      case rules::RefinementPointFate::Drop:
        ++state_.counters().dropped;
        return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
      case rules::RefinementPointFate::SplitSegment:
        break;
    }
    ++state_.counters().vetoes;
    mustSplit_[subs[k]] = 1;
    enqueue(subs[k]);
    return CGAL::CONFLICT_BUT_ELEMENT_CAN_BE_RECONSIDERED;
  }

  /// The segment points among the vertices of the zone's cells, in the order met (repeated);
  /// `pointsOnly`: only vertices of dimension 0 or 1.
  std::vector<int> segmentPointsOf(const Zone& zone, bool pointsOnly) const
  {
    std::vector<int> points;
    for (const Cell_handle& c : zone.cells)
      for (int k = 0; k < 4; ++k)
      {
        const Vertex_handle v = c->vertex(k);
        const int dim = pointsOnly ? v->in_dimension() : 0;
        if (dim != 0 && dim != 1)
          continue;
        const int p = state_.pointOf(v);
        if (p >= 0)
          points.push_back(p);
      }
    return points;
  }

  /// An insertion changes cells only in its conflict zone and its new star, whose vertices are
  /// the zone's: only sub-segments with an end there can gain or lose an incident cell of the
  /// complex. They are looked at again by the next queueMissingFromComplex.
  void markChangedAround(const Zone& zone)
  {
    for (int p : segmentPointsOf(zone, true))
      for (int s : state_.subsAt(p))
        markChanged(s);
  }

  void markChanged(int s)
  {
    if (!changed_[s])
    {
      changed_[s] = 1;
      changedList_.push_back(s);
    }
  }

  void enqueue(int s)
  {
    if (!inQueue_[s])
    {
      inQueue_[s] = 1;
      queue_.push_back(s);
    }
  }

  /// T1.2: splits sub-segment s at parameter t (the rule's midpoint) and keeps the shells of its
  /// small-angle cluster (the same distance from the apex on the cluster's other segments, see SegmentSet).
  template <class V>
  bool split(int s, double t, V& visitor)
  {
    const auto mirrors = state_.mirrorSplits(s, t);
    if (!insertSplit(s, t, visitor))
      return false;
    for (const auto& [x, t] : mirrors)
      state_.counters().mirrored += insertSplit(x, t, visitor);
    return true;
  }

  /// Inserts the point at parameter t of sub-segment s, as Mesh_3's levels insert their points:
  /// conflict zone, the upper levels told before and after.
  template <class V>
  bool insertSplit(int s, double t, V& visitor)
  {
    const Weighted_point wp(toPoint(state_.pointOn(s, t)));
    Zone zone;
    zone.cell = tr_.locate(wp, zone.locate_type, zone.i, zone.j, state_.vertexOf(state_.end(s, 0))->cell());
    if (zone.locate_type == Tr::VERTEX)
      return false; // the midpoint is already a vertex: nothing to insert
    tr_.find_conflicts(wp, zone.cell, std::back_inserter(zone.boundary_facets), std::back_inserter(zone.cells),
      std::back_inserter(zone.internal_facets));
    if (zone.cells.empty() || zone.boundary_facets.empty())
      return false;
    // segment points around the hole: the new point may encroach their sub-segments
    const std::vector<int> near = segmentPointsOf(zone, false);
    visitor.before(wp, zone);
    const auto& f = zone.boundary_facets.front();
    Vertex_handle v = tr_.insert_in_hole(wp, zone.cells.begin(), zone.cells.end(), f.first, f.second);
    c3t3_.set_dimension(v, 1);
    c3t3_.set_index(v, curveIndex_);
    const int n = state_.recordSplit(s, t, v);
    inQueue_.resize(state_.size(), 0);
    refused_.resize(state_.size(), 0);
    mustSplit_.resize(state_.size(), 0);
    changed_.resize(state_.size(), 0);
    refused_[s] = 0; // a shorter piece now: judged again
    markChanged(s);
    markChanged(n);
    visitor.after(v);
    enqueue(s);
    enqueue(n);
    for (int p : near)
      for (int x : state_.subsAt(p))
      {
        enqueue(x);
        markChanged(x);
      }
    return true;
  }

  C3t3& c3t3_;
  Tr& tr_;
  State& state_;
  Index curveIndex_;
  std::deque<int> queue_;
  std::vector<char> inQueue_;
  std::vector<char> refused_;
  std::vector<char> mustSplit_; ///< queued by a refused refinement point
  std::vector<char> changed_;   ///< cells around it may have changed since the last missing-edge scan
  std::vector<int> changedList_;
};
}
}
