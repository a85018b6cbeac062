// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstddef>

namespace omesh
{
/// Counts of values per bin between N edges (as numpy.histogram: [e0, e1), ..., the last bin closed;
/// values outside every bin, NaN too, are not counted).
template <std::size_t N>
struct BinCounts
{
  std::array<std::size_t, N - 1> counts{};

  void add(const std::array<double, N>& edges, double value)
  {
    // the edges at or below the value, counted without a branch (a loop that stops at the first
    // edge above it mispredicts on every tetrahedron)
    std::size_t below = 0;
    for (std::size_t e = 0; e < N; ++e)
      below += edges[e] <= value;
    below -= below == N && value == edges[N - 1]; // the last bin holds its right edge
    if (below > 0 && below < N)
      ++counts[below - 1];
  }
  void merge(const BinCounts& o)
  {
    for (std::size_t b = 0; b + 1 < N; ++b)
      counts[b] += o.counts[b];
  }
};
}
