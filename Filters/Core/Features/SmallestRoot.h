// SPDX-License-Identifier: GPL-3.0-or-later
// Disjoint sets whose root is their smallest member (UnionFind.h keeps whichever root joining
// gave): the feature-line search keys groups by it and keeps that member as the group's vertex.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace omesh::featurelines
{
/// Sets of 0..n-1 joined pairwise; a set's root is its smallest member.
class SmallestRoot
{
public:
  explicit SmallestRoot(size_t n)
    : parent_(n)
  {
    for (size_t v = 0; v < n; ++v)
      parent_[v] = static_cast<int>(v);
  }
  int root(int v)
  {
    while (parent_[v] != v)
      v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(int a, int b)
  {
    a = root(a), b = root(b);
    if (a != b)
      parent_[std::max(a, b)] = std::min(a, b);
  }

private:
  std::vector<int> parent_;
};
}
