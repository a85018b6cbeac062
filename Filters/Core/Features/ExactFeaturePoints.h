// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "ExactCoordinates.h"
#include "FeatureSegments.h"

#include <array>
#include <functional>
#include <unordered_map>
#include <vector>

namespace omesh
{
/// What an exact point separates: the materials meeting there (ascending) and how far a line
/// through it may move off them.
struct ExactPoint
{
  std::vector<int> materials;
  double tolerance = 0.0;
};

/// The points of feature lines found where the inputs meet lie on the interfaces they separate
/// (findFeatureLines bisects them to 1e-10 of the diagonal); a simplification that merges them
/// with points nearby moves those lines off their interfaces (issue 13: a triple line's end and a
/// crease corner 0.17 mm apart became one point 0.025 mm below the face). This records, by exact
/// coordinates (the network simplification drops and merges points, never moves them), which
/// points are such and what they separate, from the materials tagged on their segments.
class ExactFeaturePoints
{
public:
  ExactFeaturePoints() = default;
  /// `materials`: per segment of `f`, the materials it separates (-2 unused; none: a given
  /// segment, whose points are not exact); `tolerance(materials)`: how far a line separating them
  /// may move. A point of several tagged segments separates all their materials and takes the
  /// smallest tolerance.
  ExactFeaturePoints(const FeatureSegments& f, const std::vector<std::array<int, 4>>& materials,
    const std::function<double(const std::vector<int>&)>& tolerance);

  bool empty() const { return points_.empty(); }
  /// The point at these exact coordinates, or nullptr when it is not one.
  const ExactPoint* find(const Vec3& p) const;
  /// Whether `to` lies on every interface `from` lies on: both are exact, and `to` separates
  /// every material `from` does.
  bool onInterfacesOf(const Vec3& from, const Vec3& to) const;

private:
  std::unordered_map<ExactCoordinates, ExactPoint, ExactCoordinatesHash> points_;
};
}
