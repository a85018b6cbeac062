// SPDX-License-Identifier: GPL-3.0-or-later
// Disjoint sets over 0..n-1 (connected pieces of feature lines, small-angle clusters).
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace omesh
{
/// Union-find with path halving; join(a, b) puts a's set under b's root.
struct UnionFind
{
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), std::size_t{ 0 });
  }
  std::size_t find(std::size_t x)
  {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};
}
