// SPDX-License-Identifier: GPL-3.0-or-later
#include "TetMeshOrder.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace omesh
{
namespace
{
template <typename Renumber>
void orderTets(TetMesh& mesh, Renumber id)
{
  const std::size_t n = mesh.tets.size();
  auto corners = [&](std::size_t t) {
    const auto& k = mesh.tets[t];
    return std::array<int, 4>{ id(k[0]), id(k[1]), id(k[2]), id(k[3]) };
  };
  auto smallest = [](const std::array<int, 4>& k) { return static_cast<std::size_t>(std::min({ k[0], k[1], k[2], k[3] })); };
  std::vector<std::size_t> first(mesh.points.size() + 1, 0);
  for (std::size_t t = 0; t < n; ++t)
    ++first[smallest(corners(t)) + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  // a copy, not a permutation in place: following the permutation's cycles jumps across the whole
  // array at every step and costs four times as long at a million tetrahedra
  std::vector<std::array<int, 4>> tets(n);
  std::vector<int> materials(mesh.tetMaterial.size() == n ? n : 0);
  for (std::size_t t = 0; t < n; ++t)
  {
    const std::array<int, 4> k = corners(t);
    const std::size_t to = first[smallest(k)]++;
    tets[to] = k;
    if (!materials.empty())
      materials[to] = mesh.tetMaterial[t];
  }
  mesh.tets = std::move(tets);
  if (!materials.empty())
    mesh.tetMaterial = std::move(materials);
}
}

void orderTetsByPoints(TetMesh& mesh, const std::vector<int>* renumber)
{
  if (renumber)
    orderTets(mesh, [&ids = *renumber](int v) { return ids[static_cast<std::size_t>(v)]; });
  else
    orderTets(mesh, [](int v) { return v; });
}
}
