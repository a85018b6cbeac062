// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "BinCounts.h"
#include "MeshQuality.h"
#include "TetMesh.h"
#include "WorstTets.h"

#include <array>
#include <cstddef>
#include <map>
#include <string>

namespace omesh
{
/// The smallest chunk of tetrahedra the passes over a finished mesh give one thread (forEachChunk).
constexpr std::size_t kTetsPerChunk = 8192;

/// Where summariseShapes writes each tetrahedron's measures, in the caller's own buffers (the VTK
/// adapter's cell arrays): each pointer null or to one value per tetrahedron.
struct TetShapeArrays
{
  double* minDihedral = nullptr;
  double* maxDihedral = nullptr;
  double* radiusEdge = nullptr;
};

/// Shape figures of a group of tetrahedra (a material, or the whole mesh): counts, volume, and the
/// worst value of each TetShape measure.
struct ShapeFigures
{
  std::size_t tetrahedra = 0;
  double volume = 0.0;
  double minDihedral = 180.0, sumMinDihedral = 0.0, maxDihedral = 0.0;
  double worstRadiusRatio = 1.0, worstMeanRatio = 1.0, worstEdgeRatio = 1.0;

  void add(const TetShape& s);
  /// Adds another group's figures (as if its tetrahedra had been added one by one, sums aside).
  void merge(const ShapeFigures& o);
  double meanMinDihedral() const { return tetrahedra ? sumMinDihedral / static_cast<double>(tetrahedra) : 0.0; }
};

/// The edges of the bins (degrees) in which ShapeSummary counts the tetrahedra by their smallest
/// and by their largest dihedral angle: those of the quality report's lines (report.py's
/// TEXT_BINS and MAX_TEXT_BINS), which then need no pass of their own.
constexpr std::array<double, 9> kMinDihedralBinEdges = { 0, 5, 10, 20, 30, 40, 50, 60, 90 };
constexpr std::array<double, 8> kMaxDihedralBinEdges = { 60, 90, 120, 150, 155, 160, 170, 180 };

/// The shape figures of a mesh, per material and all together.
class ShapeSummary
{
public:
  std::map<int, ShapeFigures> materials;
  ShapeFigures all;
  BinCounts<kMinDihedralBinEdges.size()> minDihedralBins; ///< of the whole mesh
  BinCounts<kMaxDihedralBinEdges.size()> maxDihedralBins;
  WorstTets smallestMinDihedral; ///< of the whole mesh (key: the angle)
  WorstTets largestMaxDihedral;  ///< (key: minus the angle)

  ShapeSummary() = default;
  ShapeSummary(const ShapeSummary& o)
    : materials(o.materials)
    , all(o.all)
    , minDihedralBins(o.minDihedralBins)
    , maxDihedralBins(o.maxDihedralBins)
    , smallestMinDihedral(o.smallestMinDihedral)
    , largestMaxDihedral(o.largestMaxDihedral)
  {
  }
  ShapeSummary& operator=(const ShapeSummary& o)
  {
    materials = o.materials;
    all = o.all;
    minDihedralBins = o.minDihedralBins;
    maxDihedralBins = o.maxDihedralBins;
    smallestMinDihedral = o.smallestMinDihedral;
    largestMaxDihedral = o.largestMaxDihedral;
    last_ = nullptr;
    return *this;
  }

  /// Tetrahedron `t` of `material` (materials come in long runs: the map is asked where it changes).
  void add(int material, const TetShape& s, std::size_t t)
  {
    if (!last_ || material != lastMaterial_)
    {
      last_ = &materials[material];
      lastMaterial_ = material;
    }
    last_->add(s);
    all.add(s);
    minDihedralBins.add(kMinDihedralBinEdges, s.minDihedral);
    maxDihedralBins.add(kMaxDihedralBinEdges, s.maxDihedral);
    smallestMinDihedral.add(s.minDihedral, t);
    largestMaxDihedral.add(-s.maxDihedral, t);
  }

  /// Adds another summary's figures (per material and all together).
  void merge(const ShapeSummary& o);

  /// The figures as statistics (shape.* keys of FieldDataKeys.txt, each also per material with
  /// the suffix ".material_<id>"; the bins' counts with the suffix ".<low>_<high>"; the worst
  /// tetrahedra's indices with the suffix ".<rank>", 0 the worst).
  void addTo(std::map<std::string, double>& statistics) const;

private:
  ShapeFigures* last_ = nullptr;
  int lastMaterial_ = 0;
};

/// Measures tetrahedron `t` of `mesh` with its corners as the output writes them (positively
/// oriented: the first two swapped when the volume is negative), writes the measures to the
/// arrays that are given and adds them to `summary`. `signedVolume` gets the signed volume of the
/// corners as given, `lengths` the six edge lengths (edgeLengths of the oriented corners).
TetShape measureTet(const TetMesh& mesh, std::size_t t, ShapeSummary& summary, const TetShapeArrays& arrays,
  double& signedVolume, double lengths[6]);

/// One pass over the tetrahedra: each one's TetShape (its corners taken positively oriented, as
/// the VTK output writes them), written to `arrays` where given, and the summary; in chunks of
/// the tetrahedra on the threads runOnThreads allows, the chunks' summaries merged in order (the
/// figures the same on any number of threads). The validity check's pass measures the same way.
ShapeSummary summariseShapes(const TetMesh& mesh, const TetShapeArrays& arrays = {});
}
