// SPDX-License-Identifier: GPL-3.0-or-later
// SurfaceDomain with the winding number: its grid (values carried from cell to cell within the
// gradient bound) and where it passes 1/2 along a segment.
#include "SurfaceDomainImpl.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace omesh
{
std::optional<int> SurfaceDomain::Impl::signedCrossings(const Point& from, const Point& to, size_t c, size_t d) const
{
  int count = 0;
  for (int pass = 0; pass < (d == c ? 1 : 2); ++pass)
  {
    const size_t cellOf = pass == 0 ? c : d;
    for (uint32_t t = cellFirst[cellOf]; t < cellFirst[cellOf + 1]; ++t)
    {
      const uint32_t id = cellTriangles[t];
      if (pass == 1 && std::find(cellTriangles.begin() + cellFirst[c], cellTriangles.begin() + cellFirst[c + 1], id) !=
            cellTriangles.begin() + cellFirst[c + 1])
        continue; // listed in both cells: counted once
      const auto& [a, b, e] = triangles[id];
      const std::optional<int> crossed =
        crossing(a, b, e, from, to, CGAL::orientation(a, b, e, from), CGAL::orientation(a, b, e, to));
      if (!crossed)
        return std::nullopt;
      count += *crossed;
    }
  }
  return count;
}

double SurfaceDomain::Impl::windingEstimate(const Vec3& p, double& error) const
{
  const int i = std::clamp(static_cast<int>((p.x - origin.x) * invCell.x), 0, n[0] - 1);
  const int j = std::clamp(static_cast<int>((p.y - origin.y) * invCell.y), 0, n[1] - 1);
  const int k = std::clamp(static_cast<int>((p.z - origin.z) * invCell.z), 0, n[2] - 1);
  // the segment to the reference point must stay in the (enlarged) cell whose triangles are listed
  const Vec3 lo{ origin.x + i * cell.x, origin.y + j * cell.y, origin.z + k * cell.z };
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= lo[a] - 0.5 * cellEps && p[a] <= lo[a] + cell[a] + 0.5 * cellEps))
    {
      return evaluate(p, error);
    }
  const size_t c = cellIndex(i, j, k);
  const Vec3 r = referencePoint(i, j, k);
  double w = windingAtReference[c];
  if (state[c] == kCellBoundary)
  {
    const std::optional<int> crossed = signedCrossings(toCgal(r), toCgal(p), c, c);
    if (!crossed)
      return evaluate(p, error);
    w += *crossed;
  }
  error = windingError[c] + windingSlope[c] * norm(p - r);
  return w;
}

bool SurfaceDomain::Impl::windingInside(const Vec3& p) const
{
  double error = 0.0;
  const double w = windingEstimate(p, error);
  if (decides(w, error))
    return w > 0.5;
  return windingAt(p) > 0.5;
}

void SurfaceDomain::Impl::buildWindingGrid(size_t numTriangles)
{
  sizeGrid(numTriangles);
  markBoundaryCells();
  const size_t cells = state.size();
  windingAtReference.assign(cells, 0.0);
  windingError.assign(cells, std::numeric_limits<float>::infinity());
  windingSlope.assign(cells, 0.0f);
  if (winding->hasBorder())
    boundWindingSlopes();
  // Walk from cell 0, carrying w across faces (from any neighbour that has a value, where the first
  // cannot); an evaluation restarts the error where it would pass kMaxError and come within
  // kMaxError of 1/2 (near holes), or at a degenerate crossing. A cell whose bound is infinite (the
  // border passes through it) cannot use its reference point: no evaluation there.
  std::vector<char> seen(cells, 0);
  std::deque<size_t> queue{ 0 };
  seen[0] = 1;
  auto evaluateReference = [&](size_t c) {
    double error = 0.0;
    if (std::isfinite(windingSlope[c]))
    {
      windingAtReference[c] = evaluate(referencePoint(c), error);
      windingError[c] = static_cast<float>(error);
    }
  };
  evaluateReference(0);
  while (!queue.empty())
  {
    const size_t c = queue.front();
    queue.pop_front();
    forEachFaceNeighbour(c, [&](size_t d, const int*) {
      if (seen[d])
        return;
      seen[d] = 1;
      queue.push_back(d);
      if (carryWinding(c, d))
        return;
      bool carried = false;
      forEachFaceNeighbour(d, [&](size_t e, const int*) { carried = carried || (e != c && seen[e] && carryWinding(e, d)); });
      if (!carried)
        evaluateReference(d);
    });
  }
}

bool SurfaceDomain::Impl::carryWinding(size_t c, size_t d)
{
  constexpr float kMaxError = 0.2f;
  const Vec3 from = referencePoint(c), to = referencePoint(d);
  const float error = windingError[c] + std::max(windingSlope[c], windingSlope[d]) * static_cast<float>(norm(to - from));
  if (!std::isfinite(error))
    return false;
  const std::optional<int> crossed = signedCrossings(toCgal(from), toCgal(to), c, d);
  // the error may grow while it cannot take w across 1/2 (far from holes w stays near 0 or 1)
  if (!crossed || error > std::max(kMaxError, static_cast<float>(std::abs(windingAtReference[c] + *crossed - 0.5)) - kMaxError))
    return false;
  windingAtReference[d] = windingAtReference[c] + *crossed;
  windingError[d] = error;
  return true;
}

void SurfaceDomain::Impl::boundWindingSlopes()
{
  // a bound over a block of 4^3 cells holds in each of them: one call per block, and per cell only
  // in blocks where it is infinite (the border passes through them)
  constexpr int kBlock = 4;
  for (int k0 = 0; k0 < n[2]; k0 += kBlock)
    for (int j0 = 0; j0 < n[1]; j0 += kBlock)
      for (int i0 = 0; i0 < n[0]; i0 += kBlock)
      {
        const int i1 = std::min(i0 + kBlock, n[0]) - 1, j1 = std::min(j0 + kBlock, n[1]) - 1, k1 = std::min(k0 + kBlock, n[2]) - 1;
        BoundingBox block = cellBox(i0, j0, k0, cellEps);
        block.add(cellBox(i1, j1, k1, cellEps));
        const double blockBound = winding->gradientBound(block);
        for (int k = k0; k <= k1; ++k)
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
              windingSlope[cellIndex(i, j, k)] = static_cast<float>(
                std::isfinite(blockBound) ? blockBound : winding->gradientBound(cellBox(i, j, k, cellEps)));
      }
}

void SurfaceDomain::Impl::windingCrossings(const Vec3& a, const Vec3& b, std::vector<double>& ts, size_t firstHit) const
{
  // clip ab to the box: outside it nothing is inside
  const Vec3 d = b - a;
  double t0 = 0.0, t1 = 1.0;
  if (!box.clip(a, d, t0, t1))
    return;
  ts.push_back(t0);
  ts.push_back(t1);
  // between two triangle hits the winding number is continuous: look for where it passes 1/2
  std::vector<double> ends{ t0, t1 };
  for (size_t i = firstHit; i < ts.size(); ++i)
    if (ts[i] > t0 && ts[i] < t1)
      ends.push_back(ts[i]);
  std::sort(ends.begin(), ends.end());
  const double length = norm(d);
  for (size_t e = 0; e + 1 < ends.size(); ++e)
  {
    const double lo = ends[e], hi = ends[e + 1];
    if (!(hi > lo))
      continue;
    Sample from{ lo + 1e-3 * (hi - lo) }, to{ hi - 1e-3 * (hi - lo) };
    from.w = windingEstimate(lerp(a, b, from.t), from.error);
    to.w = windingEstimate(lerp(a, b, to.t), to.error);
    passes(a, b, length, from, to, 0, ts);
  }
}

void SurfaceDomain::Impl::passes(const Vec3& a, const Vec3& b, double length, Sample lo, Sample hi, int depth,
  std::vector<double>& ts) const
{
  constexpr int kMaxDepth = 2; // 4 pieces where the bound cannot rule a pass out
  // w changes by at most L |dt| along the piece: no pass when both ends lie certainly on one side
  // and |w - 1/2| at the ends adds up to more than that
  auto certain = [](const Sample& s) { return std::abs(s.w - 0.5) - s.error - kApproximation; };
  auto sharpen = [&](Sample& s) {
    if (s.error > kApproximation)
      s.w = evaluate(lerp(a, b, s.t), s.error);
  };
  for (int round = 0; round < 2; ++round)
  {
    if (certain(lo) > 0 && certain(hi) > 0 && (lo.w > 0.5) == (hi.w > 0.5))
    {
      BoundingBox piece;
      piece.add(lerp(a, b, lo.t));
      piece.add(lerp(a, b, hi.t));
      if (certain(lo) + certain(hi) > winding->gradientBound(piece) * (hi.t - lo.t) * length)
        return;
    }
    if (lo.error <= kApproximation && hi.error <= kApproximation)
      break;
    sharpen(lo); // the grid's estimates could not decide: evaluations
    sharpen(hi);
  }
  if (depth < kMaxDepth)
  {
    Sample mid{ 0.5 * (lo.t + hi.t) };
    mid.w = evaluate(lerp(a, b, mid.t), mid.error);
    passes(a, b, length, lo, mid, depth + 1, ts);
    passes(a, b, length, mid, hi, depth + 1, ts);
    return;
  }
  auto side = [&](const Sample& s) {
    return decides(s.w, s.error) ? s.w > 0.5 : windingAt(lerp(a, b, s.t)) > 0.5;
  };
  const bool insideLo = side(lo);
  if (insideLo == side(hi))
    return;
  double x = lo.t, y = hi.t;
  while (y - x > 1e-12 * (1.0 + std::abs(y)))
  {
    const double mid = 0.5 * (x + y);
    ((windingAt(lerp(a, b, mid)) > 0.5) == insideLo ? x : y) = mid;
  }
  ts.push_back(y);
}
}
