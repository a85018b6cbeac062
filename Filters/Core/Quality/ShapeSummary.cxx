// SPDX-License-Identifier: GPL-3.0-or-later
#include "ShapeSummary.h"

#include "FieldDataKeys.h"
#include "WorkerThreads.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace omesh
{
void ShapeFigures::add(const TetShape& s)
{
  ShapeFigures one;
  one.tetrahedra = 1;
  one.volume = s.volume;
  one.minDihedral = one.sumMinDihedral = s.minDihedral;
  one.maxDihedral = s.maxDihedral;
  one.worstRadiusRatio = s.radiusRatio;
  one.worstMeanRatio = s.meanRatio;
  one.worstEdgeRatio = s.edgeRatio;
  merge(one);
}

void ShapeFigures::merge(const ShapeFigures& o)
{
  tetrahedra += o.tetrahedra;
  volume += o.volume;
  minDihedral = std::min(minDihedral, o.minDihedral);
  sumMinDihedral += o.sumMinDihedral;
  maxDihedral = std::max(maxDihedral, o.maxDihedral);
  worstRadiusRatio = std::min(worstRadiusRatio, o.worstRadiusRatio);
  worstMeanRatio = std::min(worstMeanRatio, o.worstMeanRatio);
  worstEdgeRatio = std::min(worstEdgeRatio, o.worstEdgeRatio);
}

void ShapeSummary::merge(const ShapeSummary& o)
{
  for (const auto& [m, f] : o.materials)
    materials[m].merge(f);
  all.merge(o.all);
  minDihedralBins.merge(o.minDihedralBins);
  maxDihedralBins.merge(o.maxDihedralBins);
  smallestMinDihedral.merge(o.smallestMinDihedral);
  largestMaxDihedral.merge(o.largestMaxDihedral);
  last_ = nullptr; // the map may have grown
}

namespace
{
/// "shape.min_dihedral_bin.0_5" = the count of [0, 5), ...
template <std::size_t N>
void putBins(std::map<std::string, double>& statistics, const std::string& key, const std::array<double, N>& edges,
  const BinCounts<N>& bins)
{
  auto text = [](double degrees) {
    std::ostringstream o;
    o << degrees;
    return o.str();
  };
  for (std::size_t b = 0; b + 1 < N; ++b)
    statistics[key + "." + text(edges[b]) + "_" + text(edges[b + 1])] = static_cast<double>(bins.counts[b]);
}
}

void ShapeSummary::addTo(std::map<std::string, double>& statistics) const
{
  auto put = [&statistics](const std::string& suffix, const ShapeFigures& f) {
    statistics[keys::SHAPE_TETRAHEDRA + suffix] = static_cast<double>(f.tetrahedra);
    statistics[keys::SHAPE_VOLUME + suffix] = f.volume;
    statistics[keys::SHAPE_MIN_DIHEDRAL + suffix] = f.tetrahedra ? f.minDihedral : 0.0;
    statistics[keys::SHAPE_MEAN_MIN_DIHEDRAL + suffix] = f.meanMinDihedral();
    statistics[keys::SHAPE_MAX_DIHEDRAL + suffix] = f.tetrahedra ? f.maxDihedral : 0.0;
    statistics[keys::SHAPE_WORST_RADIUS_RATIO + suffix] = f.tetrahedra ? f.worstRadiusRatio : 0.0;
    statistics[keys::SHAPE_WORST_MEAN_RATIO + suffix] = f.tetrahedra ? f.worstMeanRatio : 0.0;
    statistics[keys::SHAPE_WORST_EDGE_RATIO + suffix] = f.tetrahedra ? f.worstEdgeRatio : 0.0;
  };
  put("", all);
  putBins(statistics, keys::SHAPE_MIN_DIHEDRAL_BIN, kMinDihedralBinEdges, minDihedralBins);
  putBins(statistics, keys::SHAPE_MAX_DIHEDRAL_BIN, kMaxDihedralBinEdges, maxDihedralBins);
  for (const auto& [key, worst] : { std::make_pair(keys::SHAPE_SMALLEST_MIN_DIHEDRAL_TET, &smallestMinDihedral),
         std::make_pair(keys::SHAPE_LARGEST_MAX_DIHEDRAL_TET, &largestMaxDihedral) })
    for (std::size_t i = 0; i < worst->count; ++i)
      statistics[std::string(key) + "." + std::to_string(i)] = static_cast<double>(worst->items[i].second);
  for (const auto& [m, f] : materials)
    put(".material_" + std::to_string(m), f);
}

TetShape measureTet(const TetMesh& mesh, std::size_t t, ShapeSummary& summary, const TetShapeArrays& arrays,
  double& volume, double lengths[6])
{
  std::array<int, 4> k = mesh.tets[t];
  const auto& P = mesh.points;
  volume = signedVolume(P[k[0]], P[k[1]], P[k[2]], P[k[3]]);
  if (volume < 0)
    std::swap(k[0], k[1]);
  edgeLengths(P[k[0]], P[k[1]], P[k[2]], P[k[3]], lengths);
  const TetShape s = tetShape(P[k[0]], P[k[1]], P[k[2]], P[k[3]], std::abs(volume), lengths);
  if (arrays.minDihedral)
    arrays.minDihedral[t] = s.minDihedral;
  if (arrays.maxDihedral)
    arrays.maxDihedral[t] = s.maxDihedral;
  if (arrays.radiusEdge)
    arrays.radiusEdge[t] = s.radiusEdge;
  summary.add(t < mesh.tetMaterial.size() ? mesh.tetMaterial[t] : 0, s, t);
  return s;
}

ShapeSummary summariseShapes(const TetMesh& mesh, const TetShapeArrays& arrays)
{
  const std::size_t chunks = chunkCount(mesh.tets.size(), kTetsPerChunk);
  std::vector<ShapeSummary> parts(chunks);
  forEachChunk(mesh.tets.size(), chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
    double volume, lengths[6];
    for (std::size_t t = begin; t < end; ++t)
      measureTet(mesh, t, parts[c], arrays, volume, lengths);
  });
  ShapeSummary summary;
  for (const ShapeSummary& part : parts)
    summary.merge(part);
  return summary;
}
}
