// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelEdgeSharpening.h"

#include "Vec3.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace omesh
{
namespace
{
constexpr double kDegree = M_PI / 180.0;
constexpr double kExplainedWithin = 0.6; ///< voxels along a sample's edge: "explained" by a face
constexpr int kMaxFaces = 3;

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

/// The faces found around one voxel, and the merged planes they belong to.
struct LocalFaces
{
  std::array<Face, kMaxFaces> faces;
  std::array<int, kMaxFaces> plane{ -1, -1, -1 };
  int count = 0;
  bool edge = false;
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

/// The distance at p to the faces' intersection (kind +1) or union (-1), positive inside.
double distanceTo(const Face* faces, int count, int kind, const Vec3& p)
{
  double d = faces[0].inside(p);
  for (int i = 1; i < count; ++i)
    d = kind > 0 ? std::min(d, faces[i].inside(p)) : std::max(d, faces[i].inside(p));
  return d;
}

/// Faces kept in order, those within edgeAngle of an earlier (larger) one dropped.
void dropNearParallel(std::vector<Face>& faces, double edgeCosine)
{
  std::vector<Face> kept;
  for (const Face& f : faces)
    if (std::all_of(kept.begin(), kept.end(), [&](const Face& k) { return dot(k.normal, f.normal) <= edgeCosine; }))
      kept.push_back(f);
  faces.swap(kept);
}

class EdgeSharpener
{
public:
  EdgeSharpener(const VoxelBox& box, const std::array<double, 3>& h, const std::vector<float>& psi,
    const std::vector<uint8_t>& inside, const LabelEdgeSharpeningOptions& o)
    : box_(box)
    , h_(h)
    , hMax_(std::max({ h[0], h[1], h[2] }))
    , psi_(psi)
    , inside_(inside)
    , o_(o)
    , faceCosine_(std::cos(o.faceAngle * kDegree))
    , edgeCosine_(std::cos(o.edgeAngle * kDegree))
  {
    for (int a = 0; a < 3; ++a)
      window_[a] = static_cast<int>(std::ceil((o.reach + 0.5) * hMax_ / h[a]));
  }

  std::size_t run(std::vector<float>& out, double delta)
  {
    if (!findCandidates())
      return 0;
    collectSamples();
    fitCandidates();
    if (!markNearEdges())
      return 0;
    mergeFaces();
    return replace(out, delta);
  }

private:
  Vec3 centre(size_t v) const
  {
    const int p[3] = { static_cast<int>(v % box_.n[0]), static_cast<int>((v / box_.n[0]) % box_.n[1]),
      static_cast<int>(v / box_.stride[2]) };
    return { (box_.lo[0] + p[0]) * h_[0], (box_.lo[1] + p[1]) * h_[1], (box_.lo[2] + p[2]) * h_[2] };
  }
  void coordinates(size_t v, int p[3]) const
  {
    p[0] = static_cast<int>(v % box_.n[0]);
    p[1] = static_cast<int>((v / box_.n[0]) % box_.n[1]);
    p[2] = static_cast<int>(v / box_.stride[2]);
  }

  /// psi's gradient at voxel v (central differences, one-sided at the box's faces).
  Vec3 gradient(size_t v) const
  {
    int p[3];
    coordinates(v, p);
    Vec3 g;
    for (int a = 0; a < 3; ++a)
    {
      const size_t lo = p[a] > 0 ? v - box_.stride[a] : v, hi = p[a] + 1 < box_.n[a] ? v + box_.stride[a] : v;
      const int span = (p[a] > 0) + (p[a] + 1 < box_.n[a]);
      g[a] = span ? (psi_[hi] - psi_[lo]) / (span * h_[a]) : 0.0;
    }
    return g;
  }

  /// Candidates: voxels near the zero set within reach of where it bends sharply (an edge's
  /// voxels, the faces' voxels around it and those that vote for them). False when none.
  bool findCandidates()
  {
    std::vector<float> bent(box_.size, 0.0f);
    bool any = false;
    for (size_t v = 0; v < box_.size; ++v)
    {
      if (std::abs(psi_[v]) > hMax_)
        continue;
      int p[3];
      coordinates(v, p);
      double lap = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        const size_t lo = p[a] > 0 ? v - box_.stride[a] : v, hi = p[a] + 1 < box_.n[a] ? v + box_.stride[a] : v;
        lap += (static_cast<double>(psi_[hi]) - 2.0 * psi_[v] + psi_[lo]) / (h_[a] * h_[a]);
      }
      if (std::abs(lap) * hMax_ >= o_.bentCurvature)
        any = true, bent[v] = 1.0f;
    }
    if (!any)
      return false;
    runningMaximum(box_, 2 + o_.near + o_.vote, bent);
    candidateOf_.assign(box_.size, -1);
    for (size_t v = 0; v < box_.size; ++v)
      if (bent[v] > 0 && std::abs(psi_[v]) <= o_.band * hMax_)
      {
        candidateOf_[v] = static_cast<int>(candidates_.size());
        candidates_.push_back(v);
      }
    return !candidates_.empty();
  }

  /// The staircase's samples, each filed under the label's voxel it starts from.
  void collectSamples()
  {
    first_.assign(box_.size + 1, 0);
    for (size_t v = 0; v < box_.size; ++v)
    {
      first_[v] = static_cast<uint32_t>(samples_.size());
      if (!inside_[v])
        continue;
      int p[3];
      coordinates(v, p);
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
          samples_.push_back(s);
        }
    }
    first_[box_.size] = static_cast<uint32_t>(samples_.size());
  }

  /// The samples within reach of voxel v (indices into samples_).
  void gather(size_t v, std::vector<int>& out) const
  {
    out.clear();
    int p[3];
    coordinates(v, p);
    const Vec3 c = centre(v);
    const double r2 = (o_.reach + 0.5) * (o_.reach + 0.5) * hMax_ * hMax_;
    for (int z = std::max(p[2] - window_[2], 0); z <= std::min(p[2] + window_[2], box_.n[2] - 1); ++z)
      for (int y = std::max(p[1] - window_[1], 0); y <= std::min(p[1] + window_[1], box_.n[1] - 1); ++y)
      {
        const size_t row = box_.stride[2] * z + box_.stride[1] * y;
        const size_t x0 = row + std::max(p[0] - window_[0], 0), x1 = row + std::min(p[0] + window_[0], box_.n[0] - 1);
        for (uint32_t s = first_[x0]; s < first_[x1 + 1]; ++s)
        {
          const Vec3 d = samples_[s].point - c;
          if (dot(d, d) <= r2)
            out.push_back(static_cast<int>(s));
        }
      }
  }

  /// How far sample s lies from face f along its voxel edge, in voxels of that axis.
  double residual(const Sample& s, const Face& f) const
  {
    return std::abs(dot(f.normal, s.point - f.point)) / (std::max(std::abs(f.normal[s.axis]), 0.3) * h_[s.axis]);
  }

  LocalFaces fitFaces(size_t v, std::vector<int>& near, std::vector<std::vector<int>>& groups) const;
  void fitCandidates();
  bool markNearEdges();
  void mergeFaces();
  std::size_t replace(std::vector<float>& out, double delta) const;

  const VoxelBox& box_;
  std::array<double, 3> h_;
  double hMax_;
  const std::vector<float>& psi_;
  const std::vector<uint8_t>& inside_;
  LabelEdgeSharpeningOptions o_;
  double faceCosine_, edgeCosine_;
  std::array<int, 3> window_{};
  std::vector<Sample> samples_;
  std::vector<uint32_t> first_;
  std::vector<size_t> candidates_;
  std::vector<int> candidateOf_;
  std::vector<LocalFaces> local_;
  std::vector<float> nearEdge_;
  std::vector<Face> planes_; ///< merged over the label
};

/// The faces around voxel v: samples grouped by normal (those most like v's own first), a plane
/// fitted to each group, then each sample given to the plane it lies nearest (a few rounds).
LocalFaces EdgeSharpener::fitFaces(size_t v, std::vector<int>& near, std::vector<std::vector<int>>& groups) const
{
  LocalFaces result;
  gather(v, near);
  const Vec3 g = gradient(v);
  if (near.empty() || !(norm(g) > 0))
    return result;
  const Vec3 own = (-1.0 / norm(g)) * g;
  std::stable_sort(near.begin(), near.end(), [&](int a, int b) { return dot(samples_[a].normal, own) > dot(samples_[b].normal, own); });
  std::vector<Vec3> sums;
  groups.clear();
  for (int s : near)
  {
    int best = -1;
    double bestCosine = faceCosine_;
    for (size_t k = 0; k < sums.size(); ++k)
    {
      const double c = dot(sums[k], samples_[s].normal) / norm(sums[k]);
      if (c >= bestCosine)
        bestCosine = c, best = static_cast<int>(k);
    }
    if (best < 0)
    {
      best = static_cast<int>(sums.size());
      sums.emplace_back();
      groups.emplace_back();
    }
    sums[best] = sums[best] + samples_[s].normal;
    groups[best].push_back(s);
  }
  std::vector<Face> faces;
  for (size_t k = 0; k < groups.size(); ++k)
  {
    const Vec3 mean = (1.0 / norm(sums[k])) * sums[k];
    const Face f = fitPlane(samples_, groups[k], mean, o_.minimumSamples);
    if (f.count > 0 && dot(f.normal, mean) >= faceCosine_)
      faces.push_back(f);
  }
  const auto byCount = [](const Face& a, const Face& b) { return a.count > b.count; };
  std::stable_sort(faces.begin(), faces.end(), byCount);
  if (faces.size() > kMaxFaces)
    faces.resize(kMaxFaces);
  for (int round = 0; round < 3 && faces.size() >= 2; ++round)
  {
    dropNearParallel(faces, edgeCosine_);
    if (faces.size() < 2)
      break;
    groups.assign(faces.size(), {});
    for (int s : near)
    {
      size_t best = 0;
      for (size_t k = 1; k < faces.size(); ++k)
        if (residual(samples_[s], faces[k]) < residual(samples_[s], faces[best]))
          best = k;
      if (residual(samples_[s], faces[best]) <= o_.trim)
        groups[best].push_back(s);
    }
    std::vector<Face> refitted;
    for (size_t k = 0; k < faces.size(); ++k)
    {
      const Face f = fitPlane(samples_, groups[k], faces[k].normal, o_.minimumSamples);
      if (f.count > 0)
        refitted.push_back(f);
    }
    faces.swap(refitted);
    std::stable_sort(faces.begin(), faces.end(), byCount);
  }
  int explained = 0;
  for (int s : near)
    explained += std::any_of(faces.begin(), faces.end(), [&](const Face& f) { return residual(samples_[s], f) <= kExplainedWithin; });
  dropNearParallel(faces, edgeCosine_);
  result.count = static_cast<int>(faces.size());
  std::copy(faces.begin(), faces.end(), result.faces.begin());
  const bool planar = explained >= o_.explained * near.size();
  result.edge = result.count >= 2 && planar && kindOf(result.faces.data(), result.count) != 0;
  if (!planar || (result.count >= 2 && !result.edge))
    result.count = 0; // faces that do not explain the staircase, or make no edge, say nothing
  return result;
}

void EdgeSharpener::fitCandidates()
{
  local_.assign(candidates_.size(), {});
  forEachChunk(candidates_.size(), chunkCount(candidates_.size(), 256), [&](size_t, size_t begin, size_t end) {
    std::vector<int> near;
    std::vector<std::vector<int>> groups;
    for (size_t i = begin; i < end; ++i)
      if (std::abs(psi_[candidates_[i]]) <= 1.5 * hMax_)
        local_[i] = fitFaces(candidates_[i], near, groups);
  });
}

/// nearEdge_: voxels within `near` of an edge voxel. False when there is none.
bool EdgeSharpener::markNearEdges()
{
  nearEdge_.assign(box_.size, 0.0f);
  bool any = false;
  for (size_t i = 0; i < candidates_.size(); ++i)
    if (local_[i].edge)
      any = true, nearEdge_[candidates_[i]] = 1.0f;
  if (any)
    runningMaximum(box_, o_.near, nearEdge_);
  return any;
}

/// The faces of the voxels near edges merged into planes (largest first: each joins the first plane
/// within mergeAngle and mergeOffset), their normals and points averaged by sample count; faces of
/// small planes dropped.
void EdgeSharpener::mergeFaces()
{
  struct Ref
  {
    int count;
    size_t candidate;
    int face;
  };
  std::vector<Ref> refs;
  for (size_t i = 0; i < candidates_.size(); ++i)
    if (nearEdge_[candidates_[i]] > 0)
      for (int k = 0; k < local_[i].count; ++k)
        refs.push_back({ local_[i].faces[k].count, i, k });
  std::stable_sort(refs.begin(), refs.end(), [](const Ref& a, const Ref& b) { return a.count > b.count; });
  const double mergeCosine = std::cos(o_.mergeAngle * kDegree), offset = o_.mergeOffset * hMax_;
  std::vector<Vec3> normalSum, pointSum;
  std::vector<double> weight;
  std::vector<int> voxels;
  for (const Ref& r : refs)
  {
    const Face& f = local_[r.candidate].faces[r.face];
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
    local_[r.candidate].plane[r.face] = static_cast<int>(k);
  }
  // a face bent by a curved surface (two balls crossing: sharp where they meet, curved elsewhere)
  // gives members that each look flat but drift off any one plane and turn with their place on it
  std::vector<double> drift(weight.size(), 0.0), turn(weight.size(), 0.0), spread(weight.size(), 0.0);
  for (const Ref& r : refs)
  {
    const Face& f = local_[r.candidate].faces[r.face];
    const size_t k = static_cast<size_t>(local_[r.candidate].plane[r.face]);
    const Vec3 n = (1.0 / norm(normalSum[k])) * normalSum[k];
    const Vec3 offset = f.point - (1.0 / weight[k]) * pointSum[k];
    const Vec3 along = offset - dot(n, offset) * n;
    drift[k] += f.count * dot(n, offset) * dot(n, offset);
    turn[k] += f.count * dot(along, f.normal - n);
    spread[k] += f.count * dot(along, along);
  }
  std::vector<bool> flat(weight.size());
  for (size_t k = 0; k < weight.size(); ++k) // RMS drift, and the curvature turn / spread (1 / radius)
    flat[k] = std::sqrt(drift[k] / weight[k]) <= o_.flatDrift * hMax_ &&
      std::abs(turn[k]) <= o_.flatCurvature * spread[k] / hMax_;
  const double largest = weight.empty() ? 0.0 : *std::max_element(weight.begin(), weight.end());
  for (size_t k = 0; k < weight.size(); ++k)
    planes_.push_back({ (1.0 / norm(normalSum[k])) * normalSum[k], (1.0 / weight[k]) * pointSum[k],
      flat[k] && weight[k] >= o_.significant * largest && voxels[k] >= o_.planeVoxels ? static_cast<int>(weight[k]) : 0 });
}

/// Each voxel near an edge: the distance to the planes of the voxels within `vote` of it.
std::size_t EdgeSharpener::replace(std::vector<float>& out, double delta) const
{
  const size_t chunks = chunkCount(candidates_.size(), 1024);
  std::vector<size_t> changed(chunks, 0);
  forEachChunk(candidates_.size(), chunks, [&](size_t chunk, size_t begin, size_t end) {
    std::vector<int> ids;
    std::vector<Face> faces;
    for (size_t i = begin; i < end; ++i)
    {
      const size_t v = candidates_[i];
      if (nearEdge_[v] <= 0)
        continue;
      int p[3];
      coordinates(v, p);
      ids.clear();
      for (int z = std::max(p[2] - o_.vote, 0); z <= std::min(p[2] + o_.vote, box_.n[2] - 1); ++z)
        for (int y = std::max(p[1] - o_.vote, 0); y <= std::min(p[1] + o_.vote, box_.n[1] - 1); ++y)
          for (int x = std::max(p[0] - o_.vote, 0); x <= std::min(p[0] + o_.vote, box_.n[0] - 1); ++x)
          {
            const int c = candidateOf_[box_.stride[2] * z + box_.stride[1] * y + x];
            if (c >= 0 && nearEdge_[candidates_[c]] > 0)
              for (int k = 0; k < local_[c].count; ++k)
                if (planes_[local_[c].plane[k]].count > 0)
                  ids.push_back(local_[c].plane[k]);
          }
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      if (ids.empty())
        continue;
      faces.clear();
      for (int id : ids)
        faces.push_back(planes_[id]);
      std::stable_sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.count > b.count; });
      dropNearParallel(faces, edgeCosine_);
      const int kind = faces.size() == 1 ? 1 : kindOf(faces.data(), static_cast<int>(faces.size()));
      if (kind == 0)
        continue;
      const double d = distanceTo(faces.data(), static_cast<int>(faces.size()), kind, centre(v));
      const double slack = 0.2 * hMax_;
      if (std::abs(d - psi_[v]) > 1.2 * hMax_ || (inside_[v] ? d < -slack : d > slack))
        continue;
      out[v] = static_cast<float>(inside_[v] ? std::max(d, delta) : std::min(d, -delta));
      ++changed[chunk];
    }
  });
  return std::accumulate(changed.begin(), changed.end(), size_t{ 0 });
}
}

std::size_t sharpenLabelEdges(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, double delta, const LabelEdgeSharpeningOptions& options)
{
  std::vector<float> out = psi;
  const std::size_t changed = EdgeSharpener(box, h, psi, inside, options).run(out, delta);
  psi.swap(out);
  return changed;
}
}
