// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). The constrained segments during meshing, in one place:
// the sub-segments and their splits (SegmentSet), the mesh vertex of each segment point, whether a
// sub-segment is an edge of the triangulation or of the complex, and the encroachment queries
// (section 2.1, rules::encroaches). The segment level (SegmentRefinementLevel.h) refines with it;
// the mesher asks it after optimisation.
#pragma once

#include "OracleMeshDomain.h"
#include "SegmentConformation.h"
#include "SegmentRules.h"

#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace omesh
{
namespace cgal
{
template <class C3t3>
class SegmentState
{
public:
  using Tr = typename C3t3::Triangulation;
  using Vertex_handle = typename Tr::Vertex_handle;
  using Cell_handle = typename Tr::Cell_handle;
  using Bare_point = typename Tr::Bare_point;

  /// What the segment level did, for the mesher's statistics.
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
    size_t missingChecks = 0;      ///< sub-segments looked at by the missing-edge search
  };

  SegmentState(C3t3& c3t3, SegmentSet segments)
    : c3t3_(c3t3)
    , tr_(c3t3.triangulation())
    , segs_(std::move(segments))
  {
  }
  SegmentState(const SegmentState&) = delete;
  SegmentState& operator=(const SegmentState&) = delete;

  /// Rule T1 done, the segment points enter the triangulation first: input points as corners
  /// (dimension 0), the others on the curve (dimension 1); CGAL's perturber moves neither.
  /// Sub-segments are never split below 1/64 of the shortest conformed one: a surface or a
  /// segment meeting a segment at a tiny angle would otherwise split it without end.
  /// Calls `check` (which may throw: the mesher's deadline) before every 16th point.
  template <class Domain>
  void insertPoints(const Domain& domain, const std::function<void()>& check = {})
  {
    vertexOf_.resize(segs_.points.size());
    for (size_t p = 0; p < segs_.points.size(); ++p)
    {
      if (check && p % 16 == 0)
        check();
      Vertex_handle v = tr_.insert(typename Tr::Point(toPoint(segs_.points[p])));
      c3t3_.set_dimension(v, segs_.corner[p] ? 0 : 1);
      c3t3_.set_index(v, segs_.corner[p] ? domain.index_from_corner_index(static_cast<int>(p) + 1)
                                         : domain.index_from_curve_index(1));
      vertexOf_[p] = v;
    }
    minLength_ = std::numeric_limits<double>::infinity();
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      minLength_ = std::min(minLength_, segs_.length(s) / 64.0);
  }

  /// Rebuilds the lookups from mesh vertex to segment point and from point to its sub-segments
  /// (in sub-segment order: the segment level's decisions depend on that order).
  void reindex()
  {
    pointOf_.clear();
    for (size_t p = 0; p < vertexOf_.size(); ++p)
      if (vertexOf_[p] != Vertex_handle())
        pointOf_[vertexOf_[p]] = static_cast<int>(p);
    subsAt_.assign(segs_.points.size(), {});
    for (size_t s = 0; s < segs_.subs.size(); ++s)
    {
      subsAt_[segs_.subs[s][0]].push_back(static_cast<int>(s));
      subsAt_[segs_.subs[s][1]].push_back(static_cast<int>(s));
    }
  }

  const SegmentSet& segments() const { return segs_; }
  size_t size() const { return segs_.subs.size(); }
  int end(int s, int k) const { return segs_.subs[s][k]; }
  Vertex_handle vertexOf(int p) const { return vertexOf_[p]; }
  /// The segment point of mesh vertex v, or -1.
  int pointOf(const Vertex_handle& v) const
  {
    const auto it = pointOf_.find(v);
    return it == pointOf_.end() ? -1 : it->second;
  }
  const std::vector<int>& subsAt(int p) const { return subsAt_[p]; }
  Counters& counters() { return count_; }
  const Counters& counters() const { return count_; }

  /// The floor of rule T1.2 during refinement: halves stay strictly longer than the smallest
  /// piece (rules::splitEncroachedT12 splits at half-length >= floor, so the next double up).
  double splitFloor() const { return std::nextafter(minLength_, std::numeric_limits<double>::infinity()); }

  /// T1.2 would split sub-segment s if it were encroached (longer than twice the smallest piece).
  bool splittable(int s) const { return splitT12(s, true).has_value(); }

  /// Rule T1.2 on sub-segment s, `bad` when encroached or asked for by T2.1/T3.1: the split
  /// parameter, or nothing. The refinement has no length bound (conformSegments applied it).
  std::optional<double> splitT12(int s, bool bad) const
  {
    return rules::splitEncroachedT12(segs_.points[segs_.subs[s][0]], segs_.points[segs_.subs[s][1]], bad, 0.0, splitFloor());
  }

  /// Section 2.1 on sub-segment s.
  bool encroachedBy(int s, const Bare_point& p) const
  {
    return rules::encroaches(segs_.points[segs_.subs[s][0]], segs_.points[segs_.subs[s][1]], toVec(p));
  }

  /// A vertex other than its ends in the diametral ball, or a null handle: the nearest vertex to
  /// the midpoint is such a vertex if any is (the ends lie on the ball's boundary).
  Vertex_handle encroacher(int s) const
  {
    const int a = segs_.subs[s][0], b = segs_.subs[s][1];
    const Vec3 mid = 0.5 * (segs_.points[a] + segs_.points[b]);
    const Vertex_handle v = tr_.nearest_power_vertex(toPoint(mid), vertexOf_[a]->cell());
    if (v == vertexOf_[a] || v == vertexOf_[b] || tr_.is_infinite(v) || !encroachedBy(s, tr_.point(v).point()))
      return Vertex_handle();
    return v;
  }
  bool encroached(int s) const { return encroacher(s) != Vertex_handle(); }

  /// Sub-segment s is an edge of the triangulation (both its points have a vertex).
  bool isEdge(int s) const
  {
    const Vertex_handle a = vertexOf_[segs_.subs[s][0]], b = vertexOf_[segs_.subs[s][1]];
    Cell_handle c;
    int i, j;
    return a != Vertex_handle() && b != Vertex_handle() && tr_.is_edge(a, b, c, i, j);
  }

  /// Number of sub-segments that are no edge of the triangulation.
  size_t countNotEdges() const
  {
    size_t n = 0;
    for (size_t s = 0; s < segs_.subs.size(); ++s)
      n += !isEdge(static_cast<int>(s));
    return n;
  }

  /// Sub-segment s is an edge with an incident cell in the complex. (Not the cells the output
  /// takes by their centroid, subdomainByCentroid: counted here they spared splits on generated
  /// bone/implant cases whose pieces then came out held by slivers of 0.05 degrees, or missing
  /// after optimisation.)
  bool inComplex(int s) const
  {
    Cell_handle c;
    int i, j;
    return tr_.is_edge(vertexOf_[segs_.subs[s][0]], vertexOf_[segs_.subs[s][1]], c, i, j) && edgeInComplex(c, i, j);
  }

  /// The finite cells around the sub-segments that are edges no cell of the complex holds, each
  /// once, in the order of the sub-segments and around them (deterministic).
  std::vector<Cell_handle> cellsAroundEdgesOutsideComplex() const
  {
    std::vector<Cell_handle> cells;
    std::unordered_set<Cell_handle> seen;
    for (size_t s = 0; s < segs_.subs.size(); ++s)
    {
      Cell_handle c;
      int i, j;
      if (!tr_.is_edge(vertexOf_[segs_.subs[s][0]], vertexOf_[segs_.subs[s][1]], c, i, j) || edgeInComplex(c, i, j))
        continue;
      auto first = tr_.incident_cells(c, i, j), cell = first;
      do
      {
        const Cell_handle h = cell;
        if (!tr_.is_infinite(h) && seen.insert(h).second)
          cells.push_back(h);
      } while (++cell != first);
    }
    return cells;
  }

  /// Sub-segment s is splittable, no cell of the complex holds it, and `wanted` it.
  template <class Wanted>
  bool missingFromComplex(int s, const Wanted& wanted) const
  {
    const int a = segs_.subs[s][0], b = segs_.subs[s][1];
    return splittable(s) && !inComplex(s) && wanted(segs_.points[a], segs_.points[b]);
  }

  /// Finds the segment points' vertices anew (the exuder re-creates the vertices it pumps); a
  /// point that is no vertex any more gets a null handle.
  void locateVertices()
  {
    vertexOf_.assign(segs_.points.size(), Vertex_handle());
    Cell_handle hint;
    for (size_t p = 0; p < segs_.points.size(); ++p)
    {
      typename Tr::Locate_type lt;
      int i, j;
      hint = tr_.locate(typename Tr::Point(toPoint(segs_.points[p])), lt, i, j, hint);
      if (lt == Tr::VERTEX)
        vertexOf_[p] = hint->vertex(i);
    }
  }

  /// After the perturber: a vertex off the segments that it moved into the diametral ball of a
  /// sub-segment too short to split breaks that sub-segment for good (seen at apexes of 1 degree).
  /// Removes such vertices; a refinement pass then fills their holes, refusing points inside the
  /// balls. Returns how many were removed (the complex needs a rescan then).
  /// `around` (if given) receives the vertices next to the removed ones: where the removals made
  /// new cells.
  size_t removeEncroachersOfShortSubSegments(std::set<Vertex_handle>* around = nullptr)
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
        if (around)
        {
          tr_.finite_adjacent_vertices(v, std::inserter(*around, around->end()));
          around->erase(v);
        }
        tr_.remove(v);
        ++removed;
      }
    }
    count_.removedEncroachers += removed;
    return removed;
  }

  /// The point at parameter t of sub-segment s, exactly as SegmentSet::split stores it (the
  /// exuder check finds segment points by exact location).
  Vec3 pointOn(int s, double t) const { return lerp(segs_.points[segs_.subs[s][0]], segs_.points[segs_.subs[s][1]], t); }

  /// The splits that keep the shells of s's small-angle cluster (SegmentSet::mirrorSplits).
  std::vector<std::pair<int, double>> mirrorSplits(int s, double t) const
  {
    return segs_.mirrorSplits(static_cast<size_t>(s), t);
  }

  /// Records the split of sub-segment s at t whose point is now vertex v: s keeps its first end,
  /// the returned new sub-segment runs from v's point to s's former second end.
  int recordSplit(int s, double t, const Vertex_handle& v)
  {
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
    return n;
  }

private:
  /// A cell of the complex holds edge (i, j) of cell c.
  bool edgeInComplex(const Cell_handle& c, int i, int j) const
  {
    auto first = tr_.incident_cells(c, i, j), cell = first;
    do
    {
      if (c3t3_.is_in_complex(cell))
        return true;
    } while (++cell != first);
    return false;
  }

  C3t3& c3t3_;
  Tr& tr_;
  SegmentSet segs_;
  std::vector<Vertex_handle> vertexOf_;
  std::unordered_map<Vertex_handle, int> pointOf_;
  std::vector<std::vector<int>> subsAt_;
  double minLength_ = 0.0;
  Counters count_;
};
}
}
