// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstddef>
#include <utility>

namespace omesh
{
/// The tetrahedra the quality report names (report.py's WORST_SHOWN).
constexpr std::size_t kWorstTetsShown = 5;

/// The kWorstTetsShown tetrahedra of smallest key, worst first; of equal keys the lower index first
/// (as a stable sort of all keys); NaN keys never among them.
struct WorstTets
{
  std::array<std::pair<double, std::size_t>, kWorstTetsShown> items{};
  std::size_t count = 0;

  void add(double key, std::size_t t)
  {
    if (!(key == key) || (count == kWorstTetsShown && !worse({ key, t }, items[count - 1])))
      return;
    std::size_t at = count < kWorstTetsShown ? count++ : count - 1;
    for (; at > 0 && worse({ key, t }, items[at - 1]); --at)
      items[at] = items[at - 1];
    items[at] = { key, t };
  }
  void merge(const WorstTets& o)
  {
    for (std::size_t i = 0; i < o.count; ++i)
      add(o.items[i].first, o.items[i].second);
  }

private:
  static bool worse(const std::pair<double, std::size_t>& a, const std::pair<double, std::size_t>& b)
  {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  }
};
}
