// SPDX-License-Identifier: GPL-3.0-or-later
// The paper's rules on constrained segments (section 2.2, rule set T), each a function of the
// geometry alone: the segment conformation (SegmentConformation.cxx) and the mesher's segment
// level (SegmentRefinementLevel.h) decide with these and only carry the decisions out.
#pragma once

#include "Vec3.h"

#include <optional>
#include <vector>

namespace omesh
{
namespace rules
{
/// Section 2.1: p encroaches the segment ab when it lies in its open diametral ball,
/// ||p - m|| < ||a - m|| with m the midpoint (a relative 1e-12 keeps points on the sphere out).
/// If no point encroaches ab, ab is an edge of the Delaunay triangulation (a Gabriel edge).
bool encroaches(const Vec3& a, const Vec3& b, const Vec3& p);

/// T1.1: a segment of length `length` at a star vertex p_i is cut at distance `cut` (l_min,i / 3)
/// from p_i when it is longer. Returns the cut point's parameter measured from p_i (cut / length),
/// or nothing when the segment is not longer than the cut (within a relative 1e-9).
std::optional<double> trimAtStarVertexT11(double length, double cut);

/// T1.2: a segment that is bad (encroached, or longer than the edge size `maxLength` when > 0) is
/// split at its midpoint; returns the split parameter (0.5) or nothing. An encroached segment whose
/// half-length is below `floor` is not split: its halves would fall below the smallest piece the
/// refinement allows (a point almost on the segment would draw splits towards it without end).
std::optional<double> splitEncroachedT12(const Vec3& a, const Vec3& b, bool encroached, double maxLength, double floor);

/// What happens to a refinement point of the facet level (T2) or the cell level (T3).
enum class RefinementPointFate
{
  Insert,          ///< no segment's diametral ball holds it: T2.2 / T3.2-T3.4 go on as without segments
  SplitSegment,    ///< T2.1 / T3.1: not inserted; the segment whose ball holds it is split instead
  Drop             ///< that segment is too short to split: the point is given up
};

/// A sub-segment near a refinement point, as T2.1 and T3.1 see it.
struct NearSegment
{
  Vec3 a, b;
  bool splittable = true; ///< longer than twice the refinement's smallest piece, and not refused
};

/// T2.1 (facet points, c in a segment diameter ball B(c', r'): insert c') and T3.1 (cell points,
/// the same with c''): the first of `near` whose diametral ball holds p decides; `which` receives
/// its index. Splitting it inserts its midpoint c', the centre of that ball.
RefinementPointFate refinementPointT21T31(const Vec3& p, const std::vector<NearSegment>& near, size_t* which);
}
}
