// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelEdgeSharpening.h"

#include "SmallLinearSystem.h"
#include "TrilinearSurfaceFit.h"
#include "Vec3.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace omesh
{
namespace
{
constexpr double kDegree = M_PI / 180.0;
constexpr double kExplainedWithin = 0.6; ///< voxels along a sample's edge: "explained" by a face
constexpr int kMaxFaces = 3;
constexpr double kEdgeReach = 2.5; ///< voxels: an edge voxel's faces meet within this of it

/// A staircase sample: the midpoint of a voxel edge from the label to another, the smooth
/// estimate's outward normal there and the edge's axis.
struct Sample
{
  Vec3 point, normal;
  int axis = 0;
};

/// A plane: outward unit normal, a point on it, the samples it was fitted to.
struct Face
{
  Vec3 normal, point;
  int count = 0;
  double inside(const Vec3& p) const { return dot(normal, point - p); } ///< signed distance, positive inside
};

/// A voxel near where the zero set bends sharply: the faces found around it (none where they do
/// not explain the staircase or make no edge), the merged planes they belong to.
struct Candidate
{
  size_t voxel = 0;
  std::array<Face, kMaxFaces> faces;
  std::array<int, kMaxFaces> plane{ -1, -1, -1 };
  int count = 0;
  bool fitted = false, edge = false, nearEdge = false;
};

/// The unit eigenvector of the smallest eigenvalue of the symmetric matrix c (cyclic Jacobi).
Vec3 leastEigenvector(std::array<std::array<double, 3>, 3> c)
{
  std::array<std::array<double, 3>, 3> v{ { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } } };
  for (int sweep = 0; sweep < 12; ++sweep)
  {
    const double off = c[0][1] * c[0][1] + c[0][2] * c[0][2] + c[1][2] * c[1][2];
    if (off < 1e-24 * (c[0][0] * c[0][0] + c[1][1] * c[1][1] + c[2][2] * c[2][2]) + 1e-300)
      break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q)
      {
        if (std::abs(c[p][q]) < 1e-300)
          continue;
        const double theta = 0.5 * (c[q][q] - c[p][p]) / c[p][q];
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double cs = 1.0 / std::sqrt(t * t + 1.0), sn = t * cs;
        for (int k = 0; k < 3; ++k) // c <- J^T c J, v <- v J
        {
          const double ckp = c[k][p], ckq = c[k][q];
          c[k][p] = cs * ckp - sn * ckq;
          c[k][q] = sn * ckp + cs * ckq;
        }
        for (int k = 0; k < 3; ++k)
        {
          const double cpk = c[p][k], cqk = c[q][k];
          c[p][k] = cs * cpk - sn * cqk;
          c[q][k] = sn * cpk + cs * cqk;
        }
        for (int k = 0; k < 3; ++k)
        {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = cs * vkp - sn * vkq;
          v[k][q] = sn * vkp + cs * vkq;
        }
      }
  }
  const int m = c[0][0] <= c[1][1] && c[0][0] <= c[2][2] ? 0 : (c[1][1] <= c[2][2] ? 1 : 2);
  return { v[0][m], v[1][m], v[2][m] };
}

/// The least-squares plane through `members` (indices into samples), its normal on the side of
/// `towards`; count 0 when too few.
Face fitPlane(const std::vector<Sample>& samples, const std::vector<int>& members, const Vec3& towards, int minimum)
{
  Face f;
  if (static_cast<int>(members.size()) < minimum)
    return f;
  for (int i : members)
    f.point = f.point + samples[i].point;
  f.point = (1.0 / members.size()) * f.point;
  std::array<std::array<double, 3>, 3> c{};
  for (int i : members)
  {
    const Vec3 d = samples[i].point - f.point;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        c[a][b] += d[a] * d[b];
  }
  f.normal = leastEigenvector(c);
  if (dot(f.normal, towards) < 0)
    f.normal = -1.0 * f.normal;
  f.count = static_cast<int>(members.size());
  return f;
}

/// +1: the faces bound a convex edge or corner (each lies inside the others' half-spaces), -1 a
/// concave one, 0 neither.
int kindOf(const Face* faces, int count)
{
  int kind = 0;
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j)
    {
      const double a = dot(faces[i].normal, faces[j].point - faces[i].point);
      const double b = dot(faces[j].normal, faces[i].point - faces[j].point);
      const int pair = a < 0 && b < 0 ? 1 : a > 0 && b > 0 ? -1 : 0;
      if (pair == 0 || (kind != 0 && pair != kind))
        return 0;
      kind = pair;
    }
  return kind;
}

/// Whether every two of the faces meet along a line within `reach` of p: the two sides of a thin
/// layer face away from each other at up to 180 degrees, but meet far away if at all.
bool meetNear(const Face* faces, int count, const Vec3& p, double reach)
{
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j)
    {
      // the point of the line nearest p: p + a n_i + b n_j
      const double g = dot(faces[i].normal, faces[j].normal), det = 1.0 - g * g;
      if (det < 1e-6)
        return false;
      const double ri = dot(faces[i].normal, faces[i].point - p), rj = dot(faces[j].normal, faces[j].point - p);
      const double a = (ri - g * rj) / det, b = (rj - g * ri) / det;
      if (a * a + b * b + 2.0 * a * b * g > reach * reach)
        return false;
    }
  return true;
}

/// The distance at p to the faces' intersection (kind +1) or union (-1), positive inside.
double distanceTo(const Face* faces, int count, int kind, const Vec3& p)
{
  double d = faces[0].inside(p);
  for (int i = 1; i < count; ++i)
    d = kind > 0 ? std::min(d, faces[i].inside(p)) : std::max(d, faces[i].inside(p));
  return d;
}

/// How a plane's member faces bend away from it: a height quadric h = c0 + c1 u + c2 w + c3 u^2 +
/// c4 u w + c5 w^2 (u, w along the plane, h across) fitted by least squares to the faces' points,
/// each weighted by its samples; the directions the points do not spread along are held flat (a
/// small ridge). The faces' points come from the staircase's own samples, whose errors average out
/// (their normals come from the smoothed estimate, which tilts near every edge).
class Bending
{
public:
  void add(const Vec3& normal, double weight, const Vec3& offset)
  {
    if (!started_)
      perpendicularPair(normal, u_, w_), started_ = true;
    const double u = dot(offset, u_), w = dot(offset, w_), h = dot(offset, normal);
    const double terms[6] = { 1.0, u, w, u * u, u * w, w * w };
    hh_ += weight * h * h;
    for (int i = 0; i < 6; ++i)
    {
      rhs_[i] += weight * terms[i] * h;
      for (int j = 0; j < 6; ++j)
        m_[i][j] += weight * terms[i] * terms[j];
    }
  }
  /// The least-squares plane through the points (h = c0 + c1 u + c2 w, the tilts held to 0 where
  /// the points do not spread), as a normal and a point, and the points' RMS distance from it.
  double plane(const Vec3& normal, const Vec3& centre, Vec3& fittedNormal, Vec3& fittedPoint) const
  {
    const double ridge = 1e-6 * (m_[1][1] + m_[2][2]) + 1e-300;
    double m[3][4];
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
        m[i][j] = m_[i][j] + (i == j && i > 0 ? ridge : 0.0);
      m[i][3] = rhs_[i];
    }
    double c[3];
    if (!solveLinear<3>(m, c))
    {
      fittedNormal = normal;
      fittedPoint = centre;
      return std::sqrt(hh_ / std::max(m_[0][0], 1e-300));
    }
    fittedNormal = normal - c[1] * u_ - c[2] * w_;
    fittedNormal = (1.0 / norm(fittedNormal)) * fittedNormal;
    fittedPoint = centre + c[0] * normal;
    const double squares = hh_ - (c[0] * rhs_[0] + c[1] * rhs_[1] + c[2] * rhs_[2]);
    return std::sqrt(std::max(squares, 0.0) / std::max(m_[0][0], 1e-300));
  }

  /// The largest principal curvature's size (1 / radius, world units).
  double largest() const
  {
    double m[6][7];
    double trace = 0.0;
    for (int i = 0; i < 6; ++i)
      trace += m_[i][i];
    for (int i = 0; i < 6; ++i)
    {
      for (int j = 0; j < 6; ++j)
        m[i][j] = m_[i][j] + (i == j ? 1e-9 * trace + 1e-300 : 0.0);
      m[i][6] = rhs_[i];
    }
    double c[6];
    if (!solveLinear<6>(m, c))
      return 0.0;
    const double a = 2.0 * c[3], b = c[4], d = 2.0 * c[5]; // the height's Hessian
    return std::abs(0.5 * (a + d)) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  }

private:
  bool started_ = false;
  Vec3 u_, w_;

  double m_[6][6] = {}, rhs_[6] = {}, hh_ = 0.0;
};

/// Faces kept in order, those within edgeAngle of an earlier (larger) one dropped.
void dropNearParallel(std::vector<Face>& faces, double edgeCosine)
{
  std::vector<Face> kept;
  for (const Face& f : faces)
    if (std::all_of(kept.begin(), kept.end(), [&](const Face& k) { return dot(k.normal, f.normal) <= edgeCosine; }))
      kept.push_back(f);
  faces.swap(kept);
}

/// One thread's buffers for EdgeSharpener::fitFaces.
struct FitScratch
{
  std::vector<int> near;
  std::vector<std::vector<int>> groups;
  std::vector<Vec3> sums, means;
  std::vector<Face> faces, refitted;
  std::vector<std::array<double, 3>> scales;
};

class EdgeSharpener
{
public:
  EdgeSharpener(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
    const std::vector<uint8_t>& inside, std::vector<float>& scratch, const LabelEdgeSharpeningOptions& o)
    : box_(box)
    , h_(h)
    , hMax_(std::max({ h[0], h[1], h[2] }))
    , psi_(psi)
    , inside_(inside)
    , scratch_(scratch)
    , o_(o)
    , faceCosine_(std::cos(o.faceAngle * kDegree))
    , edgeCosine_(std::cos(o.edgeAngle * kDegree))
  {
    for (int a = 0; a < 3; ++a)
      window_[a] = static_cast<int>(std::ceil((o.reach + 0.5) * hMax_ / h[a]));
  }

  /// Edges first where the zero set bends sharply, then the faces around them, then the planes:
  /// a label without flat faces meeting at an edge costs little more than the first look.
  std::size_t run(double delta)
  {
    if (!markBent())
      return 0;
    runningMaximum(box_, 1, scratch_);
    addCandidates(0.75); // the voxels next to the zero set find the edges
    collectSamples();
    fitCandidates();
    // the edges' own faces merged first: edges between curved faces (a rim where a flat face
    // meets a round one) are dropped before the faces around them are fitted
    for (Candidate& c : candidates_)
      c.nearEdge = c.edge;
    mergeFaces(1.5 * o_.flatCurvature); // members along a line only: a noisier turn
    for (Candidate& c : candidates_)
      c.edge = c.edge && std::all_of(c.plane.begin(), c.plane.begin() + c.count, [&](int k) { return planes_[k].count > 0; });
    if (!markEdges(o_.near + o_.vote))
      return 0;
    addCandidates(o_.band);
    fitCandidates();
    markEdges(o_.near);
    for (Candidate& c : candidates_)
      c.nearEdge = scratch_[c.voxel] > 0;
    mergeFaces(o_.flatCurvature);
    return replace(delta);
  }

private:
  Vec3 centre(size_t v) const
  {
    int p[3];
    box_.coordinates(v, p);
    return { (box_.lo[0] + p[0]) * h_[0], (box_.lo[1] + p[1]) * h_[1], (box_.lo[2] + p[2]) * h_[2] };
  }

  /// psi's gradient at voxel v (central differences, one-sided at the box's faces).
  Vec3 gradient(size_t v) const
  {
    int p[3];
    box_.coordinates(v, p);
    Vec3 g;
    for (int a = 0; a < 3; ++a)
    {
      const size_t lo = p[a] > 0 ? v - box_.stride[a] : v, hi = p[a] + 1 < box_.n[a] ? v + box_.stride[a] : v;
      const int span = (p[a] > 0) + (p[a] + 1 < box_.n[a]);
      g[a] = span ? (psi_[hi] - psi_[lo]) / (span * h_[a]) : 0.0;
    }
    return g;
  }

  /// scratch_: 1 where the zero set bends sharply (|Laplacian psi| per coarsest voxel, within half
  /// a voxel of it), else 0. False when nowhere.
  bool markBent()
  {
    scratch_.assign(box_.size, 0.0f);
    const size_t chunks = chunkCount(box_.size, 1 << 16);
    std::vector<char> any(chunks, 0);
    forEachChunk(box_.size, chunks, [&](size_t chunk, size_t begin, size_t end) {
      for (size_t v = begin; v < end; ++v)
      {
        // near the zero set, off the ridge in the middle of a thin layer (where psi kinks as well)
        if (std::abs(psi_[v]) > 0.5 * hMax_ || norm(gradient(v)) < 0.5)
          continue;
        int p[3];
        box_.coordinates(v, p);
        double lap = 0.0;
        for (int a = 0; a < 3; ++a)
        {
          const size_t lo = p[a] > 0 ? v - box_.stride[a] : v, hi = p[a] + 1 < box_.n[a] ? v + box_.stride[a] : v;
          lap += (static_cast<double>(psi_[hi]) - 2.0 * psi_[v] + psi_[lo]) / (h_[a] * h_[a]);
        }
        if (std::abs(lap) * hMax_ >= o_.bentCurvature)
          any[chunk] = 1, scratch_[v] = 1.0f;
      }
    });
    return std::find(any.begin(), any.end(), 1) != any.end();
  }

  /// Candidates added: the voxels scratch_ marks with |psi| up to `band` coarsest voxels (kept in
  /// voxel order).
  void addCandidates(double band)
  {
    std::vector<Candidate> added;
    size_t next = 0;
    for (size_t v = 0; v < box_.size; ++v)
    {
      while (next < candidates_.size() && candidates_[next].voxel < v)
        ++next;
      if (scratch_[v] > 0 && std::abs(psi_[v]) <= band * hMax_ && (next == candidates_.size() || candidates_[next].voxel != v))
      {
        added.emplace_back();
        added.back().voxel = v;
      }
    }
    const size_t old = candidates_.size();
    candidates_.insert(candidates_.end(), added.begin(), added.end());
    std::inplace_merge(candidates_.begin(), candidates_.begin() + old, candidates_.end(),
      [](const Candidate& a, const Candidate& b) { return a.voxel < b.voxel; });
  }


  /// scratch_: the edge voxels found so far, grown by r. False when there is none.
  bool markEdges(int r)
  {
    scratch_.assign(box_.size, 0.0f);
    bool any = false;
    for (const Candidate& c : candidates_)
      if (c.edge)
        any = true, scratch_[c.voxel] = 1.0f;
    if (any)
      runningMaximum(box_, r, scratch_);
    return any;
  }

  void collectSamples();
  void gather(size_t v, std::vector<int>& out) const;
  void groupByNormal(const Vec3& own, FitScratch& f) const;
  void residualScales(FitScratch& f) const;
  std::pair<size_t, double> nearestFace(int s, const FitScratch& f) const;
  void fitFaces(Candidate& c, FitScratch& f) const;
  void fitCandidates();
  void mergeFaces(double flatCurvature);
  std::size_t replace(double delta);
  bool planesAround(size_t v, std::vector<int>& ids) const;
  int surfaceOf(const std::vector<int>& ids, std::vector<Face>& faces) const;

  const VoxelBox& box_;
  std::array<double, 3> h_;
  double hMax_;
  std::vector<float>& psi_;
  const std::vector<uint8_t>& inside_;
  std::vector<float>& scratch_;
  LabelEdgeSharpeningOptions o_;
  double faceCosine_, edgeCosine_;
  std::array<int, 3> window_{};
  std::vector<Sample> samples_;      ///< in the order of their voxels
  std::vector<size_t> sampleVoxel_;  ///< the voxel of each sample
  std::vector<Candidate> candidates_; ///< in voxel order
  std::vector<Face> planes_;         ///< merged over the label (count 0: dropped)
  std::vector<bool> blocking_;       ///< per plane: dropped, but no stray
};

/// The staircase's samples, each filed under the label's voxel it starts from (chunks of voxels
/// in parallel, joined in order).
void EdgeSharpener::collectSamples()
{
  const size_t chunks = chunkCount(box_.size, 1 << 16);
  std::vector<std::vector<Sample>> found(chunks);
  std::vector<std::vector<size_t>> voxels(chunks);
  forEachChunk(box_.size, chunks, [&](size_t chunk, size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v)
    {
      if (!inside_[v] || psi_[v] > 2.0 * hMax_) // (a voxel next to another label lies within a voxel of it)
        continue;
      int p[3];
      box_.coordinates(v, p);
      for (int a = 0; a < 3; ++a)
        for (int side = -1; side <= 1; side += 2)
        {
          if ((side < 0 && p[a] == 0) || (side > 0 && p[a] + 1 == box_.n[a]))
            continue;
          const size_t u = side < 0 ? v - box_.stride[a] : v + box_.stride[a];
          if (inside_[u])
            continue;
          const Vec3 g = gradient(v) + gradient(u);
          if (!(norm(g) > 0))
            continue;
          Sample s{ centre(v), (-1.0 / norm(g)) * g, a };
          s.point[a] += 0.5 * side * h_[a];
          found[chunk].push_back(s);
          voxels[chunk].push_back(v);
        }
    }
  });
  for (size_t chunk = 0; chunk < chunks; ++chunk)
  {
    samples_.insert(samples_.end(), found[chunk].begin(), found[chunk].end());
    sampleVoxel_.insert(sampleVoxel_.end(), voxels[chunk].begin(), voxels[chunk].end());
  }
}

/// The samples within reach of voxel v (indices into samples_).
void EdgeSharpener::gather(size_t v, std::vector<int>& out) const
{
  out.clear();
  int p[3];
  box_.coordinates(v, p);
  const Vec3 c = centre(v);
  const double r2 = (o_.reach + 0.5) * (o_.reach + 0.5) * hMax_ * hMax_;
  for (int z = std::max(p[2] - window_[2], 0); z <= std::min(p[2] + window_[2], box_.n[2] - 1); ++z)
    for (int y = std::max(p[1] - window_[1], 0); y <= std::min(p[1] + window_[1], box_.n[1] - 1); ++y)
    {
      const size_t row = box_.stride[2] * z + box_.stride[1] * y;
      const size_t x0 = row + std::max(p[0] - window_[0], 0), x1 = row + std::min(p[0] + window_[0], box_.n[0] - 1);
      for (auto s = std::lower_bound(sampleVoxel_.begin(), sampleVoxel_.end(), x0); s != sampleVoxel_.end() && *s <= x1; ++s)
      {
        const int i = static_cast<int>(s - sampleVoxel_.begin());
        const Vec3 d = samples_[i].point - c;
        if (dot(d, d) <= r2)
          out.push_back(i);
      }
    }
}

/// The samples grouped by normal: each joins the group whose mean normal is nearest within
/// faceAngle, or starts a group; the first group starts at `own` (the voxel's own normal).
void EdgeSharpener::groupByNormal(const Vec3& own, FitScratch& f) const
{
  f.groups.assign(1, {});
  f.sums.assign(1, Vec3{});
  f.means.assign(1, own);
  for (int s : f.near)
  {
    const Vec3& n = samples_[s].normal;
    size_t best = f.means.size();
    double bestCosine = faceCosine_;
    for (size_t k = 0; k < f.means.size(); ++k)
    {
      const double c = dot(f.means[k], n);
      if (c >= bestCosine)
        bestCosine = c, best = k;
    }
    if (best == f.means.size())
    {
      f.groups.emplace_back();
      f.sums.emplace_back();
      f.means.emplace_back();
    }
    f.sums[best] = f.sums[best] + n;
    f.means[best] = (1.0 / norm(f.sums[best])) * f.sums[best];
    f.groups[best].push_back(s);
  }
}

/// Per face, 1 / (the share of a unit step along each axis that it takes across the face, in
/// voxels of that axis): residual(sample) = |n . (p - c)| x this along the sample's axis.
void EdgeSharpener::residualScales(FitScratch& f) const
{
  f.scales.resize(f.faces.size());
  for (size_t k = 0; k < f.faces.size(); ++k)
    for (int a = 0; a < 3; ++a)
      f.scales[k][a] = 1.0 / (std::max(std::abs(f.faces[k].normal[a]), 0.3) * h_[a]);
}

/// The face sample s lies nearest to along its voxel edge, and how far (voxels of that axis).
std::pair<size_t, double> EdgeSharpener::nearestFace(int s, const FitScratch& f) const
{
  const Sample& sample = samples_[s];
  std::pair<size_t, double> best{ 0, std::numeric_limits<double>::infinity() };
  for (size_t k = 0; k < f.faces.size(); ++k)
  {
    const double r = std::abs(dot(f.faces[k].normal, sample.point - f.faces[k].point)) * f.scales[k][sample.axis];
    if (r < best.second)
      best = { k, r };
  }
  return best;
}

/// The faces around candidate c: samples grouped by normal, a plane fitted to each group, then
/// each sample given to the plane it lies nearest (a few rounds).
void EdgeSharpener::fitFaces(Candidate& c, FitScratch& f) const
{
  c.fitted = true;
  gather(c.voxel, f.near);
  const Vec3 g = gradient(c.voxel);
  if (f.near.empty() || !(norm(g) > 0))
    return;
  groupByNormal((-1.0 / norm(g)) * g, f);
  f.faces.clear();
  for (size_t k = 0; k < f.groups.size(); ++k)
  {
    const Face face = fitPlane(samples_, f.groups[k], f.means[k], o_.minimumSamples);
    if (face.count > 0 && dot(face.normal, f.means[k]) >= faceCosine_)
      f.faces.push_back(face);
  }
  const auto byCount = [](const Face& a, const Face& b) { return a.count > b.count; };
  std::stable_sort(f.faces.begin(), f.faces.end(), byCount);
  if (f.faces.size() > kMaxFaces)
    f.faces.resize(kMaxFaces);
  for (int round = 0; round < 3 && f.faces.size() >= 2; ++round)
  {
    dropNearParallel(f.faces, edgeCosine_);
    if (f.faces.size() < 2)
      break;
    residualScales(f);
    f.groups.resize(f.faces.size());
    for (std::vector<int>& members : f.groups)
      members.clear();
    for (int s : f.near)
    {
      const auto nearest = nearestFace(s, f);
      if (nearest.second <= o_.trim)
        f.groups[nearest.first].push_back(s);
    }
    f.refitted.clear();
    for (size_t k = 0; k < f.faces.size(); ++k)
    {
      const Face face = fitPlane(samples_, f.groups[k], f.faces[k].normal, o_.minimumSamples);
      if (face.count > 0)
        f.refitted.push_back(face);
    }
    f.faces.swap(f.refitted);
    std::stable_sort(f.faces.begin(), f.faces.end(), byCount);
  }
  residualScales(f);
  size_t explained = 0;
  for (int s : f.near)
    explained += !f.faces.empty() && nearestFace(s, f).second <= kExplainedWithin;
  dropNearParallel(f.faces, edgeCosine_);
  const bool planar = explained >= o_.explained * f.near.size();
  const int count = static_cast<int>(f.faces.size());
  c.edge = count >= 2 && planar && kindOf(f.faces.data(), count) != 0 &&
    meetNear(f.faces.data(), count, centre(c.voxel), kEdgeReach * hMax_);
  if (planar && (count == 1 || c.edge)) // faces that do not explain the staircase, or make no edge, say nothing
  {
    c.count = count;
    std::copy(f.faces.begin(), f.faces.end(), c.faces.begin());
  }
}

void EdgeSharpener::fitCandidates()
{
  forEachChunk(candidates_.size(), chunkCount(candidates_.size(), 256), [&](size_t, size_t begin, size_t end) {
    FitScratch scratch;
    for (size_t i = begin; i < end; ++i)
      if (!candidates_[i].fitted && std::abs(psi_[candidates_[i].voxel]) <= 1.5 * hMax_)
        fitFaces(candidates_[i], scratch);
  });
}

/// The faces of the voxels near edges merged into planes (largest first: each joins the first plane
/// within mergeAngle and mergeOffset), their normals and points averaged by sample count; faces of
/// small planes dropped.
void EdgeSharpener::mergeFaces(double flatCurvature)
{
  planes_.clear();
  blocking_.clear();
  struct Ref
  {
    int count;
    size_t candidate;
    int face;
  };
  std::vector<Ref> refs;
  for (size_t i = 0; i < candidates_.size(); ++i)
    if (candidates_[i].nearEdge)
      for (int k = 0; k < candidates_[i].count; ++k)
        refs.push_back({ candidates_[i].faces[k].count, i, k });
  std::stable_sort(refs.begin(), refs.end(), [](const Ref& a, const Ref& b) { return a.count > b.count; });
  const double mergeCosine = std::cos(o_.mergeAngle * kDegree), offset = o_.mergeOffset * hMax_;
  std::vector<Vec3> normalSum, pointSum;
  std::vector<double> weight;
  std::vector<int> voxels;
  for (const Ref& r : refs)
  {
    const Face& f = candidates_[r.candidate].faces[r.face];
    size_t k = 0;
    for (; k < weight.size(); ++k)
    {
      const Vec3 n = (1.0 / norm(normalSum[k])) * normalSum[k];
      if (dot(n, f.normal) >= mergeCosine && std::abs(dot(n, f.point - (1.0 / weight[k]) * pointSum[k])) <= offset)
        break;
    }
    if (k == weight.size())
    {
      normalSum.emplace_back();
      pointSum.emplace_back();
      weight.push_back(0.0);
      voxels.push_back(0);
    }
    ++voxels[k];
    normalSum[k] = normalSum[k] + f.count * f.normal;
    pointSum[k] = pointSum[k] + f.count * f.point;
    weight[k] += f.count;
    candidates_[r.candidate].plane[r.face] = static_cast<int>(k);
  }
  const double largest = weight.empty() ? 0.0 : *std::max_element(weight.begin(), weight.end());
  // a face bent by a curved surface (two balls crossing: sharp where they meet, curved elsewhere;
  // a bone's shaft, round one way and straight the other) gives members that each look flat but
  // drift off any one plane and bend with their place on it
  std::vector<Bending> bending(weight.size());
  for (const Ref& r : refs)
  {
    const Face& f = candidates_[r.candidate].faces[r.face];
    const size_t k = static_cast<size_t>(candidates_[r.candidate].plane[r.face]);
    const Vec3 n = (1.0 / norm(normalSum[k])) * normalSum[k];
    const Vec3 offset = f.point - (1.0 / weight[k]) * pointSum[k];
    bending[k].add(n, f.count, offset);
  }
  for (size_t k = 0; k < weight.size(); ++k)
  {
    // the plane through its faces' points (the mean of their normals tilts a long face by a
    // degree or so, which is a fifth of a voxel at its ends)
    const Vec3 mean = (1.0 / norm(normalSum[k])) * normalSum[k], centre = (1.0 / weight[k]) * pointSum[k];
    Vec3 normal, point;
    const double drift = bending[k].plane(mean, centre, normal, point);
    const bool flat = drift <= o_.flatDrift * hMax_ && bending[k].largest() * hMax_ <= flatCurvature;
    const bool large = voxels[k] >= o_.planeVoxels && (weight[k] >= o_.significant * largest || voxels[k] >= o_.largeVoxels);
    planes_.push_back({ normal, point, flat && large ? static_cast<int>(weight[k]) : 0 });
    // dropped, yet found around too many voxels to be a stray fit at a corner: a curved face or a
    // small one, whose neighbours' planes alone would not describe the surface there
    blocking_.push_back(!(flat && large) && voxels[k] >= o_.blockingVoxels);
  }
  // ... unless it lies along a plane that is kept (the same face, split off by the merge)
  for (size_t k = 0; k < planes_.size(); ++k)
    for (size_t j = 0; j < planes_.size() && blocking_[k]; ++j)
      if (planes_[j].count > 0 && dot(planes_[j].normal, planes_[k].normal) >= std::cos(2.0 * o_.mergeAngle * kDegree) &&
        std::abs(planes_[j].inside(planes_[k].point)) <= 2.0 * o_.mergeOffset * hMax_)
        blocking_[k] = false;
}

/// The planes (ids into planes_) of the voxels near an edge within `vote` of voxel v, stray ones
/// left out; false when one of their faces belongs to a dropped plane that is no stray (the planes
/// that are left would not describe the surface there).
bool EdgeSharpener::planesAround(size_t v, std::vector<int>& ids) const
{
  ids.clear();
  int p[3];
  box_.coordinates(v, p);
  for (int z = std::max(p[2] - o_.vote, 0); z <= std::min(p[2] + o_.vote, box_.n[2] - 1); ++z)
    for (int y = std::max(p[1] - o_.vote, 0); y <= std::min(p[1] + o_.vote, box_.n[1] - 1); ++y)
    {
      const size_t row = box_.stride[2] * z + box_.stride[1] * y;
      auto c = std::lower_bound(candidates_.begin(), candidates_.end(), row + std::max(p[0] - o_.vote, 0),
        [](const Candidate& a, size_t x) { return a.voxel < x; });
      for (; c != candidates_.end() && c->voxel <= row + std::min(p[0] + o_.vote, box_.n[0] - 1); ++c)
        if (c->nearEdge)
          for (int k = 0; k < c->count; ++k)
          {
            if (blocking_[c->plane[k]])
              return false;
            if (planes_[c->plane[k]].count > 0)
              ids.push_back(c->plane[k]);
          }
    }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return !ids.empty();
}

/// Each voxel near an edge: the distance to the planes around it (their intersection at a convex
/// edge or corner, their union at a concave one), where it is within a voxel of psi and on the
/// voxel's side (or nearly: then held to delta).
/// The planes `ids` as one surface: their faces, the largest first, those within edgeAngle of a
/// larger one dropped, and their kind (+1 intersection, -1 union; 0: neither).
int EdgeSharpener::surfaceOf(const std::vector<int>& ids, std::vector<Face>& faces) const
{
  faces.clear();
  for (int id : ids)
    faces.push_back(planes_[id]);
  std::stable_sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.count > b.count; });
  dropNearParallel(faces, edgeCosine_);
  return faces.size() == 1 ? 1 : kindOf(faces.data(), static_cast<int>(faces.size()));
}

std::size_t EdgeSharpener::replace(double delta)
{
  const size_t chunks = chunkCount(candidates_.size(), 1024);
  std::vector<size_t> changed(chunks, 0);
  std::vector<float> value(candidates_.size(), std::numeric_limits<float>::quiet_NaN());
  std::vector<std::vector<int>> around(candidates_.size());
  forEachChunk(candidates_.size(), chunks, [&](size_t chunk, size_t begin, size_t end) {
    std::vector<int> ids;
    std::vector<Face> faces;
    for (size_t i = begin; i < end; ++i)
    {
      const size_t v = candidates_[i].voxel;
      if (!candidates_[i].nearEdge || !planesAround(v, ids))
        continue;
      const int kind = surfaceOf(ids, faces);
      if (kind == 0)
        continue;
      const double d = distanceTo(faces.data(), static_cast<int>(faces.size()), kind, centre(v));
      const double slack = 0.2 * hMax_;
      if (std::abs(d - psi_[v]) > 1.2 * hMax_ || (inside_[v] ? d < -slack : d > slack))
        continue;
      value[i] = static_cast<float>(inside_[v] ? std::max(d, delta) : std::min(d, -delta));
      around[i] = ids;
      ++changed[chunk];
    }
  });
  std::vector<size_t> free, freeCandidate;
  for (size_t i = 0; i < candidates_.size(); ++i)
    if (!std::isnan(value[i]))
    {
      psi_[candidates_[i].voxel] = value[i];
      free.push_back(candidates_[i].voxel);
      freeCandidate.push_back(i);
    }
  // the planes' distances at the voxel centres chamfer every convex edge between them: fitted
  // instead to the planes between the centres, each cell to the planes of all its free corners
  fitTrilinearToSurface(box_, h_, psi_, inside_, delta, free, [&](const std::vector<size_t>& corners) {
    std::vector<int> ids;
    for (size_t voxel : corners)
    {
      const std::vector<int>& mine = around[freeCandidate[static_cast<size_t>(std::lower_bound(free.begin(), free.end(), voxel) - free.begin())]];
      ids.insert(ids.end(), mine.begin(), mine.end());
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    std::vector<Face> faces;
    const int kind = surfaceOf(ids, faces);
    return kind == 0 ? std::function<double(const Vec3&)>()
                     : [faces, kind](const Vec3& p) { return distanceTo(faces.data(), static_cast<int>(faces.size()), kind, p); };
  });
  return std::accumulate(changed.begin(), changed.end(), size_t{ 0 });
}
}

std::size_t sharpenLabelEdges(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, double delta, std::vector<float>& scratch, const LabelEdgeSharpeningOptions& options)
{
  return EdgeSharpener(box, h, psi, inside, scratch, options).run(delta);
}
}
