// SPDX-License-Identifier: GPL-3.0-or-later
// Finds a curve already known by its signature where it crosses a given plane: how the feature-line
// search puts more points on a curve between two it has (refined links, chords put back on the
// curve, the domains' bend planes), with the same bisection that found it on the grid's faces.
#pragma once

#include "Domain.h"
#include "FeatureCrossings.h"

namespace omesh::featurelines
{
class FeatureCurveLocator
{
public:
  /// Crossings are located to `precision` (the search's: 1e-10 of the bounding-box diagonal).
  FeatureCurveLocator(const HierarchicalOracle& oracle, double precision)
    : oracle_(oracle)
    , precision_(precision)
  {
  }

  const HierarchicalOracle& oracle() const { return oracle_; }
  double precision() const { return precision_; }

  /// The curve with signature `regions` where it crosses the plane halfway between pa and pb, in the
  /// square of side |pb - pa| centred on their midpoint; false when it does not pass there.
  bool curveBetween(const Vec3& pa, const Vec3& pb, const Signature& regions, Crossing& m) const;

  /// The curve with signature `regions` where it crosses the plane through `centre` normal to
  /// `normal`, in the square of side L centred there; false when it does not pass there.
  bool curveInSquare(const Vec3& centre, const Vec3& normal, double L, const Signature& regions, Crossing& m) const;

  /// The curve with signature `regions` where it crosses `plane`, in the square of side L centred
  /// on plane.point; false when it does not pass there.
  bool curveInPlane(const BendPlane& plane, double L, const Signature& regions, Crossing& m) const
  {
    return curveInSquare(plane.point, plane.normal, L, regions, m);
  }

private:
  const HierarchicalOracle& oracle_;
  double precision_;
};
}
