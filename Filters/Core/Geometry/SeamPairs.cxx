// SPDX-License-Identifier: GPL-3.0-or-later
#include "SeamPairs.h"

#include <cmath>
#include <cstdint>
#include <limits>
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

/// Edges of length in [2^c, 2^(c+1)) are hashed by midpoint on a grid of kSeamGap 2^(c+1): a
/// partner's midpoint, at most its gap away, lies in the cell or a face, edge or corner neighbour.
double cellSize(int lengthClass) { return std::ldexp(1.0, lengthClass + 1) * kSeamGap; }

int lengthClassOf(double length) { return std::ilogb(length); }

CellKey keyOf(const Vec3& m, int lengthClass)
{
  const double h = cellSize(lengthClass);
  return { lengthClass, static_cast<int64_t>(std::floor(m.x / h)), static_cast<int64_t>(std::floor(m.y / h)),
    static_cast<int64_t>(std::floor(m.z / h)) };
}
}

std::vector<SeamPair> pairSeams(
  const std::vector<Vec3>& points, const std::vector<std::array<int, 2>>& edges, bool oppositeOnly, bool unambiguous)
{
  const int count = static_cast<int>(edges.size());
  std::unordered_multimap<CellKey, int, CellHash> byCell;
  byCell.reserve(edges.size());
  std::vector<int> lengthClass(edges.size(), 0);
  for (int e = 0; e < count; ++e)
  {
    const Vec3 &a = points[edges[e][0]], &b = points[edges[e][1]];
    const double length = norm(b - a);
    if (!(length > 0.0) || !std::isfinite(length))
    {
      lengthClass[e] = INT32_MIN; // a zero-length edge pairs with nothing
      continue;
    }
    lengthClass[e] = lengthClassOf(length);
    byCell.emplace(keyOf(0.5 * (a + b), lengthClass[e]), e);
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
    for (int c = lengthClass[e] - 1; c <= lengthClass[e] + 1; ++c)
    {
      const CellKey centre = keyOf(m, c);
      for (int n = 0; n < 27; ++n)
      {
        const CellKey key{ c, centre.x + n % 3 - 1, centre.y + (n / 3) % 3 - 1, centre.z + n / 9 - 1 };
        const auto range = byCell.equal_range(key);
        for (auto it = range.first; it != range.second; ++it)
        {
          const int o = it->second;
          if (used[o])
            continue;
          const Vec3 &c0 = points[edges[o][0]], &c1 = points[edges[o][1]];
          const double limit = kSeamGap * std::min(length, norm(c1 - c0));
          const double reversedGap = std::max(norm(c1 - a), norm(c0 - b));
          const double sameGap = oppositeOnly ? std::numeric_limits<double>::infinity() : std::max(norm(c0 - a), norm(c1 - b));
          const double gap = std::min(reversedGap, sameGap);
          if (!(gap <= limit))
            continue;
          if (best.second < 0 || gap < best.gap)
          {
            runnerUp = best.second < 0 ? runnerUp : best.gap;
            best = { e, o, gap, reversedGap <= sameGap };
          }
          else
            runnerUp = std::min(runnerUp, gap);
        }
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
