// SPDX-License-Identifier: GPL-3.0-or-later
#include "TetStars.h"

namespace omesh
{
std::size_t FaceKeyHash::operator()(const FaceKey& k) const
{
  std::uint64_t h = static_cast<std::uint64_t>(k.v[0]) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(k.v[1]) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(k.v[2]) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
  return static_cast<std::size_t>(h);
}

TetStars::TetStars(const TetMesh& mesh)
  : tets_(mesh.tets)
  , material_(mesh.tetMaterial)
  , alive_(mesh.tets.size(), 1)
  , stars_(mesh.points.size())
{
  for (std::size_t t = 0; t < tets_.size(); ++t)
    for (int v : tets_[t])
      stars_[static_cast<std::size_t>(v)].push_back(static_cast<int>(t));
}

int TetStars::add(const std::array<int, 4>& t, int material)
{
  const int id = static_cast<int>(tets_.size());
  tets_.push_back(t);
  material_.push_back(material);
  alive_.push_back(1);
  for (int v : t)
    stars_[static_cast<std::size_t>(v)].push_back(id);
  return id;
}

void TetStars::revive(int t)
{
  alive_[static_cast<std::size_t>(t)] = 1;
  for (int v : tets_[static_cast<std::size_t>(t)])
    stars_[static_cast<std::size_t>(v)].push_back(t);
}

void TetStars::remove(int t)
{
  alive_[static_cast<std::size_t>(t)] = 0;
  for (int v : tets_[static_cast<std::size_t>(t)])
  {
    auto& s = stars_[static_cast<std::size_t>(v)];
    s.erase(std::find(s.begin(), s.end(), t));
  }
}

std::vector<int> TetStars::around(int a, int b) const
{
  std::vector<int> out;
  for (int t : star(a))
  {
    const auto& q = tet(t);
    if (std::find(q.begin(), q.end(), b) != q.end())
      out.push_back(t);
  }
  return out;
}

int TetStars::beyond(int t, int a, int b, int c) const
{
  for (int u : star(a))
  {
    const auto& q = tet(u);
    if (u != t && std::find(q.begin(), q.end(), b) != q.end() && std::find(q.begin(), q.end(), c) != q.end())
      return u;
  }
  return -1;
}

void TetStars::compact(TetMesh& mesh) const
{
  mesh.tets.clear();
  mesh.tetMaterial.clear();
  for (std::size_t t = 0; t < tets_.size(); ++t)
    if (alive_[t])
    {
      mesh.tets.push_back(tets_[t]);
      mesh.tetMaterial.push_back(material_[t]);
    }
}
}
