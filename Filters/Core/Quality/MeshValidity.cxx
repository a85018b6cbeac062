// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshValidity.h"

#include "FieldDataKeys.h"
#include "BoundingBox.h"
#include "MeshQuality.h"
#include "ShapeSummary.h"
#include "WorkerThreads.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

namespace omesh
{
namespace
{
/// Used vertices with another used vertex closer than `tol`. The vertices are sorted by the cell of
/// a grid of 8 `tol` that holds them; each is compared with the vertices of its own cell and of
/// the neighbouring cells it lies within `tol` of (about two cells on average, not 27). Such
/// cells hold few vertices that are not duplicates (a vertex stops at its first duplicate),
/// wherever the vertices crowd: with cells of the median edge, a cluster of tiny tetrahedra would
/// make it a quadratic search. Keys count from the smallest coordinates in cells of at least 1e-12 of the
/// extent, so that they fit.
std::vector<char> findDuplicates(const std::vector<Vec3>& points, const std::vector<char>& used, double tol)
{
  BoundingBox box;
  for (std::size_t v = 0; v < points.size(); ++v)
    if (used[v] && isFinite(points[v]))
      box.add(points[v]);
  const Vec3 extent = box.size(), low = box.min;
  const double cell = std::max(8.0 * tol, 1e-12 * std::max({ extent.x, extent.y, extent.z, 0.0 }));
  using Key = std::array<std::int64_t, 3>;
  struct Entry
  {
    Key key;
    int vertex;
    bool operator<(const Entry& o) const { return key < o.key; }
  };
  auto coordinate = [cell](double x) { return static_cast<std::int64_t>(std::floor(x / cell)); };
  std::vector<Entry> sorted;
  sorted.reserve(points.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    if (used[v] && isFinite(points[v]))
    {
      const Vec3 p = points[v] - low;
      sorted.push_back({ { coordinate(p.x), coordinate(p.y), coordinate(p.z) }, static_cast<int>(v) });
    }
  std::sort(sorted.begin(), sorted.end());
  std::vector<char> duplicate(points.size(), 0);
  auto within = [&](const Entry& e, const Entry& o) { return norm(points[o.vertex] - points[e.vertex]) < tol; };
  for (auto at = sorted.begin(); at != sorted.end(); ++at)
  {
    const Entry& e = *at;
    // its own cell: the entries of the same key beside it (no search)
    bool dup = false;
    for (auto it = at; !dup && it != sorted.begin() && (it - 1)->key == e.key; --it)
      dup = within(e, *(it - 1));
    for (auto it = at + 1; !dup && it != sorted.end() && it->key == e.key; ++it)
      dup = within(e, *it);
    const Vec3 p = points[e.vertex] - low;
    // the neighbouring cells along each axis that lie within tol of p
    std::int64_t from[3], to[3];
    const double x[3] = { p.x, p.y, p.z };
    for (int a = 0; a < 3; ++a)
    {
      const double inCell = x[a] - static_cast<double>(e.key[a]) * cell;
      from[a] = e.key[a] - (inCell < tol ? 1 : 0);
      to[a] = e.key[a] + (inCell > cell - tol ? 1 : 0);
    }
    for (std::int64_t i = from[0]; i <= to[0] && !dup; ++i)
      for (std::int64_t j = from[1]; j <= to[1] && !dup; ++j)
        for (std::int64_t k = from[2]; k <= to[2] && !dup; ++k)
        {
          const Entry probe{ { i, j, k }, 0 };
          if (probe.key == e.key)
            continue; // looked at above
          for (auto it = std::lower_bound(sorted.begin(), sorted.end(), probe); !dup && it != sorted.end() && it->key == probe.key; ++it)
            dup = within(e, *it);
        }
    duplicate[e.vertex] = dup;
  }
  return duplicate;
}

/// The corners of a tetrahedron in ascending order (a sorting network of five exchanges).
std::array<int, 4> ascendingCorners(std::array<int, 4> k)
{
  auto order = [&k](int i, int j) {
    if (k[j] < k[i])
      std::swap(k[i], k[j]);
  };
  order(0, 1);
  order(2, 3);
  order(0, 2);
  order(1, 3);
  order(1, 2);
  return k;
}

/// The tetrahedra with valid indices: all of them (no list: the mesher's output) or those listed.
class GoodTets
{
public:
  explicit GoodTets(std::size_t all)
    : count_(all)
  {
  }
  explicit GoodTets(std::vector<std::size_t> listed)
    : list_(std::move(listed))
    , count_(list_.size())
    , listed_(true)
  {
  }
  std::size_t size() const { return count_; }
  std::size_t operator[](std::size_t i) const { return listed_ ? list_[i] : i; }
  template <typename F>
  void forEach(F&& f) const
  {
    for (std::size_t i = 0; i < count_; ++i)
      f((*this)[i]);
  }

private:
  std::vector<std::size_t> list_;
  std::size_t count_ = 0;
  bool listed_ = false;
};

/// A face in countNonManifoldFaces' buckets (bucketed by its smallest vertex). FaceIndex holds
/// 4 x tetrahedron + its corner not on the face.
template <typename FaceIndex>
struct FaceEntry
{
  std::uint32_t b, c; // the two larger vertices
  FaceIndex face;
  std::uint64_t key() const { return (std::uint64_t{ b } << 32) | c; }
  bool operator<(const FaceEntry& o) const { return key() < o.key(); }
  bool sameFace(const FaceEntry& o) const { return b == o.b && c == o.c; }
};

/// Sorts one bucket: buckets hold about 20 faces, where an insertion sort beats std::sort's set-up.
template <typename Iterator>
void sortBucket(Iterator begin, Iterator end)
{
  if (end - begin > 32)
  {
    std::sort(begin, end);
    return;
  }
  for (auto i = begin + (begin != end); i < end; ++i)
  {
    const auto e = *i; // shifted into place: one move per step, not a swap's three
    auto j = i;
    for (; j != begin && e < *(j - 1); --j)
      *j = *(j - 1);
    *j = e;
  }
}

/// What countNonManifoldFaces finds in one range of buckets.
struct FacesFound
{
  std::size_t count = 0;              ///< faces shared by more than two tetrahedra
  std::vector<std::size_t> crowded;   ///< their entries' faces (4 x tetrahedron + corner)
  std::vector<TetMesh::SeparatingFace> separating;
};

/// Sorts and reads the buckets of the vertices [from, to).
template <typename FaceIndex>
void scanBuckets(std::vector<FaceEntry<FaceIndex>>& entries, const std::vector<std::size_t>& first, std::size_t from,
  std::size_t to, const std::vector<int>& materials, bool separating, FacesFound& found)
{
  auto materialOf = [&materials](std::size_t f) { return f / 4 < materials.size() ? materials[f / 4] : 0; };
  auto keep = [&found](std::size_t f, int other) { found.separating.push_back({ f / 4, static_cast<int>(f % 4), other }); };
  for (std::size_t v = from; v < to; ++v)
  {
    const auto begin = entries.begin() + static_cast<std::ptrdiff_t>(first[v]);
    const auto end = entries.begin() + static_cast<std::ptrdiff_t>(first[v + 1]);
    sortBucket(begin, end);
    for (auto i = begin; i != end;)
    {
      auto j = i;
      while (j != end && j->sameFace(*i))
        ++j;
      if (j - i > 2)
      {
        ++found.count;
        for (auto k = i; k != j; ++k)
          found.crowded.push_back(static_cast<std::size_t>(k->face));
      }
      else if (separating && j - i == 1)
        keep(static_cast<std::size_t>(i->face), -1);
      else if (separating)
      {
        const auto f = static_cast<std::size_t>(i->face), g = static_cast<std::size_t>((i + 1)->face);
        const int a = materialOf(f), b = materialOf(g);
        if (a != b)
          a < b ? keep(f, b) : keep(g, a);
      }
      i = j;
    }
  }
}

/// Faces shared by more than two tetrahedra; the tetrahedra holding one are flagged. Faces are
/// bucketed by their smallest vertex (a counting sort), then each small bucket is sorted by the
/// other two (scanBuckets, in chunks of vertices on the threads runOnThreads allows, merged in
/// chunk order): linear in the mesh, where one sort of all faces cost more than the rest of the
/// check. Indices are valid (measureTets); `good` are the tetrahedra to look at. The
/// faces of one tetrahedron, or of two of different materials, go to `separating` when given (the
/// owner: the lower material id, the first tetrahedron for equal ids). FaceIndex holds 4 x
/// tetrahedra (32 bits below a billion tetrahedra: the entries, four per tetrahedron, are the
/// check's largest array).
template <typename FaceIndex>
std::size_t countNonManifoldFaces(const std::vector<std::array<int, 4>>& tets, const std::vector<int>& materials,
  const GoodTets& good, std::size_t pointCount, std::vector<unsigned char>& flags,
  std::vector<TetMesh::SeparatingFace>* separating)
{
  // with its corners sorted, a b c d, a tetrahedron's faces are abc, abd, acd (smallest a) and bcd
  std::vector<std::size_t> first(pointCount + 1, 0);
  good.forEach([&](std::size_t t) {
    const std::array<int, 4> k = ascendingCorners(tets[t]);
    first[k[0] + 1] += 3;
    first[k[1] + 1] += 1;
  });
  for (std::size_t v = 0; v < pointCount; ++v)
    first[v + 1] += first[v];
  std::vector<FaceEntry<FaceIndex>> entries(first[pointCount]);
  std::vector<std::size_t> next(first.begin(), first.end() - 1);
  auto add = [&](int a, int b, int c, std::size_t t, int without) {
    const auto& k = tets[t];
    const int corner = k[0] == without ? 0 : k[1] == without ? 1 : k[2] == without ? 2 : 3;
    entries[next[a]++] = { static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c),
      static_cast<FaceIndex>(4 * t + static_cast<std::size_t>(corner)) };
  };
  good.forEach([&](std::size_t t) {
    const std::array<int, 4> k = ascendingCorners(tets[t]);
    add(k[0], k[1], k[2], t, k[3]);
    add(k[0], k[1], k[3], t, k[2]);
    add(k[0], k[2], k[3], t, k[1]);
    add(k[1], k[2], k[3], t, k[0]);
  });
  constexpr std::size_t kVerticesPerChunk = 2048; // about 12,000 tetrahedra
  const std::size_t chunks = chunkCount(pointCount, kVerticesPerChunk);
  std::vector<FacesFound> parts(chunks);
  forEachChunk(pointCount, chunks, [&](std::size_t part, std::size_t from, std::size_t to) {
    scanBuckets(entries, first, from, to, materials, separating != nullptr, parts[part]);
  });
  std::size_t count = 0;
  for (const FacesFound& found : parts)
  {
    count += found.count;
    for (std::size_t f : found.crowded)
      flags[f / 4] |= kNonManifoldFace;
    if (separating)
      separating->insert(separating->end(), found.separating.begin(), found.separating.end());
  }
  return count;
}
}

std::string MeshValidity::describe() const
{
  std::ostringstream o;
  const std::pair<std::size_t, const char*> items[] = { { duplicateVertices, "duplicate vertices" },
    { microTetrahedra, "micro tetrahedra" }, { flatTetrahedra, "flat tetrahedra" },
    { invertedTetrahedra, "inverted tetrahedra" }, { nonManifoldFaces, "faces shared by more than two tetrahedra" },
    { badIndices, "tetrahedra with bad vertex indices" },
    { materialMismatches, "tetrahedra whose material differs from the oracle's inside them" },
    { missingSegmentPieces, "constrained segment pieces missing from the mesh edges" },
    { unusedVertices, "vertices no tetrahedron uses" } };
  const char* sep = "";
  for (const auto& [n, what] : items)
    if (n)
    {
      o << sep << n << ' ' << what;
      sep = ", ";
    }
  return o.str();
}

std::vector<std::pair<std::string, double>> MeshValidity::asStatistics() const
{
  auto d = [](std::size_t n) { return static_cast<double>(n); };
  return { { keys::VALIDITY_DEFECTS, d(defects()) }, { keys::VALIDITY_DUPLICATE_VERTICES, d(duplicateVertices) },
    { keys::VALIDITY_MICRO_TETRAHEDRA, d(microTetrahedra) }, { keys::VALIDITY_FLAT_TETRAHEDRA, d(flatTetrahedra) },
    { keys::VALIDITY_INVERTED_TETRAHEDRA, d(invertedTetrahedra) }, { keys::VALIDITY_NON_MANIFOLD_FACES, d(nonManifoldFaces) },
    { keys::VALIDITY_BAD_VERTEX_INDICES, d(badIndices) }, { keys::VALIDITY_MATERIAL_MISMATCHES, d(materialMismatches) },
    { keys::VALIDITY_MISSING_SEGMENT_PIECES, d(missingSegmentPieces) }, { keys::VALIDITY_MEDIAN_EDGE, medianEdge },
    { keys::VALIDITY_SHORTEST_EDGE, shortestEdge }, { keys::VALIDITY_UNUSED_VERTICES, d(unusedVertices) },
    { keys::VALIDITY_ACROSS_BOUNDARY_TETRAHEDRA, d(acrossBoundaryTetrahedra) },
    { keys::VALIDITY_ACROSS_BOUNDARY_VOLUME, acrossBoundaryVolume } };
}

namespace
{
/// The exact median and the shortest of the tetrahedra's edge lengths (an edge once per
/// tetrahedron holding it), without a list of them (six doubles per tetrahedron: 480 MB at 10M
/// tetrahedra): the lengths are counted in bins of their leading bits (the exponent and 5 bits of
/// the mantissa, in the order of the values for non-negative doubles), then a second pass collects
/// only the median's bin and orders that.
class EdgeLengthMedian
{
public:
  EdgeLengthMedian() : bins_(kBins, 0) {}

  /// Adds the counts of `other` (the same lengths counted in another chunk of the tetrahedra).
  void merge(const EdgeLengthMedian& other)
  {
    for (std::size_t b = 0; b < kBins; ++b)
      bins_[b] += other.bins_[b];
    count_ += other.count_;
    shortest_ = std::min(shortest_, other.shortest_);
  }

  void add(double length)
  {
    ++bins_[bin(length)];
    ++count_;
    shortest_ = std::min(shortest_, length);
  }
  std::size_t count() const { return count_; }
  double shortest() const { return shortest_; }

  /// The bin of the median (the length of rank count / 2, as std::nth_element picks it) and its
  /// rank within the bin.
  void locate()
  {
    std::size_t before = 0, rank = count_ / 2;
    for (medianBin_ = 0; before + bins_[medianBin_] <= rank; ++medianBin_)
      before += bins_[medianBin_];
    rankInBin_ = rank - before;
    candidates_.reserve(bins_[medianBin_]);
  }
  /// The lengths the median's bin holds, from `low` up to below `high` (after locate).
  void medianBin(double& low, double& high) const
  {
    low = valueAt(medianBin_);
    high = medianBin_ + 1 < kBins ? valueAt(medianBin_ + 1) : std::numeric_limits<double>::infinity();
  }
  /// Second pass: the same lengths again, into `candidates` (one list per chunk of the
  /// tetrahedra), then addCandidates.
  bool inMedianBin(double length) const { return bin(length) == medianBin_; }
  void addCandidates(const std::vector<double>& candidates)
  {
    candidates_.insert(candidates_.end(), candidates.begin(), candidates.end());
  }
  double median()
  {
    std::nth_element(candidates_.begin(), candidates_.begin() + static_cast<std::ptrdiff_t>(rankInBin_), candidates_.end());
    return candidates_[rankInBin_];
  }

private:
  static constexpr std::size_t kBins = std::size_t{ 1 } << 16;
  static std::size_t bin(double length)
  {
    std::uint64_t bits;
    std::memcpy(&bits, &length, sizeof bits);
    return std::min<std::size_t>(bits >> 47, kBins - 1); // a negative or NaN length (bad points) counts as the largest
  }
  /// The smallest length of bin b.
  static double valueAt(std::size_t b)
  {
    const std::uint64_t bits = static_cast<std::uint64_t>(b) << 47;
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }
  std::vector<std::uint32_t> bins_;
  std::vector<double> candidates_;
  std::size_t count_ = 0, medianBin_ = 0, rankInBin_ = 0;
  double shortest_ = std::numeric_limits<double>::infinity();
};

/// Tetrahedra per chunk of the pass that counts edge lengths (each chunk has its histogram).
constexpr std::size_t kHistogramChunk = 65536;

/// Calls f with each of the six edge lengths of tetrahedron t.
template <typename F>
void forEachEdgeLength(const TetMesh& mesh, std::size_t t, F&& f)
{
  const auto& k = mesh.tets[t];
  double l[6];
  edgeLengths(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]], mesh.points[k[3]], l);
  for (double length : l)
    f(length);
}

/// Four distinct indices of points of the mesh (`n` points).
bool validIndices(const std::array<int, 4>& k, int n)
{
  bool ok = true;
  for (int i = 0; i < 4; ++i)
  {
    ok = ok && k[i] >= 0 && k[i] < n;
    for (int j = 0; ok && j < i; ++j)
      ok = k[i] != k[j];
  }
  return ok;
}

/// Every vertex on an interface or line, reaching across a boundary (acrossBoundaryBy).
bool acrossBoundary(const TetMesh& mesh, std::size_t t, const std::function<int(const Vec3&)>& materialAt,
  const std::function<double(int)>& facetDistanceOf)
{
  const auto& k = mesh.tets[t];
  for (int i = 0; i < 4; ++i)
    if (mesh.pointDimension[k[i]] == 3)
      return false;
  return acrossBoundaryBy(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]], mesh.points[k[3]],
           mesh.tetMaterial[t], facetDistanceOf, materialAt) > 0;
}

/// What the pass over the tetrahedra finds in one chunk of them.
struct PassPart
{
  std::vector<std::size_t> bad; ///< the tetrahedra with bad indices (few: not the good ones)
  EdgeLengthMedian edges;
  ShapeSummary shapes;
  double volume = 0.0, acrossVolume = 0.0;
  std::size_t across = 0;
};

/// What the pass needs besides the mesh and writes besides the chunks' parts.
struct PassInput
{
  const std::function<int(const Vec3&)>& materialAt;
  const ValidityThresholds& th;
  const ValidityByproducts& byproducts;
  bool across; ///< look for tetrahedra across a boundary
  std::vector<unsigned char>& flags;
};

/// One tetrahedron with valid indices: its edge lengths counted and volume summed (for L), its
/// measures (measureTet, with byproducts.shapes), the defects that do not depend on L (flat,
/// inverted, a material mismatch when all four corners are inside a material) and whether it lies
/// across a boundary (every vertex on an interface or line: never both). Micro is relative to L:
/// the median's pass flags it (medianAndMicro).
void measureAndFlag(const TetMesh& mesh, std::size_t t, const PassInput& in, PassPart& part)
{
  const auto& k = mesh.tets[t];
  const Vec3 &a = mesh.points[k[0]], &b = mesh.points[k[1]], &c = mesh.points[k[2]], &d = mesh.points[k[3]];
  double v, l[6];
  if (in.byproducts.shapes)
    measureTet(mesh, t, part.shapes, in.byproducts.shapeArrays, v, l);
  else
  {
    edgeLengths(a, b, c, d, l);
    v = signedVolume(a, b, c, d);
  }
  for (double length : l)
    part.edges.add(length);
  part.volume += std::abs(v);
  const double longest = *std::max_element(l, l + 6);
  unsigned char flags = (!(std::abs(v) >= in.th.flat * longest * longest * longest) ? kFlat : 0) | (v < 0 ? kInverted : 0);
  if (in.materialAt && t < mesh.tetMaterial.size() && mesh.pointDimension.size() == mesh.points.size())
  {
    bool inside = true;
    for (int i = 0; i < 4; ++i)
      inside = inside && mesh.pointDimension[k[i]] == 3;
    if (inside && in.materialAt(0.25 * (a + b + c + d)) != mesh.tetMaterial[t])
      flags |= kMaterialMismatch;
    else if (!inside && in.across && acrossBoundary(mesh, t, in.materialAt, in.th.facetDistanceOf))
    {
      ++part.across;
      part.acrossVolume += std::abs(v);
    }
  }
  in.flags[t] |= flags;
}

/// The one pass over the tetrahedra, in chunks on the threads runOnThreads allows, merged in chunk
/// order (the same figures on any number of threads; a chunk holds a 256 kB histogram, hence large
/// chunks): those with bad indices counted and flagged (0 in the shape arrays), the others measured
/// and flagged (measureAndFlag). Marks the points the good ones use; returns them.
GoodTets measureTets(const TetMesh& mesh, const PassInput& in, MeshValidity& r, std::vector<char>& used,
  EdgeLengthMedian& edges, double& volume)
{
  const int n = static_cast<int>(mesh.points.size());
  const TetShapeArrays& arrays = in.byproducts.shapeArrays;
  const std::size_t chunks = chunkCount(mesh.tets.size(), kHistogramChunk);
  std::vector<PassPart> parts(chunks);
  forEachChunk(mesh.tets.size(), chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
    PassPart& part = parts[c];
    for (std::size_t t = begin; t < end; ++t)
      if (validIndices(mesh.tets[t], n))
        measureAndFlag(mesh, t, in, part);
      else
      {
        part.bad.push_back(t);
        in.flags[t] |= kBadIndices;
        for (double* a : { arrays.minDihedral, arrays.maxDihedral, arrays.radiusEdge })
          if (a && in.byproducts.shapes)
            a[t] = 0.0; // a tetrahedron with bad indices has no shape
      }
  });
  for (const PassPart& part : parts)
  {
    edges.merge(part.edges);
    volume += part.volume;
    r.badIndices += part.bad.size();
    r.acrossBoundaryTetrahedra += part.across;
    r.acrossBoundaryVolume += part.acrossVolume;
    if (in.byproducts.shapes)
      in.byproducts.shapes->merge(part.shapes);
  }
  GoodTets good(mesh.tets.size());
  if (r.badIndices) // listed: all but the bad ones
  {
    std::vector<std::size_t> listed;
    listed.reserve(mesh.tets.size() - r.badIndices);
    std::size_t t = 0;
    for (const PassPart& part : parts)
      for (std::size_t bad : part.bad)
      {
        for (; t < bad; ++t)
          listed.push_back(t);
        t = bad + 1;
      }
    for (; t < mesh.tets.size(); ++t)
      listed.push_back(t);
    good = GoodTets(std::move(listed));
  }
  good.forEach([&](std::size_t t) {
    for (int i = 0; i < 4; ++i)
      used[mesh.tets[t][i]] = 1;
  });
  return good;
}

/// The median of the edge lengths `edges` counted, from a second pass over the tetrahedra (in
/// chunks), which also flags the micro ones: L (validityLength) is not known before the median, but
/// the median's bin bounds it (3 % wide), so only a tetrahedron whose longest edge falls between
/// the two bounds waits for it.
double medianAndMicro(const TetMesh& mesh, const GoodTets& good, EdgeLengthMedian& edges, double volume,
  double micro, std::vector<unsigned char>& flags)
{
  edges.locate();
  double low, high;
  edges.medianBin(low, high);
  const double below = micro * validityLength(low, volume, good.size()), above = micro * validityLength(high, volume, good.size());
  const std::size_t chunks = chunkCount(good.size(), kTetsPerChunk);
  std::vector<std::vector<double>> candidates(chunks);
  std::vector<std::vector<std::size_t>> undecided(chunks);
  auto longestEdge = [&mesh](std::size_t t) {
    double longest = 0.0;
    forEachEdgeLength(mesh, t, [&longest](double l) { longest = std::max(longest, l); });
    return longest;
  };
  forEachChunk(good.size(), chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const std::size_t t = good[i];
      double longest = 0.0;
      forEachEdgeLength(mesh, t, [&](double l) {
        longest = std::max(longest, l);
        if (edges.inMedianBin(l))
          candidates[c].push_back(l);
      });
      if (longest < below)
        flags[t] |= kMicro;
      else if (longest < above)
        undecided[c].push_back(t);
    }
  });
  for (const auto& part : candidates)
    edges.addCandidates(part);
  const double median = edges.median();
  const double L = validityLength(median, volume, good.size());
  for (const auto& part : undecided)
    for (std::size_t t : part)
      if (longestEdge(t) < micro * L)
        flags[t] |= kMicro;
  return median;
}
}

double acrossBoundaryBy(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int own,
  const std::function<double(int)>& facetDistanceOf, const std::function<int(const Vec3&)>& materialAt)
{
  const Vec3 centroid = 0.25 * (a + b + c + d);
  const int there = materialAt(centroid);
  if (there == own)
    return 0.0;
  const double length = acrossBoundaryLength(facetDistanceOf(own), there >= 0 ? facetDistanceOf(there) : 0.0);
  if (!(length > 0 && smallestAltitude(a, b, c, d) > length))
    return 0.0;
  for (const Vec3* v : { &a, &b, &c, &d })
    if (materialAt(0.5 * (centroid + *v)) != there)
      return 0.0;
  return length;
}

double validityLength(double medianEdge, double totalVolume, std::size_t tetrahedra)
{
  const double meanVolumeEdge =
    tetrahedra ? std::cbrt(6.0 * std::sqrt(2.0) * totalVolume / static_cast<double>(tetrahedra)) : 0.0;
  return std::max(medianEdge, meanVolumeEdge);
}

MeshValidity checkMeshValidity(const TetMesh& mesh, const std::function<int(const Vec3&)>& materialAt,
  const ValidityThresholds& th, std::vector<unsigned char>* tetDefects, const ValidityByproducts& byproducts)
{
  std::vector<TetMesh::SeparatingFace>* separating = byproducts.separatingFaces;
  if (separating)
    separating->clear();
  if (byproducts.shapes)
    *byproducts.shapes = ShapeSummary();

  MeshValidity r;
  std::vector<unsigned char> flags(mesh.tets.size(), 0);
  std::vector<char> used(mesh.points.size(), 0);
  EdgeLengthMedian edges;
  double volume = 0.0;
  const bool across = materialAt && th.facetDistanceOf && mesh.pointDimension.size() == mesh.points.size();
  const PassInput in{ materialAt, th, byproducts, across, flags };
  const GoodTets good = measureTets(mesh, in, r, used, edges, volume);
  for (char u : used)
    r.unusedVertices += !u;
  if (edges.count() == 0)
  {
    if (tetDefects)
      *tetDefects = std::move(flags);
    return r;
  }
  r.shortestEdge = edges.shortest();
  r.medianEdge = medianAndMicro(mesh, good, edges, volume, th.micro, flags);
  // A cluster of tiny tetrahedra that is most of the mesh pulls the median down with it (a run
  // stopped at the vertex budget with 300k vertices around one point, edges of 1e-8 against a
  // median of 1e-4, read "no defects"): L is at least the edge of a regular tetrahedron of the
  // mesh's mean volume.
  const double L = validityLength(r.medianEdge, volume, good.size());
  const double tol = th.duplicate * L;
  if (tol > 0)
  {
    const std::vector<char> duplicate = findDuplicates(mesh.points, used, tol);
    r.duplicateVertices = static_cast<std::size_t>(std::count(duplicate.begin(), duplicate.end(), 1));
    if (r.duplicateVertices)
      good.forEach([&](std::size_t t) {
        for (int i = 0; i < 4; ++i)
          if (duplicate[mesh.tets[t][i]])
            flags[t] |= kDuplicateVertex;
      });
  }
  r.nonManifoldFaces = mesh.tets.size() < (std::size_t{ 1 } << 30)
    ? countNonManifoldFaces<std::uint32_t>(mesh.tets, mesh.tetMaterial, good, mesh.points.size(), flags, separating)
    : countNonManifoldFaces<std::uint64_t>(mesh.tets, mesh.tetMaterial, good, mesh.points.size(), flags, separating);
  for (unsigned char f : flags)
  {
    r.microTetrahedra += (f & kMicro) != 0;
    r.flatTetrahedra += (f & kFlat) != 0;
    r.invertedTetrahedra += (f & kInverted) != 0;
    r.materialMismatches += (f & kMaterialMismatch) != 0;
  }
  for (const auto& s : mesh.segments)
    r.missingSegmentPieces += th.segmentsRequired && !s.present;
  if (tetDefects)
    *tetDefects = std::move(flags);
  return r;
}
}
