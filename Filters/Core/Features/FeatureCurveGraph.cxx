// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureCurveGraph.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace omesh::featurelines
{
namespace
{
/// The point nearest (least squares) to lines through p[i] along unit d[i]; false when they are
/// (nearly) parallel.
bool nearestToLines(const std::vector<Vec3>& p, const std::vector<Vec3>& d, Vec3& x)
{
  double A[3][3] = {}, b[3] = {};
  for (size_t k = 0; k < p.size(); ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
      {
        const double m = (i == j ? 1.0 : 0.0) - d[k][i] * d[k][j];
        A[i][j] += m;
        b[i] += m * p[k][j];
      }
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
    A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  if (!(std::abs(det) > 1e-6 * std::pow(static_cast<double>(p.size()), 3)))
    return false;
  for (int c = 0; c < 3; ++c)
  {
    double M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        M[i][j] = j == c ? b[i] : A[i][j];
    x[c] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
             M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
      det;
  }
  return isFinite(x);
}
}

FeatureCurveGraph::FeatureCurveGraph(const GridCrossings& found)
  : h_(found.spacing)
{
  crossingCount_ = static_cast<int>(found.crossings.size());
  for (const Crossing& c : found.crossings)
    nodes_.push_back(c.point);
  adjacent_.resize(nodes_.size());
  for (const Link& l : found.links)
  {
    adjacent_[l.a].push_back(l.b);
    adjacent_[l.b].push_back(l.a);
  }
  for (const auto& [centre, ending] : found.junctions)
    addJunction(centre, ending);
}

std::vector<std::vector<int>> FeatureCurveGraph::curves() const
{
  std::set<std::pair<int, int>> walked;
  auto take = [&](int a, int b) { return walked.insert({ std::min(a, b), std::max(a, b) }).second; };
  std::vector<std::vector<int>> chains;
  auto walk = [&](int start, int next) {
    std::vector<int> chain{ start, next };
    // junctions end chains, so that a chain is one curve with one signature
    for (int previous = start, v = next; adjacent_[v].size() == 2 && v != start && v < crossingCount_;)
    {
      const int w = adjacent_[v][0] == previous ? adjacent_[v][1] : adjacent_[v][0];
      if (!take(v, w))
        break;
      chain.push_back(w);
      previous = v;
      v = w;
    }
    chains.push_back(std::move(chain));
  };
  for (int v = 0; v < static_cast<int>(nodes_.size()); ++v)
    if (adjacent_[v].size() != 2 || v >= crossingCount_)
      for (int w : adjacent_[v])
        if (take(v, w))
          walk(v, w);
  for (int v = 0; v < static_cast<int>(nodes_.size()); ++v)
    for (int w : adjacent_[v])
      if (take(v, w))
        walk(v, w);
  return chains;
}

/// A junction vertex for the curves `ending` near `centre`: the meeting point of their tangents
/// (exact for straight curves), else their mean.
void FeatureCurveGraph::addJunction(const Vec3& centre, const std::vector<int>& ending)
{
  std::vector<Vec3> at, along;
  Vec3 mean;
  for (int c : ending)
  {
    mean = mean + (1.0 / ending.size()) * nodes_[c];
    if (adjacent_[c].size() == 1 && adjacent_[c][0] < crossingCount_)
    {
      const Vec3 d = nodes_[c] - nodes_[adjacent_[c][0]];
      if (norm(d) > 0)
      {
        at.push_back(nodes_[c]);
        along.push_back((1.0 / norm(d)) * d);
      }
    }
  }
  Vec3 x;
  if (at.size() < 2 || !nearestToLines(at, along, x) || norm(x - centre) > 1.5 * h_)
    x = mean;
  const int junction = static_cast<int>(nodes_.size());
  nodes_.push_back(x);
  adjacent_.emplace_back();
  for (int c : ending)
  {
    adjacent_[c].push_back(junction);
    adjacent_[junction].push_back(c);
  }
}
}
