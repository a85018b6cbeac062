// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureJunctions.h"

#include "FeatureCurveLengths.h"
#include "SmallestRoot.h"

#include <algorithm>
#include <map>

namespace omesh::featurelines
{
void trimArms(const FeatureCurveGraph& graph, std::vector<std::vector<int>>& chains)
{
  const std::vector<Vec3>& nodes = graph.nodes();
  for (auto& chain : chains)
    for (int end = 0; end < 2; ++end)
    {
      while (chain.size() > 2 && chain.front() >= graph.crossingCount() &&
        angleAt(nodes[chain[1]], nodes[chain[0]], nodes[chain[2]]) < 90.0)
        chain.erase(chain.begin() + 1);
      std::reverse(chain.begin(), chain.end());
    }
}

void collapseShortCurves(FeatureCurveGraph& graph, std::vector<std::vector<int>>& chains,
  const std::vector<Crossing>& crossings, const FeatureLineOptions& options)
{
  const int crossingCount = graph.crossingCount();
  const std::vector<Vec3>& nodes = graph.nodes();
  SmallestRoot same(nodes.size());
  std::vector<char> collapsed(chains.size(), 0);
  for (size_t c = 0; c < chains.size(); ++c)
  {
    const auto& chain = chains[c];
    if (chain.size() < 2 || chain.front() < crossingCount || chain.back() < crossingCount)
      continue;
    double length = 0.0;
    for (size_t k = 0; k + 1 < chain.size(); ++k)
      length += norm(nodes[chain[k + 1]] - nodes[chain[k]]);
    // two junctions joined directly have no crossing between them to tell the materials
    // (crossings holds crossings only): the global chord length
    const int tag = graph.tagOf(chain);
    const std::vector<int> materials = tag < crossingCount ? materialsOf(crossings[tag].regions) : std::vector<int>{};
    if (!(length < lengthFor(options, materials)))
      continue;
    collapsed[c] = 1;
    same.join(chain.front(), chain.back());
  }
  std::map<int, std::vector<int>> members;
  for (int v = crossingCount; v < static_cast<int>(nodes.size()); ++v)
    members[same.root(v)].push_back(v);
  for (const auto& [root, group] : members)
    if (group.size() > 1)
    {
      Vec3 mean;
      for (int v : group)
        mean = mean + (1.0 / group.size()) * nodes[v];
      graph.moveNode(root, mean);
    }
  std::vector<std::vector<int>> kept;
  for (size_t c = 0; c < chains.size(); ++c)
    if (!collapsed[c])
    {
      std::vector<int> chain = chains[c];
      chain.front() = same.root(chain.front());
      chain.back() = same.root(chain.back());
      kept.push_back(std::move(chain));
    }
  chains = std::move(kept);
}
}
