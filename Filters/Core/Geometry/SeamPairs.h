// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Vec3.h"

#include <array>
#include <vector>

namespace omesh
{
/// Two border edges that are the sides of one unwelded seam (indices into the edges given).
struct SeamPair
{
  int first = -1, second = -1;
  /// The larger distance between matching ends.
  double gap = 0.0;
  /// Whether the second runs the other way (its end matches the first's start).
  bool reversed = false;
};

/// The border edges that pair up as the two sides of an unwelded seam (an exporter's triangle soup,
/// a crack): the second edge's ends lie at most a third of the shorter edge's length from the first's.
/// With `oppositeOnly` the second must run the other way (b' near a, a' near b, as the seams of a
/// consistently oriented surface do); otherwise either way round. Each edge is in at most one pair,
/// with its closest partner; with `unambiguous` only where every other candidate is four times
/// farther (where seams are as wide as the edges are long, a partner may be the wrong one). Edges are hashed by length class and midpoint, so the search costs
/// the same per edge whatever the spread of lengths.
std::vector<SeamPair> pairSeams(
  const std::vector<Vec3>& points, const std::vector<std::array<int, 2>>& edges, bool oppositeOnly, bool unambiguous);
}
