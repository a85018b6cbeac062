// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshSizeEstimate.h"

#include "FeatureEdgeSizes.h"
#include "HierarchicalOracle.h"
#include "InputError.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

namespace omesh
{
namespace
{
double orDefault(double v, double fallback) { return v > 0 ? v : fallback; }

constexpr int kSamples = 24; // grid cells along each axis of the oracle's bounds

/// The oracle's material at the centres of a kSamples^3 grid over its bounds (index (k n + j) n + i).
std::vector<int> sampleMaterials(const HierarchicalOracle& oracle, const BoundingBox& box)
{
  constexpr int n = kSamples;
  const Vec3 step = (1.0 / n) * box.size();
  std::vector<int> label(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        label[(static_cast<size_t>(k) * n + j) * n + i] =
          oracle.material(box.min + Vec3{ (i + 0.5) * step.x, (j + 0.5) * step.y, (k + 0.5) * step.z });
  return label;
}

double cellVertices(const std::vector<int>& label, const BoundingBox& box, const MaterialCriteria& criteria)
{
  const Vec3 step = (1.0 / kSamples) * box.size();
  std::map<int, double> volume;
  for (int m : label)
    if (m != kOutside)
      volume[m] += step.x * step.y * step.z;
  double vertices = 0.0;
  for (const auto& [m, v] : volume)
  {
    const double cell = orDefault(criteria.of(m).cellSize, norm(box.size()) / 20.0);
    vertices += v / (cell * cell * cell);
  }
  return vertices;
}
}

double estimateCellVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria)
{
  const BoundingBox box = oracle.bounds();
  return cellVertices(sampleMaterials(oracle, box), box, criteria);
}

double estimateMeshVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria,
  const FeatureSegments& features)
{
  return estimateMeshSize(oracle, criteria, features).total();
}

MeshSizeEstimate estimateMeshSize(const HierarchicalOracle& oracle, const MaterialCriteria& criteria,
  const FeatureSegments& features)
{
  const BoundingBox box = oracle.bounds();
  const double fallback = norm(box.size()) / 20.0;
  constexpr int n = kSamples;
  const Vec3 step = (1.0 / n) * box.size();
  const std::vector<int> label = sampleMaterials(oracle, box);
  auto at = [&](int i, int j, int k) { return label[(static_cast<size_t>(k) * n + j) * n + i]; };

  // Interface area per material (a staircase over-counts a slanted area by at most sqrt(3), and
  // the box's own faces count as boundary).
  std::map<int, double> area;
  const double faceArea[3] = { step.y * step.z, step.x * step.z, step.x * step.y };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const int m = at(i, j, k);
        const int next[3] = { i + 1 < n ? at(i + 1, j, k) : kOutside, j + 1 < n ? at(i, j + 1, k) : kOutside,
          k + 1 < n ? at(i, j, k + 1) : kOutside };
        const int index[3] = { i, j, k };
        for (int axis = 0; axis < 3; ++axis)
        {
          if (next[axis] != m)
            for (int side : { m, next[axis] })
              if (side != kOutside)
                area[side] += faceArea[axis];
          if (index[axis] == 0 && m != kOutside)
            area[m] += faceArea[axis];
        }
      }

  MeshSizeEstimate estimate;
  estimate.volume = cellVertices(label, box, criteria);
  for (const auto& [m, a] : area)
  {
    const MeshCriteria::Values c = criteria.of(m);
    const double facet = orDefault(c.facetSize, orDefault(c.cellSize, fallback));
    // triangles of circumradius `facet` have an area of about 1.3 facet^2; two per vertex
    estimate.surfaces += a / (2.6 * facet * facet);
  }
  // each segment at its own edge size (global < per material < per feature, FeatureEdgeSizes.h)
  const std::vector<double> edges = resolveFeatureEdgeSizes(features, criteria, oracle);
  for (size_t s = 0; s < features.segments.size(); ++s)
    estimate.lines += features.length(s) / (edges[s] > 0 ? edges[s] : fallback);
  return estimate;
}

void checkMeshSize(const MeshSizeEstimate& estimate, double budget, double timeLimit)
{
  const double asked = estimate.total();
  const bool overBudget = budget > 0 && asked > kBudgetRefusalFactor * budget;
  const double timed = timeLimit > 0 ? timeLimit / kFastestSecondsPerVertex : 0.0;
  const bool overTime = timed > 0 && asked > timed;
  if (!overBudget && !overTime)
    return;
  // the criteria to coarsen: each part asking for more than a third of what fits, by the factor
  // that brings it there (sizes enter the volume cubed, the surfaces squared, the lines once)
  struct Part
  {
    double vertices;
    const char* what;
    const char* criterion;
    double power;
  };
  const Part parts[3] = { { estimate.volume, "the volumes at their cell sizes", "CellSize", 3.0 },
    { estimate.surfaces, "the interfaces at their facet sizes", "FacetSize", 2.0 },
    { estimate.lines, "the feature lines at their edge sizes", "EdgeSize", 1.0 } };
  const double fits = overBudget ? kBudgetRefusalFactor * budget : timed;
  std::ostringstream o;
  o.precision(3);
  o << "the criteria ask for about " << asked << " vertices (" << parts[0].vertices << " for " << parts[0].what
    << ", " << parts[1].vertices << " for " << parts[1].what << ", " << parts[2].vertices << " for "
    << parts[2].what << "), ";
  if (overBudget)
    o << "more than " << kBudgetRefusalFactor << " times the vertex budget of " << budget
      << " (MaximumNumberOfVertices): refinement would stop far from them";
  else
    o << "more than the time limit of " << timeLimit << " s allows (at most about " << timed
      << " vertices at the fastest rate measured)";
  o << ". Coarsen the criteria";
  const char* sep = " (";
  for (const Part& p : parts)
    if (p.vertices > fits / 3.0)
    {
      o << sep << p.criterion << " about " << std::pow(p.vertices / (fits / 3.0), 1.0 / p.power) << " times larger";
      sep = ", ";
    }
  o << (sep[0] == ',' ? ")" : "") << ", or raise "
    << (overBudget ? "MaximumNumberOfVertices" : "the time limit (TimeLimit)")
    << "; a size much smaller than the domain may be a units slip";
  throw InputError(o.str());
}

std::vector<std::string> criteriaScaleWarnings(const HierarchicalOracle& oracle, const MaterialCriteria& criteria)
{
  std::vector<std::string> warnings;
  const BoundingBox box = oracle.bounds();
  const double diagonal = box.empty() ? 0.0 : norm(box.size());
  if (!(diagonal > 0) || !std::isfinite(diagonal))
    return warnings;
  const MeshCriteria::Values global = criteria.globalValues();
  // one warning per level and kind: "CellSize 1000 and FacetSize 1000 are larger than ..."
  auto check = [&](const MeshCriteria::Values& v, const std::string& who, const MeshCriteria::Values* inherited) {
    const struct
    {
      double value, inheritedValue;
      const char* name;
      bool small; // a value this much smaller than the domain is a slip too
    } sizes[4] = { { v.cellSize, inherited ? inherited->cellSize : -1, "CellSize", true },
      { v.facetSize, inherited ? inherited->facetSize : -1, "FacetSize", true },
      { v.edgeSize, inherited ? inherited->edgeSize : -1, "EdgeSize", true },
      { v.facetDistance, inherited ? inherited->facetDistance : -1, "FacetDistance", false } };
    std::vector<std::string> large, small;
    double smallest = diagonal;
    for (const auto& s : sizes)
    {
      if (!(s.value > 0) || s.value == s.inheritedValue) // no bound, or the global value again
        continue;
      std::ostringstream o;
      o.precision(4);
      o << s.name << " " << s.value;
      if (s.value > diagonal)
        large.push_back(o.str());
      else if (s.small && s.value * kUnitsSlipRatio < diagonal)
      {
        small.push_back(o.str());
        smallest = std::min(smallest, s.value);
      }
    }
    auto joined = [](const std::vector<std::string>& items) {
      std::string text;
      for (size_t i = 0; i < items.size(); ++i)
        text += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
      return text;
    };
    std::ostringstream o;
    o.precision(4);
    if (!large.empty())
      o << who << ": " << joined(large) << (large.size() > 1 ? " are" : " is")
        << " larger than the whole domain (the diagonal of its bounds is " << diagonal
        << "): the mesh follows the shapes only coarsely; a units slip?";
    if (!large.empty())
      warnings.push_back(o.str());
    std::ostringstream p;
    p.precision(4);
    if (!small.empty())
      p << who << ": " << joined(small) << (small.size() > 1 ? " are" : " is") << " up to " << diagonal / smallest
        << " times smaller than the domain (the diagonal of its bounds is " << diagonal
        << "): a units slip (metres against millimetres)?";
    if (!small.empty())
      warnings.push_back(p.str());
  };
  check(global, "global criteria", nullptr);
  for (const auto& entry : criteria.perMaterial)
    check(criteria.of(entry.first), "criteria of material " + std::to_string(entry.first), &global);
  return warnings;
}
}
