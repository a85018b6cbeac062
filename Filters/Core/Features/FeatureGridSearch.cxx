// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureGridSearch.h"

#include "InputError.h"
#include "SmallestRoot.h"

#include <array>
#include <cmath>
#include <map>
#include <set>

namespace omesh::featurelines
{
void reportProgress(const FeatureLineOptions& options, double fraction)
{
  if (options.progress && !options.progress(fraction))
    throw FeatureSearchAborted();
}

FeatureGridSearch::FeatureGridSearch(
  const HierarchicalOracle& oracle, const FeatureLineOptions& options, std::vector<std::string>& warnings)
  : oracle_(oracle)
  , options_(options)
{
  const BoundingBox box = oracle.bounds(); // throws for an empty or unbounded oracle
  const double diagonal = norm(box.size());
  double h = options.spacing > 0 ? options.spacing
    : options.maxSegmentLength > 0 ? 0.5 * options.maxSegmentLength
                                   : diagonal / 64.0;
  h = std::min(h, diagonal / 4.0);
  if (!(h > 0) || !std::isfinite(h))
    throw InputError("feature lines: the search grid's spacing " + std::to_string(h) + " is not a positive number");
  // The origin is shifted by odd fractions of a step so that grid planes do not fall on the
  // round coordinates inputs like to have.
  const Vec3 shift{ 0.5 + 0.1234567, 0.5 + 0.2718282, 0.5 + 0.3141593 };
  auto gridSize = [&](double step) {
    std::array<int, 3> n;
    for (int i = 0; i < 3; ++i)
      n[i] = static_cast<int>(std::ceil(box.size()[i] / step + 2 * shift[i])) + 2;
    return n;
  };
  std::array<int, 3> n = gridSize(h);
  const double wanted = h;
  while (static_cast<double>(n[0]) * n[1] * n[2] > static_cast<double>(options.maximumGridPoints))
    n = gridSize(h *= 1.1);
  if (h > wanted)
    warnings.push_back("feature lines: the search grid's spacing was widened from " + std::to_string(wanted) + " to " +
      std::to_string(h) + " (at most " + std::to_string(options.maximumGridPoints) +
      " grid points): curves shorter or closer than that can be missed");
  found_.spacing = h_ = h;
  found_.diagonal = diagonal;
  origin_ = Vec3{ box.min.x - shift.x * h, box.min.y - shift.y * h, box.min.z - shift.z * h };
  nx_ = n[0], ny_ = n[1], nz_ = n[2];
  stride_[0] = 1, stride_[1] = nx_, stride_[2] = nx_ * ny_;
  found_.precision = 1e-10 * diagonal;
}

GridCrossings FeatureGridSearch::search()
{
  classifyGridPoints();
  findCrossings();
  refineLinks();
  mergeJunctionCubes();
  return std::move(found_);
}

void FeatureGridSearch::classifyGridPoints()
{
  region_.resize(static_cast<size_t>(nx_ * ny_ * nz_));
  for (std::int64_t k = 0; k < nz_; ++k)
  {
    for (std::int64_t j = 0; j < ny_; ++j)
      for (std::int64_t i = 0; i < nx_; ++i)
      {
        const std::int64_t id = index(i, j, k);
        region_[id] = oracle_.decide(pointAt(id));
      }
    reportProgress(options_, 0.4 * (k + 1) / nz_);
  }
}

void FeatureGridSearch::findCrossings()
{
  for (std::int64_t k = 0; k + 1 < nz_; ++k)
  {
    for (std::int64_t j = 0; j + 1 < ny_; ++j)
      for (std::int64_t i = 0; i + 1 < nx_; ++i)
        linkCube(index(i, j, k));
    reportProgress(options_, 0.4 + 0.5 * (k + 1) / nz_);
  }
  found_.gridFacesCrossed = found_.crossings.size();
}

void FeatureGridSearch::refineLinks()
{
  tolerance_ = options_.tolerance > 0 ? options_.tolerance
    : options_.maxSegmentLength > 0   ? 0.05 * options_.maxSegmentLength
                                      : 0.01 * h_;
  const FeatureCurveLocator locator(oracle_, found_.precision);
  std::vector<Link> refined;
  for (const Link& l : found_.links)
  {
    std::vector<int> path{ l.a };
    refine(locator, l.a, l.b, 8, path);
    path.push_back(l.b);
    for (size_t k = 0; k + 1 < path.size(); ++k)
      refined.push_back({ path[k], path[k + 1] });
  }
  found_.links = std::move(refined);
}

void FeatureGridSearch::mergeJunctionCubes()
{
  std::unordered_map<std::int64_t, int> cubeIndex;
  for (size_t c = 0; c < junctionCubes_.size(); ++c)
    cubeIndex.emplace(junctionCubes_[c].first, static_cast<int>(c));
  SmallestRoot touching(junctionCubes_.size());
  for (size_t c = 0; c < junctionCubes_.size(); ++c)
    for (int d = 0; d < 27; ++d)
    {
      const std::int64_t q = junctionCubes_[c].first + (d % 3 - 1) * stride_[0] + ((d / 3) % 3 - 1) * stride_[1] + (d / 9 - 1) * stride_[2];
      if (auto it = cubeIndex.find(q); it != cubeIndex.end())
        touching.join(static_cast<int>(c), it->second);
    }
  std::map<int, std::pair<std::vector<Vec3>, std::set<int>>> groups;
  for (size_t c = 0; c < junctionCubes_.size(); ++c)
  {
    auto& g = groups[touching.root(static_cast<int>(c))];
    g.first.push_back(pointAt(junctionCubes_[c].first) + Vec3{ 0.5 * h_, 0.5 * h_, 0.5 * h_ });
    g.second.insert(junctionCubes_[c].second.begin(), junctionCubes_[c].second.end());
  }
  std::vector<Junction> junctions;
  for (const auto& [unused, g] : groups)
    if (g.second.size() >= 2)
    {
      Junction j;
      for (const Vec3& c : g.first)
        j.centre = j.centre + (1.0 / g.first.size()) * c;
      j.ending.assign(g.second.begin(), g.second.end());
      junctions.push_back(std::move(j));
    }
  found_.junctions = std::move(junctions);
}

const EdgeRegions& FeatureGridSearch::edge(std::int64_t p, int axis)
{
  const std::int64_t key = 3 * p + axis;
  auto it = edges_.find(key);
  if (it == edges_.end())
    it = edges_.emplace(key, regionsAlong(oracle_, pointAt(p), pointAt(p + stride_[axis]))).first;
  return it->second;
}

/// The crossing on the grid face at lowest corner p normal to `axis`, or -1 (cached).
int FeatureGridSearch::face(std::int64_t p, int axis)
{
  const std::int64_t key = 3 * p + axis;
  if (auto it = faceCrossing_.find(key); it != faceCrossing_.end())
    return it->second;
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  Vec3 U, V;
  U[u] = h_;
  V[v] = h_;
  Rect q{ pointAt(p), U, V, edge(p, u), edge(p + stride_[v], u), edge(p, v), edge(p + stride_[u], v) };
  int found = -1;
  if (holdsCurve(loopOf(q)))
  {
    Crossing c = locate(oracle_, std::move(q), found_.precision);
    if (c.regions.size() >= 3 && isFeature(c.regions))
    {
      found = static_cast<int>(found_.crossings.size());
      found_.crossings.push_back(std::move(c));
    }
  }
  faceCrossing_.emplace(key, found);
  return found;
}

/// The cube at lowest corner p, when its corners are not all in one region.
void FeatureGridSearch::linkCube(std::int64_t p)
{
  bool mixed = false;
  for (int c = 1; c < 8 && !mixed; ++c)
    mixed = region_[p + (c & 1) * stride_[0] + ((c >> 1) & 1) * stride_[1] + ((c >> 2) & 1) * stride_[2]] != region_[p];
  if (!mixed)
    return;
  std::map<Signature, std::vector<int>> bySignature;
  for (int axis = 0; axis < 3; ++axis)
    for (std::int64_t side : { std::int64_t(0), stride_[axis] })
    {
      const int c = face(p + side, axis);
      if (c >= 0)
        bySignature[found_.crossings[c].regions].push_back(c);
    }
  std::vector<int> ending;
  for (const auto& [signature, ids] : bySignature)
  {
    if (ids.size() == 2)
      found_.links.push_back({ ids[0], ids[1] });
    else if (ids.size() == 4)
      pairPasses(ids);
    else
      ending.insert(ending.end(), ids.begin(), ids.end());
  }
  // one ending curve is kept too: its junction may be shared with a touching cube (mergeJunctionCubes)
  if (!ending.empty())
    junctionCubes_.push_back({ p, ending });
}

/// One curve passing a cube twice (a fold, two near-parallel pieces): two passes, paired by the
/// shorter total chord, not a junction (that made zigzags meeting at 0 degrees).
void FeatureGridSearch::pairPasses(const std::vector<int>& ids)
{
  const auto d = [&](int a, int b) { return norm(found_.crossings[ids[a]].point - found_.crossings[ids[b]].point); };
  const double p01 = d(0, 1) + d(2, 3), p02 = d(0, 2) + d(1, 3), p03 = d(0, 3) + d(1, 2);
  const int partner = p01 <= p02 && p01 <= p03 ? 1 : p02 <= p03 ? 2 : 3;
  const int rest[2] = { partner == 1 ? 2 : 1, partner == 3 ? 2 : 3 };
  found_.links.push_back({ ids[0], ids[partner] });
  found_.links.push_back({ ids[rest[0]], ids[rest[1]] });
}

void FeatureGridSearch::refine(const FeatureCurveLocator& locator, int a, int b, int depth, std::vector<int>& path)
{
  auto& crossings = found_.crossings;
  const Vec3 pa = crossings[a].point, pb = crossings[b].point;
  Crossing m;
  if (depth == 0 || !locator.curveBetween(pa, pb, crossings[a].regions, m) || !(norm(m.point - 0.5 * (pa + pb)) > tolerance_))
    return;
  const int id = static_cast<int>(crossings.size());
  crossings.push_back(std::move(m));
  refine(locator, a, id, depth - 1, path);
  path.push_back(id);
  refine(locator, id, b, depth - 1, path);
}
}
