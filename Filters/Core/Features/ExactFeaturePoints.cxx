// SPDX-License-Identifier: GPL-3.0-or-later
#include "ExactFeaturePoints.h"

#include <algorithm>

namespace omesh
{
namespace
{
ExactCoordinates key(const Vec3& p) { return exactCoordinates(p.x, p.y, p.z); }
}

ExactFeaturePoints::ExactFeaturePoints(const FeatureSegments& f, const std::vector<std::array<int, 4>>& materials,
  const std::function<double(const std::vector<int>&)>& tolerance)
{
  for (std::size_t s = 0; s < f.segments.size() && s < materials.size(); ++s)
  {
    std::vector<int> tags;
    for (int m : materials[s])
      if (m != -2)
        tags.push_back(m);
    if (tags.empty())
      continue;
    std::sort(tags.begin(), tags.end());
    const double t = tolerance(tags);
    for (int end : f.segments[s])
    {
      auto [it, added] = points_.try_emplace(key(f.points[end]), ExactPoint{ {}, t });
      ExactPoint& p = it->second;
      std::vector<int> all;
      std::set_union(p.materials.begin(), p.materials.end(), tags.begin(), tags.end(), std::back_inserter(all));
      p.materials = std::move(all);
      if (!added)
        p.tolerance = std::min(p.tolerance, t);
    }
  }
}

const ExactPoint* ExactFeaturePoints::find(const Vec3& p) const
{
  const auto it = points_.find(key(p));
  return it == points_.end() ? nullptr : &it->second;
}

bool ExactFeaturePoints::onInterfacesOf(const Vec3& from, const Vec3& to) const
{
  const ExactPoint* a = find(from);
  const ExactPoint* b = find(to);
  return a && b && std::includes(b->materials.begin(), b->materials.end(), a->materials.begin(), a->materials.end());
}

}
