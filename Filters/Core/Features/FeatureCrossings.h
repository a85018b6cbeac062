// SPDX-License-Identifier: GPL-3.0-or-later
// The exact queries the feature-line search (findFeatureLines) is built on: the regions met along a
// segment, from the domains' own crossings, and a curve's crossing through a rectangle, located by
// bisection, so that every point found lies on the true curve. A region is a material together
// with the domain that decides it; a curve is where three or more regions meet.
#pragma once

#include "HierarchicalOracle.h"
#include "Vec3.h"

#include <vector>

namespace omesh::featurelines
{
using Region = Decision;
using Signature = std::vector<Region>; // the regions around a curve, sorted

/// The regions met along a segment: r[0] up to t[0], r[1] up to t[1], ..., r.back() up to 1.
struct EdgeRegions
{
  std::vector<double> t;
  std::vector<Region> r;
};

/// Exact: every domain lists where its material may change, and the region is evaluated between
/// consecutive candidates (as HierarchicalOracle::intersect does).
EdgeRegions regionsAlong(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b);

/// A rectangle o + s U + t V (s, t in [0, 1]) with the regions along its four edges; bottom and top
/// run along U, left and right along V.
struct Rect
{
  Vec3 o, U, V;
  EdgeRegions bottom, top, left, right;
};

/// The regions met walking once around the rectangle, consecutive repeats merged.
std::vector<Region> loopOf(const Rect& q);

/// A curve where regions meet passes through the rectangle when some boundary between two regions
/// crosses its edges an odd number of times (a boundary that only enters and leaves crosses twice).
bool holdsCurve(const std::vector<Region>& loop);

struct Crossing
{
  Vec3 point;
  Signature regions;
};

/// Bisects a rectangle that holds a curve down to `precision`; the centre of the last one and the
/// regions around it.
Crossing locate(const HierarchicalOracle& oracle, Rect q, double precision);

/// The materials meeting at a curve, ascending.
std::vector<int> materialsOf(const Signature& s);

/// A curve is a feature when three or more materials meet there, or when the interfaces meeting
/// there belong to two different inputs' boundaries: the boundary between two regions of different
/// materials is the boundary of the higher-priority deciding domain of the two.
bool isFeature(const Signature& s);
}
