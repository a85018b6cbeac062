// SPDX-License-Identifier: GPL-3.0-or-later
#include "SeamPairs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <unordered_map>

namespace omesh
{
namespace
{
/// Matching ends lie at most this fraction of the shorter edge apart.
constexpr double kSeamGap = 1.0 / 3.0;
/// An unambiguous pair: every other candidate's gap is this many times larger.
constexpr double kAmbiguity = 4.0;

/// A cell of one length class's grid: partners differ in length by at most twice their gap, so by
/// a factor below 5/3, and lie in the same or a neighbouring class.
struct CellKey
{
  int lengthClass;
  int64_t x, y, z;
  bool operator==(const CellKey& o) const { return lengthClass == o.lengthClass && x == o.x && y == o.y && z == o.z; }
};

struct CellHash
{
  size_t operator()(const CellKey& k) const
  {
    uint64_t h = static_cast<uint64_t>(k.lengthClass) * 0x9E3779B97F4A7C15ull;
    for (int64_t v : { k.x, k.y, k.z })
      h = (h ^ static_cast<uint64_t>(v)) * 0x100000001B3ull + (h >> 29);
    return static_cast<size_t>(h);
  }
};

/// Edges of length in [2^c, 2^(c+1)) are hashed by midpoint on a grid of 2 kSeamGap 2^(c+1): a
/// partner's midpoint, at most its gap (half a cell) away, lies in one of the 2 x 2 x 2 cells
/// nearest to the point.
double cellSize(int lengthClass) { return std::ldexp(1.0, lengthClass + 1) * 2.0 * kSeamGap; }

int lengthClassOf(double length) { return std::ilogb(length); }

/// The cell index of coordinate v, clamped where an edge is tiny against its coordinates (the
/// distances still decide; the cast alone would overflow).
int64_t cellIndex(double v, double h)
{
  constexpr double kLimit = 4.0e18;
  return static_cast<int64_t>(std::clamp(std::floor(v / h), -kLimit, kLimit));
}

CellKey keyOf(const Vec3& m, int lengthClass)
{
  const double h = cellSize(lengthClass);
  return { lengthClass, cellIndex(m.x, h), cellIndex(m.y, h), cellIndex(m.z, h) };
}

/// The 2 x 2 x 2 cells of `lengthClass` nearest to m: its own and, per axis, the neighbour on the
/// side of the cell's nearer face.
std::array<CellKey, 8> nearestCells(const Vec3& m, int lengthClass)
{
  const double h = cellSize(lengthClass);
  const CellKey own = keyOf(m, lengthClass);
  int64_t side[3];
  for (int a = 0; a < 3; ++a)
    side[a] = m[a] / h - std::floor(m[a] / h) < 0.5 ? -1 : 1;
  std::array<CellKey, 8> cells;
  for (int n = 0; n < 8; ++n)
    cells[n] = { lengthClass, own.x + (n & 1) * side[0], own.y + ((n >> 1) & 1) * side[1], own.z + ((n >> 2) & 1) * side[2] };
  return cells;
}
}

std::vector<SeamPair> pairSeams(
  const std::vector<Vec3>& points, const std::vector<std::array<int, 2>>& edges, bool oppositeOnly, bool unambiguous)
{
  const int count = static_cast<int>(edges.size());
  // the edges sorted by cell, and per cell its range: one probe per cell, then contiguous reads
  std::vector<int> lengthClass(edges.size(), INT32_MIN); // a zero-length edge pairs with nothing
  std::vector<std::pair<CellKey, int>> sorted;
  sorted.reserve(edges.size());
  for (int e = 0; e < count; ++e)
  {
    const Vec3 &a = points[edges[e][0]], &b = points[edges[e][1]];
    const double length = norm(b - a);
    if (!(length > 0.0) || !std::isfinite(length))
      continue;
    lengthClass[e] = lengthClassOf(length);
    sorted.emplace_back(keyOf(0.5 * (a + b), lengthClass[e]), e);
  }
  auto before = [](const std::pair<CellKey, int>& x, const std::pair<CellKey, int>& y) {
    const CellKey &p = x.first, &q = y.first;
    return std::tie(p.lengthClass, p.x, p.y, p.z, x.second) < std::tie(q.lengthClass, q.x, q.y, q.z, y.second);
  };
  std::sort(sorted.begin(), sorted.end(), before);
  std::unordered_map<CellKey, std::pair<uint32_t, uint32_t>, CellHash> cells;
  cells.reserve(sorted.size());
  for (uint32_t i = 0; i < sorted.size();)
  {
    uint32_t j = i + 1;
    while (j < sorted.size() && sorted[j].first == sorted[i].first)
      ++j;
    cells.emplace(sorted[i].first, std::make_pair(i, j));
    i = j;
  }
  std::vector<char> used(edges.size(), 0);
  std::vector<SeamPair> pairs;
  for (int e = 0; e < count; ++e)
  {
    if (used[e] || lengthClass[e] == INT32_MIN)
      continue;
    used[e] = 1;
    const Vec3 &a = points[edges[e][0]], &b = points[edges[e][1]];
    const Vec3 m = 0.5 * (a + b);
    const double length = norm(b - a);
    SeamPair best;
    double runnerUp = std::numeric_limits<double>::infinity(); // the second smallest gap
    // a partner's length lies within a factor 1 + 2 kSeamGap of this one's
    const int lowest = lengthClassOf(length / (1.0 + 2.0 * kSeamGap)), highest = lengthClassOf(length * (1.0 + 2.0 * kSeamGap));
    for (int c = lowest; c <= highest; ++c)
      for (const CellKey& key : nearestCells(m, c))
      {
        const auto cell = cells.find(key);
        if (cell == cells.end())
          continue;
        for (uint32_t i = cell->second.first; i < cell->second.second; ++i)
        {
          const int o = sorted[i].second;
          if (used[o])
            continue;
          const Vec3 &c0 = points[edges[o][0]], &c1 = points[edges[o][1]];
          const double limit2 = kSeamGap * kSeamGap * std::min(length * length, dot(c1 - c0, c1 - c0));
          const double reversed2 = std::max(dot(c1 - a, c1 - a), dot(c0 - b, c0 - b));
          const double same2 = oppositeOnly ? std::numeric_limits<double>::infinity() : std::max(dot(c0 - a, c0 - a), dot(c1 - b, c1 - b));
          const double gap2 = std::min(reversed2, same2);
          if (!(gap2 <= limit2))
            continue;
          const double gap = std::sqrt(gap2);
          if (best.second < 0 || gap < best.gap)
          {
            runnerUp = best.second < 0 ? runnerUp : best.gap;
            best = { e, o, gap, reversed2 <= same2 };
          }
          else
            runnerUp = std::min(runnerUp, gap);
        }
      }
    if (best.second >= 0 && (!unambiguous || runnerUp > kAmbiguity * best.gap))
    {
      used[best.second] = 1;
      pairs.push_back(best);
    }
  }
  return pairs;
}
}
