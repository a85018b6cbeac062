// SPDX-License-Identifier: GPL-3.0-or-later
#include "ImprovementMesh.h"

#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "ShapeSummary.h"
#include "WorkerThreads.h"

#include <algorithm>
#include <cmath>

namespace omesh
{
namespace
{
/// A tetrahedron whose longest edge is below this x the typical edge is not made: ten times the
/// validity check's micro threshold (MeshValidity.h), which measures against the median edge;
/// one that already was so small must not go below twice that threshold.
constexpr double kMicroEdge = 1e-3;
constexpr double kMicroFloor = 2e-4;

/// Why a tetrahedron may not be made (ImprovementMesh::flaws).
constexpr unsigned kMicroFlaw = 1;  ///< longest edge below kMicroEdge x the typical edge
constexpr unsigned kTinyFlaw = 2;   ///< below kMicroFloor x the typical edge
constexpr unsigned kLargeFlaw = 4;  ///< circumradius above its material's cell size
constexpr unsigned kAcrossFlaw = 8; ///< every vertex on an interface or line, centroid in another material
}

ImprovementMesh::ImprovementMesh(
  TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options)
  : mesh_(mesh)
  , oracle_(oracle)
  , options_(options)
  , stars_(mesh)
{
  orientation_ = orientationOfMesh();
  microLength_ = kMicroEdge * typicalEdge();
  classifyVertices();
}

// --- measures ----------------------------------------------------------------------------
double ImprovementMesh::quality(const std::array<int, 4>& t) const
{
  const auto& p = mesh_.points;
  if (orient(t) <= 0)
    return -1.0;
  return dihedralWindowQuality(p[t[0]], p[t[1]], p[t[2]], p[t[3]], options_.minAngle, options_.maxAngle);
}

double ImprovementMesh::orient(const std::array<int, 4>& t) const
{
  const auto& p = mesh_.points;
  return orientation_ * signedVolume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
}

double ImprovementMesh::typicalEdge() const
{
  std::vector<double> lengths;
  lengths.reserve(mesh_.tets.size());
  double volume = 0.0;
  const auto& p = mesh_.points;
  for (const auto& t : mesh_.tets)
  {
    lengths.push_back(norm(p[t[0]] - p[t[1]]));
    volume += std::abs(signedVolume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]));
  }
  if (lengths.empty())
    return 0.0;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return validityLength(lengths[lengths.size() / 2], volume, mesh_.tets.size());
}

double ImprovementMesh::orientationOfMesh() const
{
  const auto& p = mesh_.points;
  for (const auto& t : mesh_.tets)
  {
    const double v = signedVolume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
    if (v != 0)
      return v > 0 ? 1.0 : -1.0;
  }
  return 1.0;
}

void ImprovementMesh::measure(std::size_t& outside, double& minAngle, double& maxAngle, std::size_t* held) const
{
  // in chunks on the threads runOnThreads allows: counts, minimum and maximum in any order alike
  struct Part
  {
    std::size_t outside = 0, held = 0;
    double lo = 180.0, hi = 0.0;
  };
  const auto& p = mesh_.points;
  const std::size_t chunks = chunkCount(mesh_.tets.size(), kTetsPerChunk);
  std::vector<Part> parts(chunks);
  forEachChunk(mesh_.tets.size(), chunks, [&](std::size_t k, std::size_t begin, std::size_t end) {
    Part& part = parts[k];
    for (std::size_t i = begin; i < end; ++i)
    {
      const auto& t = mesh_.tets[i];
      double lo = 0.0, hi = 180.0;
      dihedralAngleRange(p[t[0]], p[t[1]], p[t[2]], p[t[3]], lo, hi);
      part.lo = std::min(part.lo, lo);
      part.hi = std::max(part.hi, hi);
      const bool out = lo < options_.minAngle || hi > options_.maxAngle;
      part.outside += out;
      if (out && std::all_of(t.begin(), t.end(), [&](int v) { return kind_[static_cast<std::size_t>(v)] == VertexKind::Fixed; }))
        ++part.held;
    }
  });
  Part all;
  for (const Part& part : parts)
  {
    all.outside += part.outside;
    all.held += part.held;
    all.lo = std::min(all.lo, part.lo);
    all.hi = std::max(all.hi, part.hi);
  }
  outside = all.outside;
  if (held)
    *held = all.held;
  minAngle = mesh_.tets.empty() ? 0.0 : all.lo;
  maxAngle = mesh_.tets.empty() ? 0.0 : all.hi;
}

double ImprovementMesh::longestEdge(const std::array<int, 4>& t) const
{
  const auto& p = mesh_.points;
  double longest = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      longest = std::max(longest, norm(p[t[i]] - p[t[j]]));
  return longest;
}

double ImprovementMesh::worstOf(const std::vector<int>& tets) const
{
  double q = std::numeric_limits<double>::infinity();
  for (int t : tets)
    q = std::min(q, quality(t));
  return q;
}

double ImprovementMesh::starQuality(int v, int* worst) const
{
  double q = std::numeric_limits<double>::infinity();
  for (int t : stars_.star(v))
  {
    const double x = quality(t);
    if (x < q)
    {
      q = x;
      if (worst)
        *worst = t;
    }
  }
  return q;
}

unsigned ImprovementMesh::flaws(const std::array<int, 4>& t, int material, double sizeFactor) const
{
  const auto& p = mesh_.points;
  unsigned f = 0;
  const double longest = longestEdge(t);
  if (longest < microLength_)
    f |= longest < microLength_ * (kMicroFloor / kMicroEdge) ? kMicroFlaw | kTinyFlaw : kMicroFlaw;
  if (options_.cellSizeOf)
  {
    const double size = options_.cellSizeOf(material);
    if (size > 0 && !(norm(p[t[0]] - circumcenter(p[t[0]], p[t[1]], p[t[2]], p[t[3]])) <= sizeFactor * size))
      f |= kLargeFlaw;
  }
  if (std::none_of(t.begin(), t.end(), [&](int v) { return mesh_.pointDimension[static_cast<std::size_t>(v)] == 3; }) &&
    oracle_.material(0.25 * (p[t[0]] + p[t[1]] + p[t[2]] + p[t[3]])) != material)
    f |= kAcrossFlaw;
  return f;
}

bool ImprovementMesh::starAcceptable(int v, const std::vector<unsigned>* flawsBefore) const
{
  const auto& star = stars_.star(v);
  for (std::size_t k = 0; k < star.size(); ++k)
  {
    const unsigned now = flaws(stars_.tet(star[k]), stars_.material(star[k]));
    const unsigned allowed = flawsBefore ? tolerableFlaws((*flawsBefore)[k]) : 0u;
    if (now & ~allowed)
      return false;
  }
  return true;
}

unsigned ImprovementMesh::tolerableFlaws(unsigned before)
{
  return before & (kLargeFlaw | kMicroFlaw);
}

int ImprovementMesh::addTet(const std::array<int, 4>& t, int material)
{
  const int id = stars_.add(t, material);
  touched_.push_back(id);
  return id;
}

// --- what may change -----------------------------------------------------------------------
void ImprovementMesh::classifyVertices()
{
  const std::size_t n = mesh_.points.size();
  kind_.assign(n, VertexKind::Interior);
  sides_.assign(n, { 0, 0 });
  interfaceAt_.assign(n, {});
  interfaceGone_.assign(mesh_.interfaceTriangles.size(), 0);
  for (std::size_t v = 0; v < n; ++v)
    if (mesh_.pointDimension[v] <= 1)
      kind_[v] = VertexKind::Fixed;
  for (const auto& s : mesh_.segments)
    if (s.aId >= 0 && s.bId >= 0)
    {
      kept_.insert(edgeKey(s.aId, s.bId));
      kind_[static_cast<std::size_t>(s.aId)] = kind_[static_cast<std::size_t>(s.bId)] = VertexKind::Fixed;
    }
  for (std::size_t k = 0; k < mesh_.interfaceTriangles.size(); ++k)
  {
    const auto& tri = mesh_.interfaceTriangles[k];
    const auto& m = mesh_.interfaceMaterials[k];
    const std::array<int, 2> pair{ std::min(m[0], m[1]), std::max(m[0], m[1]) };
    interfaces_.emplace(FaceKey(tri[0], tri[1], tri[2]), static_cast<int>(k));
    for (int v : tri)
    {
      auto& at = interfaceAt_[static_cast<std::size_t>(v)];
      if (at.empty())
        sides_[static_cast<std::size_t>(v)] = pair;
      else if (sides_[static_cast<std::size_t>(v)] != pair)
        kind_[static_cast<std::size_t>(v)] = VertexKind::Fixed; // interfaces meet here
      at.push_back(static_cast<int>(k));
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (kind_[v] != VertexKind::Fixed)
      kind_[v] = classifyFree(static_cast<int>(v));
  classifyLineVertices();
}

void ImprovementMesh::classifyLineVertices()
{
  std::unordered_map<int, std::vector<const TetMesh::Segment*>> pieces;
  for (const auto& s : mesh_.segments)
    if (s.aId >= 0 && s.bId >= 0 && s.present)
    {
      pieces[s.aId].push_back(&s);
      pieces[s.bId].push_back(&s);
    }
  for (const auto& [v, at] : pieces)
  {
    if (mesh_.pointDimension[static_cast<std::size_t>(v)] != 1 || at.size() != 2 || at[0]->input != at[1]->input)
      continue;
    const Vec3 d = at[0]->b - at[0]->a, e = at[1]->b - at[1]->a;
    if (!(norm(d) > 0) || norm(cross(d, e)) > 1e-9 * norm(d) * norm(e))
      continue;
    kind_[static_cast<std::size_t>(v)] = VertexKind::OnLine;
    lineDirection_[v] = (1.0 / norm(d)) * d;
  }
}

VertexKind ImprovementMesh::classifyFree(int v) const
{
  const auto& star = stars_.star(v);
  if (star.empty())
    return VertexKind::Fixed;
  if (interfaceAt_[static_cast<std::size_t>(v)].empty())
  {
    // inside one material by its star (a vertex CGAL put on a surface that no interface
    // triangle shows stays: moving it could leave that surface)
    const int m = stars_.material(star.front());
    for (int t : star)
      if (stars_.material(t) != m)
        return VertexKind::Fixed;
    return mesh_.pointDimension[static_cast<std::size_t>(v)] == 3 ? VertexKind::Interior : VertexKind::Fixed;
  }
  const auto pair = sides_[static_cast<std::size_t>(v)];
  for (int t : star)
    if (stars_.material(t) != pair[0] && stars_.material(t) != pair[1])
      return VertexKind::Fixed;
  return mesh_.pointDimension[static_cast<std::size_t>(v)] == 2 ? VertexKind::Interface : VertexKind::Fixed;
}

bool ImprovementMesh::isKept(int a, int b) const
{
  if (kept_.count(edgeKey(a, b)))
    return true;
  // edges between two feature vertices: chords of protecting balls count as the line
  return mesh_.pointDimension[static_cast<std::size_t>(a)] <= 1 && mesh_.pointDimension[static_cast<std::size_t>(b)] <= 1;
}

void ImprovementMesh::addInteriorVertex(const Vec3& x)
{
  mesh_.points.push_back(x);
  mesh_.pointDimension.push_back(3);
  kind_.push_back(VertexKind::Interior);
  sides_.push_back({ 0, 0 });
  interfaceAt_.emplace_back();
  stars_.addVertex();
}

void ImprovementMesh::removeLastVertex()
{
  stars_.removeLastVertex();
  mesh_.points.pop_back();
  mesh_.pointDimension.pop_back();
  kind_.pop_back();
  sides_.pop_back();
  interfaceAt_.pop_back();
}

void ImprovementMesh::dropVertex(int v)
{
  kind_[static_cast<std::size_t>(v)] = VertexKind::Fixed;
  dropped_.push_back(v);
}

// --- interfaces ----------------------------------------------------------------------------
InterfaceSwap ImprovementMesh::swapInterfaces(const std::vector<Retriangulated>& changes)
{
  InterfaceSwap swap;
  for (const auto& change : changes)
  {
    const auto it = interfaces_.find(FaceKey(change.tri[0], change.tri[1], change.tri[2]));
    if (it == interfaces_.end())
      continue;
    swap.gone.push_back(it->second);
    interfaceGone_[static_cast<std::size_t>(it->second)] = 1;
    for (int v : change.tri)
    {
      auto& at = interfaceAt_[static_cast<std::size_t>(v)];
      at.erase(std::find(at.begin(), at.end(), it->second));
    }
    interfaces_.erase(it);
  }
  for (const auto& change : changes)
  {
    if (change.gone)
      continue;
    const auto& tri = change.tri;
    const auto& materials = change.materials;
    const std::array<int, 2> pair{ std::min(materials[0], materials[1]), std::max(materials[0], materials[1]) };
    const int k = static_cast<int>(mesh_.interfaceTriangles.size());
    mesh_.interfaceTriangles.push_back(tri);
    mesh_.interfaceMaterials.push_back(materials);
    interfaceGone_.push_back(0);
    interfaces_.emplace(FaceKey(tri[0], tri[1], tri[2]), k);
    swap.made.push_back(k);
    for (int v : tri)
    {
      interfaceAt_[static_cast<std::size_t>(v)].push_back(k);
      auto& kind = kind_[static_cast<std::size_t>(v)];
      if (kind != VertexKind::Fixed && sides_[static_cast<std::size_t>(v)] != pair)
      {
        swap.kinds.emplace_back(v, kind);
        kind = VertexKind::Fixed;
      }
    }
  }
  return swap;
}

void ImprovementMesh::undoSwap(const InterfaceSwap& swap)
{
  for (auto k = swap.made.rbegin(); k != swap.made.rend(); ++k)
  {
    const auto tri = mesh_.interfaceTriangles[static_cast<std::size_t>(*k)];
    interfaces_.erase(FaceKey(tri[0], tri[1], tri[2]));
    for (int v : tri)
      interfaceAt_[static_cast<std::size_t>(v)].pop_back();
    mesh_.interfaceTriangles.pop_back();
    mesh_.interfaceMaterials.pop_back();
    interfaceGone_.pop_back();
  }
  for (auto it = swap.kinds.rbegin(); it != swap.kinds.rend(); ++it)
    kind_[static_cast<std::size_t>(it->first)] = it->second;
  for (int k : swap.gone)
  {
    const auto& tri = mesh_.interfaceTriangles[static_cast<std::size_t>(k)];
    interfaceGone_[static_cast<std::size_t>(k)] = 0;
    interfaces_.emplace(FaceKey(tri[0], tri[1], tri[2]), k);
    for (int v : tri)
      interfaceAt_[static_cast<std::size_t>(v)].push_back(k);
  }
}

void ImprovementMesh::compactInterfaces()
{
  std::size_t kept = 0;
  for (std::size_t k = 0; k < mesh_.interfaceTriangles.size(); ++k)
    if (!interfaceGone_[k])
    {
      mesh_.interfaceTriangles[kept] = mesh_.interfaceTriangles[k];
      mesh_.interfaceMaterials[kept] = mesh_.interfaceMaterials[k];
      ++kept;
    }
  mesh_.interfaceTriangles.resize(kept);
  mesh_.interfaceMaterials.resize(kept);
}

void ImprovementMesh::compactPoints()
{
  if (dropped_.empty())
    return;
  std::vector<int> index(mesh_.points.size(), 0);
  for (int v : dropped_)
    index[static_cast<std::size_t>(v)] = -1;
  int next = 0;
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0)
    {
      mesh_.points[static_cast<std::size_t>(next)] = mesh_.points[v];
      mesh_.pointDimension[static_cast<std::size_t>(next)] = mesh_.pointDimension[v];
      index[v] = next++;
    }
  mesh_.points.resize(static_cast<std::size_t>(next));
  mesh_.pointDimension.resize(static_cast<std::size_t>(next));
  for (auto& t : mesh_.tets)
    for (int& v : t)
      v = index[static_cast<std::size_t>(v)];
  for (auto& tri : mesh_.interfaceTriangles)
    for (int& v : tri)
      v = index[static_cast<std::size_t>(v)];
  for (auto& piece : mesh_.segments) // a collapsed vertex ends no piece (no kept edge)
  {
    if (piece.aId >= 0)
      piece.aId = index[static_cast<std::size_t>(piece.aId)];
    if (piece.bId >= 0)
      piece.bId = index[static_cast<std::size_t>(piece.bId)];
  }
  dropped_.clear();
}

void ImprovementMesh::writeBack()
{
  stars_.compact(mesh_);
  compactInterfaces();
  compactPoints();
  for (auto& piece : mesh_.segments) // their ends may have slid along the line
  {
    if (piece.aId >= 0)
      piece.a = mesh_.points[static_cast<std::size_t>(piece.aId)];
    if (piece.bId >= 0)
      piece.b = mesh_.points[static_cast<std::size_t>(piece.bId)];
  }
}
}
