// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "MeshQuality.h"
#include "TetMesh.h"

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

/// The shape figures of a mesh, per material and all together.
class ShapeSummary
{
public:
  std::map<int, ShapeFigures> materials;
  ShapeFigures all;

  ShapeSummary() = default;
  ShapeSummary(const ShapeSummary& o) : materials(o.materials), all(o.all) {}
  ShapeSummary& operator=(const ShapeSummary& o)
  {
    materials = o.materials;
    all = o.all;
    last_ = nullptr;
    return *this;
  }

  /// One tetrahedron of `material` (materials come in long runs: the map is asked where it changes).
  void add(int material, const TetShape& s)
  {
    if (!last_ || material != lastMaterial_)
    {
      last_ = &materials[material];
      lastMaterial_ = material;
    }
    last_->add(s);
    all.add(s);
  }

  /// Adds another summary's figures (per material and all together).
  void merge(const ShapeSummary& o);

  /// The figures as statistics (shape.* keys of FieldDataKeys.txt, each also per material with
  /// the suffix ".material_<id>").
  void addTo(std::map<std::string, double>& statistics) const;

private:
  ShapeFigures* last_ = nullptr;
  int lastMaterial_ = 0;
};

/// Measures tetrahedron `t` of `mesh` with its corners as the output writes them (positively
/// oriented: the first two swapped when the volume is negative), writes the measures to the
/// arrays that are given and adds them to `summary`. `signedVolume` gets the signed volume of the
/// corners as given.
TetShape measureTet(const TetMesh& mesh, std::size_t t, ShapeSummary& summary, const TetShapeArrays& arrays,
  double& signedVolume);

/// One pass over the tetrahedra: each one's TetShape (its corners taken positively oriented, as
/// the VTK output writes them), written to `arrays` where given, and the summary; in chunks of
/// the tetrahedra on the threads runOnThreads allows, the chunks' summaries merged in order (the
/// figures the same on any number of threads). The validity check's pass measures the same way.
ShapeSummary summariseShapes(const TetMesh& mesh, const TetShapeArrays& arrays = {});
}
