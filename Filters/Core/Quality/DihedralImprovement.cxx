// SPDX-License-Identifier: GPL-3.0-or-later
#include "DihedralImprovement.h"

#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "TetStars.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace omesh
{
namespace
{
/// A tetrahedron whose longest edge is below this x the typical edge is not made: ten times the
/// validity check's micro threshold (MeshValidity.h), which measures against the median edge;
/// one that already was so small must not go below twice that threshold.
constexpr double kMicro = 1e-3;
constexpr double kMicroFloor = 2e-4;

/// A tetrahedron is peeled (DihedralImprover::peel) only when its height is below this x its
/// longest edge: the interface moves by no more than that.
constexpr double kPeelHeight = 0.2;

/// Why a tetrahedron may not be made (DihedralImprover::flaws).
constexpr unsigned kMicroFlaw = 1;  ///< longest edge below kMicro x the typical edge
constexpr unsigned kTinyFlaw = 2;   ///< below kMicroFloor x the typical edge
constexpr unsigned kLargeFlaw = 4;  ///< circumradius above its material's cell size
constexpr unsigned kAcrossFlaw = 8; ///< every vertex on an interface or line, centroid in another material

enum class VertexKind : unsigned char
{
  Fixed,
  Interior,
  Interface,
  OnLine ///< inside one straight feature segment: slides along it
};

/// Raises the worst tetrahedra by flips and vertex moves (see improveDihedralAngles).
class DihedralImprover
{
public:
  DihedralImprover(TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options)
    : mesh_(mesh)
    , oracle_(oracle)
    , options_(options)
    , stars_(mesh)
  {
    orientation_ = orientationOfMesh();
    microLength_ = kMicro * typicalEdge();
    classifyVertices();
  }

  DihedralImprovementReport run()
  {
    measure(report_.outsideBefore, report_.minBefore, report_.maxBefore);
    // A tetrahedron keeps its quality until one of its vertices moves: after the first round only
    // the ones left bad and the ones made or moved since can be bad.
    std::vector<int> candidates(stars_.size());
    for (std::size_t t = 0; t < candidates.size(); ++t)
      candidates[t] = static_cast<int>(t);
    bool changed = true;
    for (int round = 0; round < options_.rounds && changed; ++round)
    {
      changed = runRound(round, candidates);
      report_.rounds = round + 1;
    }
    report_.cutShort = changed && report_.rounds == options_.rounds && options_.rounds > 0;
    stars_.compact(mesh_);
    compactInterfaces();
    for (auto& piece : mesh_.segments) // their ends may have slid along the line
    {
      if (piece.aId >= 0)
        piece.a = mesh_.points[static_cast<std::size_t>(piece.aId)];
      if (piece.bId >= 0)
        piece.b = mesh_.points[static_cast<std::size_t>(piece.bId)];
    }
    measure(report_.outsideAfter, report_.minAfter, report_.maxAfter, &report_.outsideHeld);
    return report_;
  }

private:
  // --- measures ----------------------------------------------------------------------------
  double quality(const std::array<int, 4>& t) const
  {
    const auto& p = mesh_.points;
    if (orient(t) <= 0)
      return -1.0;
    return dihedralWindowQuality(p[t[0]], p[t[1]], p[t[2]], p[t[3]], options_.minAngle, options_.maxAngle);
  }
  double quality(int t) const { return quality(stars_.tet(t)); }

  /// Signed volume in the mesh's orientation (positive for its tetrahedra).
  double orient(const std::array<int, 4>& t) const
  {
    const auto& p = mesh_.points;
    return orientation_ * signedVolume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
  }

  /// The validity check's length (validityLength, MeshValidity.h), with the median of one edge per
  /// tetrahedron.
  double typicalEdge() const
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

  double orientationOfMesh() const
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

  /// Tetrahedra outside the window and the extreme angles; with `held`, the outside ones whose
  /// vertices are all held.
  void measure(std::size_t& outside, double& minAngle, double& maxAngle, std::size_t* held = nullptr) const
  {
    if (held)
      *held = 0;
    outside = 0;
    minAngle = 180.0;
    maxAngle = 0.0;
    const auto& p = mesh_.points;
    for (const auto& t : mesh_.tets)
    {
      double lo = 0.0, hi = 180.0;
      dihedralAngleRange(p[t[0]], p[t[1]], p[t[2]], p[t[3]], lo, hi);
      minAngle = std::min(minAngle, lo);
      maxAngle = std::max(maxAngle, hi);
      const bool out = lo < options_.minAngle || hi > options_.maxAngle;
      outside += out;
      if (held && out && std::all_of(t.begin(), t.end(), [&](int v) { return kind_[static_cast<std::size_t>(v)] == VertexKind::Fixed; }))
        ++*held;
    }
    if (mesh_.tets.empty())
      minAngle = maxAngle = 0.0;
  }

  double longestEdge(const std::array<int, 4>& t) const
  {
    const auto& p = mesh_.points;
    double longest = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        longest = std::max(longest, norm(p[t[i]] - p[t[j]]));
    return longest;
  }

  /// What keeps tetrahedron t of `material` out of the mesh (Flaw bits, 0 = nothing): micro (the
  /// checks would call it so, MeshValidity.h, whatever its angles), larger than its material's
  /// cell size, or, with all four vertices on interfaces or feature lines, its centroid in another
  /// material.
  unsigned flaws(const std::array<int, 4>& t, int material) const
  {
    const auto& p = mesh_.points;
    unsigned f = 0;
    const double longest = longestEdge(t);
    if (longest < microLength_)
      f |= longest < microLength_ * (kMicroFloor / kMicro) ? kMicroFlaw | kTinyFlaw : kMicroFlaw;
    if (options_.cellSizeOf)
    {
      const double size = options_.cellSizeOf(material);
      if (size > 0 && !(norm(p[t[0]] - circumcenter(p[t[0]], p[t[1]], p[t[2]], p[t[3]])) <= size))
        f |= kLargeFlaw;
    }
    if (std::none_of(t.begin(), t.end(), [&](int v) { return mesh_.pointDimension[static_cast<std::size_t>(v)] == 3; }) &&
      oracle_.material(0.25 * (p[t[0]] + p[t[1]] + p[t[2]] + p[t[3]])) != material)
      f |= kAcrossFlaw;
    return f;
  }

  bool acceptable(const std::array<int, 4>& t, int material) const { return flaws(t, material) == 0; }

  /// Whether the tetrahedra around v are acceptable; with `flawsBefore` (one set per star
  /// tetrahedron, taken before a move), a move need not mend what it found: a tetrahedron already
  /// larger than its cell size may stay so, one already below the micro length must stay above
  /// the floor; one already across a boundary may not be moved (it could only go further).
  bool starAcceptable(int v, const std::vector<unsigned>* flawsBefore = nullptr) const
  {
    const auto& star = stars_.star(v);
    for (std::size_t k = 0; k < star.size(); ++k)
    {
      const unsigned now = flaws(stars_.tet(star[k]), stars_.material(star[k]));
      const unsigned allowed = flawsBefore ? (*flawsBefore)[k] & (kLargeFlaw | kMicroFlaw) : 0u;
      if (now & ~allowed)
        return false;
    }
    return true;
  }

  /// Adds a tetrahedron and remembers it for the next round.
  int addTet(const std::array<int, 4>& t, int material)
  {
    const int id = stars_.add(t, material);
    touched_.push_back(id);
    return id;
  }

  // --- what may change -----------------------------------------------------------------------
  /// Interface triangles and feature edges are kept; vertices on one interface move along it,
  /// interior vertices anywhere, the others stay.
  void classifyVertices()
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

  /// A segment point between two present pieces of the same straight segment (not an input point)
  /// slides along it: its edges stay on the line.
  void classifyLineVertices()
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

  VertexKind classifyFree(int v) const
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

  bool isKept(int a, int b) const
  {
    if (kept_.count(edgeKey(a, b)))
      return true;
    // edges between two feature vertices: chords of protecting balls count as the line
    return mesh_.pointDimension[static_cast<std::size_t>(a)] <= 1 && mesh_.pointDimension[static_cast<std::size_t>(b)] <= 1;
  }
  bool isInterface(int a, int b, int c) const { return interfaces_.count(FaceKey(a, b, c)) != 0; }

  // --- rounds -----------------------------------------------------------------------------------
  /// Works through the bad tetrahedra among `candidates`, worst first; leaves in `candidates` the
  /// ones to look at next round (those still there and bad, and those made or moved).
  bool runRound(int round, std::vector<int>& candidates)
  {
    std::vector<std::pair<double, int>> bad;
    for (int t : candidates)
      if (stars_.alive(t))
      {
        const double q = quality(t);
        if (q < 1.0)
          bad.emplace_back(q, t);
      }
    std::sort(bad.begin(), bad.end());
    touched_.clear();
    bool changed = false;
    for (std::size_t k = 0; k < bad.size(); ++k)
    {
      if (options_.progress && (k & 63u) == 0)
        options_.progress((round + static_cast<double>(k) / bad.size()) / options_.rounds);
      const int t = bad[k].second;
      if (stars_.alive(t) && quality(t) < 1.0)
        changed = improveTet(t) || changed;
    }
    candidates = std::move(touched_);
    for (const auto& entry : bad)
      candidates.push_back(entry.second);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    return changed;
  }

  bool improveTet(int t)
  {
    const auto q = stars_.tet(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (removeEdge(q[i], q[j]))
          return true;
    for (int f = 0; f < 4; ++f)
      if (removeFace(t, f))
        return true;
    bool moved = false;
    for (int v : q)
    {
      if (!stars_.alive(t) || quality(t) >= 1.0)
        break;
      moved = moveVertex(v) || moved;
    }
    if (moved || !stars_.alive(t))
      return moved;
    if (peel(t))
      return true;
    // the last resort, for tetrahedra whose vertices cannot move (a thin layer between two
    // interfaces, feature lines): a new interior vertex on one of its edges, longest first
    std::array<std::pair<double, std::pair<int, int>>, 6> edges;
    int k = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edges[k++] = { -norm(mesh_.points[static_cast<std::size_t>(q[i])] - mesh_.points[static_cast<std::size_t>(q[j])]),
          { q[i], q[j] } };
    std::sort(edges.begin(), edges.end());
    for (const auto& e : edges)
      if (splitEdge(e.second.first, e.second.second))
        return true;
    return false;
  }

  /// Splits interior edge ab at its midpoint (each tetrahedron around it in two), moves the new
  /// vertex to where its star is best and keeps it when the star's worst beats the ring's before;
  /// else everything goes back.
  bool splitEdge(int a, int b)
  {
    std::vector<int> ring, old;
    if (!ringAround(a, b, ring, old))
      return false;
    const double before = worstOf(old);
    const int material = stars_.material(old.front());
    const int m = static_cast<int>(mesh_.points.size());
    const auto& p = mesh_.points;
    mesh_.points.push_back(splitPoint(a, b, ring, material));
    mesh_.pointDimension.push_back(3);
    kind_.push_back(VertexKind::Interior);
    sides_.push_back({ 0, 0 });
    interfaceAt_.emplace_back();
    stars_.addVertex();
    for (int t : old)
      stars_.remove(t);
    std::vector<int> made;
    for (std::size_t i = 0; i < ring.size(); ++i)
    {
      const int c = ring[i], d = ring[(i + 1) % ring.size()];
      made.push_back(addTet({ a, m, c, d }, material));
      made.push_back(addTet({ m, b, c, d }, material));
    }
    const std::size_t movesBefore = report_.interiorMoves;
    moveVertex(m);
    report_.interiorMoves = movesBefore;
    if (starQuality(m) > before + 1e-9 && starAcceptable(m) && oracle_.material(mesh_.points.back()) == material)
    {
      ++report_.edgeSplits;
      return true;
    }
    for (int t : made)
      stars_.remove(t);
    for (int t : old)
      stars_.revive(t);
    stars_.removeLastVertex();
    mesh_.points.pop_back();
    mesh_.pointDimension.pop_back();
    kind_.pop_back();
    sides_.pop_back();
    interfaceAt_.pop_back();
    return false;
  }

  // --- peeling --------------------------------------------------------------------------------
  /// A thin tetrahedron lying on a fold of an interface (every vertex on an interface, two faces
  /// on it towards the same side X, the edge between its other two faces inside its own material)
  /// goes over to X: the outside (it is removed) or the material beyond (and the edge it leaves
  /// inside X is removed, else it goes back). The interface then runs through its other two
  /// faces, at most its height away (CGAL's Tetrahedral_remeshing peels slivers the same way).
  /// Tetrahedra whose vertices are all held are reached this way only.
  bool peel(int t)
  {
    const auto q = stars_.tet(t);
    const int m = stars_.material(t);
    const auto& p = mesh_.points;
    for (int v : q)
      if (mesh_.pointDimension[static_cast<std::size_t>(v)] > 2)
        return false;
    if (!(smallestAltitude(p[q[0]], p[q[1]], p[q[2]], p[q[3]]) <= kPeelHeight * longestEdge(q)))
      return false;
    std::array<int, 4> side; // the material beyond the face opposite q[f], -1 outside
    for (int f = 0; f < 4; ++f)
    {
      const auto [a, b, c] = face(q, f);
      const int next = stars_.beyond(t, a, b, c);
      side[f] = next < 0 ? -1 : stars_.material(next);
      if (isInterface(a, b, c) != (side[f] != m))
        return false; // an interface that does not separate materials here: not ours to move
    }
    for (int f = 0; f < 4; ++f)
      for (int g = f + 1; g < 4; ++g)
      {
        // faces f and g towards x, the other two not
        const int x = side[f];
        int k1 = -1, k2 = -1;
        for (int e = 0; e < 4; ++e)
          if (e != f && e != g)
            (k1 < 0 ? k1 : k2) = e;
        if (x == m || side[g] != x || side[k1] == x || side[k2] == x)
          continue;
        const int a = q[k1], b = q[k2]; // the fold edge, shared by faces f and g
        const int c = q[f], d = q[g];   // shared by the other two faces
        // the other two faces towards t's own material: edge cd stays inside it (no pinch);
        // removed: cd must not be on the boundary already (no non-manifold edge)
        if (isKept(a, b) || (side[k1] == m && side[k2] == m && !insideOneMaterial(c, d, m)) ||
          (x < 0 && !closedAround(c, d)))
          continue;
        std::vector<Retriangulated> changes;
        for (int e : { f, g })
          changes.push_back({ face(q, e), { 0, 0 }, true });
        for (int e : { k1, k2 })
          changes.push_back({ face(q, e), { x, side[e] }, false });
        if (x < 0 ? removeToOutside(t, changes) : giveTo(t, x, a, b, changes))
          return true;
      }
    return false;
  }

  static std::array<int, 3> face(const std::array<int, 4>& q, int f)
  {
    return { q[(f + 1) & 3], q[(f + 2) & 3], q[(f + 3) & 3] };
  }

  /// Whether edge cd is inside material m: every tetrahedron around it of m, no face around it on
  /// an interface or the boundary.
  bool insideOneMaterial(int c, int d, int m) const
  {
    const auto around = stars_.around(c, d);
    for (int u : around)
    {
      if (stars_.material(u) != m)
        return false;
      for (int v : stars_.tet(u))
        if (v != c && v != d && isInterface(c, d, v))
          return false;
    }
    return !around.empty() && closedAround(c, d);
  }

  /// Whether the tetrahedra around edge cd close around it (no face at it on the boundary).
  bool closedAround(int c, int d) const
  {
    for (int u : stars_.around(c, d))
      for (int v : stars_.tet(u))
        if (v != c && v != d && stars_.beyond(u, c, d, v) < 0)
          return false;
    return true;
  }

  /// A face of a peeled tetrahedron: off every interface (`gone`), or on one between `materials`.
  struct Retriangulated
  {
    std::array<int, 3> tri;
    std::array<int, 2> materials;
    bool gone;
  };

  /// Tetrahedron t leaves the mesh; its faces towards the outside go, the others become the
  /// boundary.
  bool removeToOutside(int t, std::vector<Retriangulated>& changes)
  {
    for (int v : stars_.tet(t))
      if (stars_.star(v).size() < 2)
        return false;
    stars_.remove(t);
    swapInterfaces(changes);
    for (int v : stars_.tet(t)) // a removed tetrahedron keeps its vertices
      touched_.insert(touched_.end(), stars_.star(v).begin(), stars_.star(v).end());
    ++report_.peeled;
    return true;
  }

  /// Tetrahedron t goes from its material to x; kept when a flip inside x then removes it, or
  /// when removing its fold edge ab and moving the vertices around it does.
  bool giveTo(int t, int x, int a, int b, std::vector<Retriangulated>& changes)
  {
    const int m = stars_.material(t);
    const double before = quality(t);
    stars_.setMaterial(t, x);
    const auto undo = swapInterfaces(changes);
    const auto q = stars_.tet(t);
    bool done = false;
    for (int i = 0; i < 4 && !done; ++i)
      for (int j = i + 1; j < 4 && !done; ++j)
        done = removeEdge(q[i], q[j]);
    for (int f = 0; f < 4 && !done; ++f)
      done = removeFace(t, f);
    if (!done)
      done = removeEdgeAndMove(a, b, before);
    if (done)
    {
      ++report_.peeled;
      return true;
    }
    stars_.setMaterial(t, m);
    undoSwap(undo);
    return false;
  }

  /// Removes edge ab although that alone does not pay, then moves the vertices of its ring; kept
  /// when the new tetrahedra end better than `before`, else everything goes back.
  bool removeEdgeAndMove(int a, int b, double before)
  {
    std::vector<int> made, old;
    const auto report = report_;
    const std::size_t touched = touched_.size();
    if (!removeEdge(a, b, &made, &old))
      return false;
    std::vector<std::pair<int, Vec3>> positions;
    for (int t : made)
      for (int v : stars_.tet(t))
        if (v != a && v != b && std::none_of(positions.begin(), positions.end(), [&](const auto& e) { return e.first == v; }))
          positions.emplace_back(v, mesh_.points[static_cast<std::size_t>(v)]);
    for (const auto& [v, at] : positions)
      moveVertex(v);
    if (worstOf(made) > before + 1e-9)
      return true;
    for (const auto& [v, at] : positions)
      mesh_.points[static_cast<std::size_t>(v)] = at;
    for (int t : made)
      stars_.remove(t);
    for (int t : old)
      stars_.revive(t);
    report_ = report;
    touched_.resize(touched);
    return false;
  }

  /// What swapInterfaces changed, for undoSwap.
  struct InterfaceSwap
  {
    std::vector<int> gone, made;
    std::vector<std::pair<int, VertexKind>> kinds;
  };

  /// The interface triangles of `changes` that were on an interface go; those not `gone` come
  /// (again) with their materials. Vertices of one interface that now touch another are held.
  InterfaceSwap swapInterfaces(const std::vector<Retriangulated>& changes)
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

  void undoSwap(const InterfaceSwap& swap)
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

  /// Drops the peeled interface triangles from the mesh.
  void compactInterfaces()
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

  /// Where a new vertex on edge ab starts: its midpoint, or where that lies outside the material
  /// (a chord across a concave interface), the first point towards the centre of the ring that
  /// lies inside.
  Vec3 splitPoint(int a, int b, const std::vector<int>& ring, int material) const
  {
    const auto& p = mesh_.points;
    const Vec3 mid = 0.5 * (p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)]);
    if (oracle_.material(mid) == material)
      return mid;
    Vec3 centre{ 0, 0, 0 };
    for (int v : ring)
      centre = centre + p[static_cast<std::size_t>(v)];
    centre = (1.0 / static_cast<double>(ring.size())) * centre;
    for (double f : { 0.25, 0.5, 0.75 })
    {
      const Vec3 x = mid + f * (centre - mid);
      if (oracle_.material(x) == material)
        return x;
    }
    return mid;
  }

  // --- flips --------------------------------------------------------------------------------
  /// The ring of vertices around edge ab, ordered so that (a, b, r[i], r[i+1]) is positive, and the
  /// tetrahedra around it; false when the edge may not go (on a boundary, an interface or a feature
  /// line, between materials) or the ring is not closed.
  bool ringAround(int a, int b, std::vector<int>& ring, std::vector<int>& tets) const
  {
    if (isKept(a, b))
      return false;
    tets = stars_.around(a, b);
    if (tets.size() < 3 || tets.size() > 7)
      return false;
    const int material = stars_.material(tets.front());
    std::vector<std::pair<int, int>> next; // (c, d) with (a, b, c, d) positive
    for (int t : tets)
    {
      if (stars_.material(t) != material)
        return false;
      int cd[2], k = 0;
      for (int v : stars_.tet(t))
        if (v != a && v != b)
          cd[k++] = v;
      if (isInterface(a, b, cd[0]) || isInterface(a, b, cd[1]))
        return false;
      if (orient({ a, b, cd[0], cd[1] }) < 0)
        std::swap(cd[0], cd[1]);
      next.emplace_back(cd[0], cd[1]);
    }
    ring.assign(1, next.front().first);
    for (std::size_t k = 1; k < next.size(); ++k)
    {
      const auto it = std::find_if(next.begin(), next.end(), [&](const auto& e) { return e.first == ring.back(); });
      if (it == next.end())
        return false;
      ring.push_back(it->second);
    }
    const auto last = std::find_if(next.begin(), next.end(), [&](const auto& e) { return e.first == ring.back(); });
    return last != next.end() && last->second == ring.front() &&
      std::unordered_set<int>(ring.begin(), ring.end()).size() == ring.size();
  }

  /// Removes edge ab: its ring is triangulated the best way (Shewchuk's dynamic programme over the
  /// ring polygon), each triangle making one tetrahedron with a and one with b.
  /// With `made`: the edge goes even when that does not pay (as long as no tetrahedron is flat or
  /// inverted), and `made` receives the new tetrahedra, `old` the ones removed.
  bool removeEdge(int a, int b, std::vector<int>* made = nullptr, std::vector<int>* removed = nullptr)
  {
    std::vector<int> ring, old;
    if (!ringAround(a, b, ring, old))
      return false;
    const double before = made ? 0.0 : worstOf(old);
    const int n = static_cast<int>(ring.size());
    auto pairQuality = [&](int i, int k, int j) {
      return std::min(quality({ ring[i], ring[k], ring[j], b }), quality({ ring[j], ring[k], ring[i], a }));
    };
    std::vector<double> best(n * n, std::numeric_limits<double>::infinity());
    std::vector<int> split(n * n, -1);
    for (int len = 2; len < n; ++len)
      for (int i = 0; i + len < n; ++i)
      {
        const int j = i + len;
        double top = -std::numeric_limits<double>::infinity();
        for (int k = i + 1; k < j; ++k)
        {
          const double q = std::min({ best[i * n + k], best[k * n + j], pairQuality(i, k, j) });
          if (q > top)
          {
            top = q;
            split[i * n + j] = k;
          }
        }
        best[i * n + j] = top;
      }
    if (!(best[n - 1] > before + 1e-9))
      return false;
    const int material = stars_.material(old.front());
    std::vector<std::array<int, 4>> tets;
    std::vector<std::pair<int, int>> todo{ { 0, n - 1 } };
    while (!todo.empty())
    {
      const auto [i, j] = todo.back();
      todo.pop_back();
      if (j - i < 2)
        continue;
      const int k = split[i * n + j];
      tets.push_back({ ring[i], ring[k], ring[j], b });
      tets.push_back({ ring[j], ring[k], ring[i], a });
      todo.push_back({ i, k });
      todo.push_back({ k, j });
    }
    for (const auto& m : tets)
      if (!acceptable(m, material))
        return false;
    for (int t : old)
      stars_.remove(t);
    for (const auto& m : tets)
    {
      const int id = addTet(m, material);
      if (made)
        made->push_back(id);
    }
    if (removed)
      *removed = old;
    ++report_.edgeRemovals;
    return true;
  }

  /// 2-3 flip: face f of t and the same-material tetrahedron beyond it become three around the
  /// edge joining their apexes.
  bool removeFace(int t, int f)
  {
    const auto q = stars_.tet(t);
    const int d = q[f];
    const int a = q[(f + 1) & 3], b = q[(f + 2) & 3], c = q[(f + 3) & 3];
    if (isInterface(a, b, c))
      return false;
    const int other = stars_.beyond(t, a, b, c);
    if (other < 0 || stars_.material(other) != stars_.material(t))
      return false;
    int e = -1;
    for (int v : stars_.tet(other))
      if (v != a && v != b && v != c)
        e = v;
    std::array<int, 3> ring{ a, b, c };
    if (orient({ d, e, a, b }) < 0)
      std::swap(ring[1], ring[2]);
    const std::array<std::array<int, 4>, 3> made{ { { d, e, ring[0], ring[1] }, { d, e, ring[1], ring[2] },
      { d, e, ring[2], ring[0] } } };
    const double before = std::min(quality(t), quality(other));
    double after = std::numeric_limits<double>::infinity();
    for (const auto& m : made)
      after = std::min(after, quality(m));
    const int material = stars_.material(t);
    if (!(after > before + 1e-9) ||
      !std::all_of(made.begin(), made.end(), [&](const auto& m) { return acceptable(m, material); }))
      return false;
    stars_.remove(t);
    stars_.remove(other);
    for (const auto& m : made)
      addTet(m, material);
    ++report_.faceRemovals;
    return true;
  }

  // --- vertex moves -------------------------------------------------------------------------------
  double worstOf(const std::vector<int>& tets) const
  {
    double q = std::numeric_limits<double>::infinity();
    for (int t : tets)
      q = std::min(q, quality(t));
    return q;
  }

  double starQuality(int v, int* worst = nullptr) const
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

  double meanEdgeLength(int v) const
  {
    double sum = 0.0;
    int count = 0;
    for (int t : stars_.star(v))
      for (int u : stars_.tet(t))
        if (u != v)
        {
          sum += norm(mesh_.points[static_cast<std::size_t>(u)] - mesh_.points[static_cast<std::size_t>(v)]);
          ++count;
        }
    return count ? sum / count : 0.0;
  }

  /// Unit normal of the interface at v, pointing from sides_[v][0] to sides_[v][1] (area-weighted
  /// mean of its interface triangles'); zero when they do not agree on a side.
  Vec3 interfaceNormal(int v) const
  {
    Vec3 sum{ 0, 0, 0 };
    const auto pair = sides_[static_cast<std::size_t>(v)];
    for (int k : interfaceAt_[static_cast<std::size_t>(v)])
    {
      const auto& tri = mesh_.interfaceTriangles[static_cast<std::size_t>(k)];
      const auto& p = mesh_.points;
      Vec3 n = cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]]);
      // orient by a tetrahedron on the triangle: away from it on the first side, into it on the second
      for (int t : stars_.star(v))
      {
        const auto& q = stars_.tet(t);
        const auto apex = std::find_if(q.begin(), q.end(), [&](int u) { return u != tri[0] && u != tri[1] && u != tri[2]; });
        if (std::count_if(q.begin(), q.end(), [&](int u) { return u == tri[0] || u == tri[1] || u == tri[2]; }) != 3)
          continue;
        const double side = dot(n, p[*apex] - p[tri[0]]);
        if ((stars_.material(t) == pair[0]) == (side > 0))
          n = -1.0 * n;
        break;
      }
      sum = sum + n;
    }
    const double l = norm(sum);
    return l > 0 ? (1.0 / l) * sum : Vec3{ 0, 0, 0 };
  }

  /// x put back on v's interface: the change from sides_[v][0] to sides_[v][1] along `normal`
  /// within `reach`; false when there is none.
  bool onInterface(int v, const Vec3& normal, double reach, Vec3& x) const
  {
    const auto pair = sides_[static_cast<std::size_t>(v)];
    const Intersection hit = oracle_.intersect(x - reach * normal, x + reach * normal);
    if (!hit.found || hit.materialBefore != pair[0] || hit.materialAfter != pair[1])
      return false;
    x = hit.point;
    return true;
  }

  /// Gradient ascent on the star's worst quality (numerical gradient of the worst tetrahedron,
  /// halving steps until the star's worst rises); interface vertices move in the tangent plane and
  /// are put back on the interface.
  bool moveVertex(int v)
  {
    const VertexKind kind = kind_[static_cast<std::size_t>(v)];
    if (kind == VertexKind::Fixed)
      return false;
    Vec3& x = mesh_.points[static_cast<std::size_t>(v)];
    const Vec3 start = x;
    const double length = meanEdgeLength(v);
    const Vec3 normal = kind == VertexKind::Interface ? interfaceNormal(v) : Vec3{ 0, 0, 0 };
    if (kind == VertexKind::Interface && norm(normal) == 0.0)
      return false;
    int worst = -1;
    double current = starQuality(v, &worst);
    std::vector<unsigned> flawsBefore;
    for (int t : stars_.star(v))
      flawsBefore.push_back(flaws(stars_.tet(t), stars_.material(t)));
    Step s{ v, kind, normal, length, stars_.material(stars_.star(v).front()), current, worst, flawsBefore };
    for (int iteration = 0; iteration < 6 && s.current < 1.0; ++iteration)
    {
      // the worst tetrahedron's gradient; where another one blocks it, the axes (a pattern search)
      bool stepped = lineSearch(s, gradient(s.worst, v, 1e-4 * length));
      for (int axis = 0; axis < 6 && !stepped; ++axis)
      {
        Vec3 d{ 0, 0, 0 };
        d[axis / 2] = axis % 2 ? -1.0 : 1.0;
        stepped = lineSearch(s, d);
      }
      if (!stepped)
        break;
    }
    const bool moved = x.x != start.x || x.y != start.y || x.z != start.z;
    if (moved)
      touched_.insert(touched_.end(), stars_.star(v).begin(), stars_.star(v).end());
    if (moved)
      ++(kind == VertexKind::Interface ? report_.surfaceMoves
          : kind == VertexKind::OnLine ? report_.lineMoves
                                       : report_.interiorMoves);
    return moved;
  }

  /// A vertex being moved: where it may go and how good its star is.
  struct Step
  {
    int v;
    VertexKind kind;
    Vec3 normal;   ///< of its interface (Interface vertices move in the tangent plane)
    double length; ///< mean edge length around it
    int material;  ///< of its tetrahedra (an interior vertex's)
    double current;
    int worst;
    const std::vector<unsigned>& flawsBefore;
  };

  /// Moves s.v along `direction` (in the tangent plane for an interface vertex, then put back on
  /// the interface) by the longest of 0.2, 0.1, ... x the edge length that raises its star's worst
  /// quality; false (and the vertex where it was) when none does.
  bool lineSearch(Step& s, Vec3 direction)
  {
    if (s.kind == VertexKind::Interface)
      direction = direction - dot(direction, s.normal) * s.normal;
    else if (s.kind == VertexKind::OnLine)
    {
      const Vec3& line = lineDirection_.at(s.v);
      direction = dot(direction, line) * line;
    }
    const double dl = norm(direction);
    if (!(dl > 0))
      return false;
    Vec3& x = mesh_.points[static_cast<std::size_t>(s.v)];
    const Vec3 here = x;
    for (double step = 0.2 * s.length; step > 1e-3 * s.length; step *= 0.5)
    {
      Vec3 trial = here + (step / dl) * direction;
      if (s.kind == VertexKind::Interface && !onInterface(s.v, s.normal, 0.5 * s.length, trial))
        continue;
      // an interior vertex stays inside its material (its tetrahedra would reach across otherwise)
      if (s.kind == VertexKind::Interior && oracle_.material(trial) != s.material)
        continue;
      x = trial;
      int w = -1;
      const double q = starQuality(s.v, &w);
      if (q > s.current + 1e-9 && starAcceptable(s.v, &s.flawsBefore))
      {
        s.current = q;
        s.worst = w;
        return true;
      }
      x = here;
    }
    return false;
  }

  /// Central-difference gradient of tetrahedron t's quality with respect to vertex v's position.
  Vec3 gradient(int t, int v, double h)
  {
    Vec3& x = mesh_.points[static_cast<std::size_t>(v)];
    const Vec3 at = x;
    Vec3 g{ 0, 0, 0 };
    for (int axis = 0; axis < 3; ++axis)
    {
      x = at;
      x[axis] += h;
      const double up = quality(t);
      x = at;
      x[axis] -= h;
      const double down = quality(t);
      g[axis] = (up - down) / (2 * h);
    }
    x = at;
    return g;
  }

  TetMesh& mesh_;
  const HierarchicalOracle& oracle_;
  const DihedralImprovementOptions& options_;
  TetStars stars_;
  double orientation_ = 1.0;
  double microLength_ = 0.0; ///< no tetrahedron is made whose longest edge is shorter
  std::vector<VertexKind> kind_;
  std::vector<std::array<int, 2>> sides_;      ///< the two materials of an interface vertex
  std::vector<std::vector<int>> interfaceAt_;  ///< interface triangles at each vertex
  std::unordered_set<std::uint64_t> kept_;     ///< present feature-segment edges
  std::unordered_map<int, Vec3> lineDirection_; ///< of each OnLine vertex's segment (unit)
  std::unordered_map<FaceKey, int, FaceKeyHash> interfaces_; ///< -> index in mesh_.interfaceTriangles
  std::vector<unsigned char> interfaceGone_;                 ///< per interface triangle: peeled away
  DihedralImprovementReport report_;
  std::vector<int> touched_; ///< tetrahedra made or moved in this round
};
}

double dihedralWindowQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double minAngle,
  double maxAngle)
{
  double lo = 0.0, hi = 180.0;
  if (!dihedralAngleRange(a, b, c, d, lo, hi) || !(lo > 0))
    return -1.0;
  return std::min(lo / minAngle, (180.0 - hi) / (180.0 - maxAngle));
}

DihedralImprovementReport improveDihedralAngles(
  TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options)
{
  DihedralImprover improver(mesh, oracle, options);
  return improver.run();
}
}
