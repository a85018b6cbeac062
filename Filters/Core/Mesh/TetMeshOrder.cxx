// SPDX-License-Identifier: GPL-3.0-or-later
#include "TetMeshOrder.h"

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace omesh
{
void orderTetsByPoints(TetMesh& mesh)
{
  const std::size_t n = mesh.tets.size();
  auto smallest = [&mesh](std::size_t t) {
    const auto& k = mesh.tets[t];
    return static_cast<std::size_t>(std::min({ k[0], k[1], k[2], k[3] }));
  };
  std::vector<std::size_t> first(mesh.points.size() + 1, 0);
  for (std::size_t t = 0; t < n; ++t)
    ++first[smallest(t) + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  // a copy, not a permutation in place: following the permutation's cycles jumps across the whole
  // array at every step and costs four times as long at a million tetrahedra
  std::vector<std::array<int, 4>> tets(n);
  std::vector<int> materials(mesh.tetMaterial.size() == n ? n : 0);
  for (std::size_t t = 0; t < n; ++t)
  {
    const std::size_t to = first[smallest(t)]++;
    tets[to] = mesh.tets[t];
    if (!materials.empty())
      materials[to] = mesh.tetMaterial[t];
  }
  mesh.tets = std::move(tets);
  if (!materials.empty())
    mesh.tetMaterial = std::move(materials);
}
}
