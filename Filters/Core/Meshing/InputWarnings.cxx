// SPDX-License-Identifier: GPL-3.0-or-later
#include "InputWarnings.h"

#include "HierarchicalOracle.h"
#include "SurfaceDeviation.h"
#include "SurfaceDomain.h"
#include "TetMesh.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace omesh
{
std::vector<std::string> hiddenDomainWarnings(const HierarchicalOracle& oracle)
{
  std::vector<std::string> warnings;
  const auto& domains = oracle.domains();
  constexpr int N = 20;
  for (size_t i = 1; i < domains.size(); ++i)
  {
    const Domain& d = *domains[i];
    if (!d.bounded())
      continue;
    const BoundingBox box = d.bounds();
    const Vec3 size = box.size();
    size_t inside = 0, claimed = 0;
    std::set<size_t> by;
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b)
        for (int c = 0; c < N; ++c)
        {
          const Vec3 p{ box.min.x + (a + 0.5) / N * size.x, box.min.y + (b + 0.5) / N * size.y,
            box.min.z + (c + 0.5) / N * size.z };
          if (d.material(p) == kOutside)
            continue;
          ++inside;
          for (size_t j = 0; j < i; ++j)
            if (domains[j]->material(p) != kOutside)
            {
              ++claimed;
              by.insert(j);
              break;
            }
        }
    if (inside < 8 || claimed < inside) // too thin to judge, or visible
      continue;
    std::string names;
    for (size_t j : by)
      names += (names.empty() ? "" : ", ") + domains[j]->name();
    warnings.push_back(d.name() + " is hidden: all " +
      std::to_string(inside) + " points sampled inside it belong to higher-priority domain(s) " + names +
      (d.isCut() ? "; the cut has no effect" : "; its material will not appear in the mesh"));
  }
  return warnings;
}

std::vector<std::string> inputPlacementWarnings(const HierarchicalOracle& oracle)
{
  std::vector<std::string> warnings;
  std::vector<const Domain*> placed;
  for (const auto& d : oracle.domains())
    if (!d->isCut() && d->bounded() && !d->bounds().empty())
      placed.push_back(d.get());
  auto largest = [](const Vec3& v) { return std::max({ v.x, v.y, v.z }); };
  // share of the smaller box inside the other, per axis (a flat box counts as overlapping on its
  // flat axis when it lies within the other's range); `across` leaves out the axes where the
  // boxes only touch (a face, an edge shared), for parts meeting on purpose
  auto overlapShare = [](const BoundingBox& a, const BoundingBox& b, bool across)
  {
    double share = 1.0;
    const double amin[3] = { a.min.x, a.min.y, a.min.z }, amax[3] = { a.max.x, a.max.y, a.max.z };
    const double bmin[3] = { b.min.x, b.min.y, b.min.z }, bmax[3] = { b.max.x, b.max.y, b.max.z };
    for (int k = 0; k < 3; ++k)
    {
      const double overlap = std::min(amax[k], bmax[k]) - std::max(amin[k], bmin[k]);
      const double smaller = std::min(amax[k] - amin[k], bmax[k] - bmin[k]);
      if (across && overlap == 0.0)
        continue;
      share *= overlap < 0 ? 0.0 : (smaller > 0 ? std::min(1.0, overlap / smaller) : 1.0);
    }
    return share;
  };
  const size_t n = placed.size();
  std::vector<double> share(n * n, 0.0);
  // inputs whose boxes overlap (enough) are one group: two implant parts that only touch each
  // other but both sit in the bone are placed alike; a group apart from the rest is not
  std::vector<size_t> group(n);
  for (size_t i = 0; i < n; ++i)
    group[i] = i;
  auto root = [&group](size_t i)
  {
    while (group[i] != i)
      i = group[i] = group[group[i]];
    return i;
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
    {
      const BoundingBox a = placed[i]->bounds(), b = placed[j]->bounds();
      const double ea = largest(a.size()), eb = largest(b.size());
      const double ratio = std::max(ea, eb) / std::max(std::min(ea, eb), 1e-300);
      if (ratio >= kScaleWarningRatio)
      {
        std::ostringstream o;
        o << "inputs: " << placed[i]->name() << " (largest extent " << ea << ") and " << placed[j]->name()
          << " (largest extent " << eb << ") differ in size by " << std::llround(ratio)
          << "x: different units (metres and millimetres)?";
        warnings.push_back(o.str());
        group[root(j)] = root(i); // warned once: not again as apart
        continue;
      }
      share[i * n + j] = share[j * n + i] = overlapShare(a, b, false);
      if (overlapShare(a, b, true) >= kOverlapWarningShare)
        group[root(j)] = root(i);
    }
  // each group but the one of the highest-priority input, named against all the others
  for (size_t g = 0; g < n; ++g)
  {
    if (root(g) != g || root(0) == g)
      continue;
    std::string members, others;
    double most = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
      std::string& list = root(i) == g ? members : others;
      list += (list.empty() ? "" : ", ") + placed[i]->name();
      if (root(i) == g)
        for (size_t j = 0; j < n; ++j)
          if (root(j) != g)
            most = std::max(most, share[i * n + j]);
    }
    std::ostringstream o;
    o << "inputs: the bounding boxes of " << members
      << (most == 0.0 ? " do not overlap" : " barely overlap (" + std::to_string(100.0 * most).substr(0, 4) +
               "% of the smaller)")
      << " those of " << others << ": placed in different frames (LPS and RAS, a missing transform)?";
    warnings.push_back(o.str());
  }
  return warnings;
}

std::vector<std::string> vanishedMaterialWarnings(
  const HierarchicalOracle& oracle, const std::map<int, std::size_t>& tetsPerMaterial)
{
  std::vector<std::string> warnings;
  std::set<int> reported;
  for (const auto& d : oracle.domains())
  {
    if (d->isCut())
      continue;
    const bool labels = std::string(d->kind()) == "LabelMap";
    for (int m : d->materials())
    {
      auto it = tetsPerMaterial.find(m);
      if ((it != tetsPerMaterial.end() && it->second > 0) || !reported.insert(m).second)
        continue;
      warnings.push_back(labels
          ? "label " + std::to_string(m) + " of " + d->name() +
            " was dropped: no tetrahedron has it (a label of a few voxels, below the mesh size, or hidden by higher-priority domains?)"
          : "material " + std::to_string(m) + " of " + d->name() +
            " has no tetrahedron although its input is not empty (smaller than the mesh size, or hidden by higher-priority domains?)");
    }
  }
  return warnings;
}

std::vector<std::string> surfaceWarnings(const HierarchicalOracle& oracle, const TetMesh* mesh)
{
  std::vector<std::string> warnings;
  for (const auto& d : oracle.domains())
    if (const auto* surface = dynamic_cast<const SurfaceDomain*>(d.get()))
      for (const std::string& w : surface->warnings())
      {
        const bool measured = mesh && !mesh->tets.empty() && surface->usesWindingNumber() && !surface->isCut();
        warnings.push_back(
          measured ? w + "; " + surfaceDeviation(*mesh, surface->materialId(), *surface).describe() : w);
      }
  return warnings;
}

std::vector<std::string> domainWarnings(const HierarchicalOracle& oracle)
{
  std::vector<std::string> warnings = surfaceWarnings(oracle);
  for (std::string& w : hiddenDomainWarnings(oracle))
    warnings.push_back(std::move(w));
  return warnings;
}
}
