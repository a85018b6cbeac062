// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher's translation units (includes CGAL): the per-material refinement criteria,
// for the sequential and the parallel triangulation (MeshTriangulation3.h).
#pragma once

#include "MeshQuality.h"
#include "MesherCriteria3.h"
#include "MeshValidity.h"
#include "OracleMeshDomain.h"
#include "OracleMesher.h"

#include <CGAL/Mesh_criteria_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace omesh::cgal
{
inline double squared(double x) { return x * x; }

/// How a facet or cell touches protecting balls (vertices of positive weight), measured as CGAL's
/// criteria visitors with features measure it. Next to a ball CGAL does not apply a criterion to a
/// simplex that is small against the ball: there the refinement point lies on the power diagram
/// at about the ball's surface, every insertion makes a smaller simplex of the same kind, and
/// refinement converges onto one point of the sphere until a point repeats a vertex.
struct BallContact
{
  int balls = 0;          ///< vertices with a protecting ball
  bool ballsMeet = false; ///< two or more such balls with a common point
  /// Largest squared radius of the smallest sphere orthogonal to a ball and another vertex,
  /// relative to that ball's squared radius (0 when every vertex has a ball).
  double ratio = 0.0;
  /// True when a criterion with this bound on `ratio` is not applied (CGAL's rule).
  bool exempt(double bound) const { return (balls == 1 || ballsMeet) && ratio < bound; }
};

template <size_t N, class Tr>
inline BallContact ballContact(const Tr& tr, const std::array<const typename Tr::Weighted_point*, N>& v)
{
  const auto sqRadius = tr.geom_traits().compute_squared_radius_smallest_orthogonal_sphere_3_object();
  const auto compare = tr.geom_traits().compare_weighted_squared_radius_3_object();
  std::array<const typename Tr::Weighted_point*, N> ball{}, other{};
  size_t nb = 0, no = 0;
  for (const typename Tr::Weighted_point* p : v)
    (p->weight() > 0 ? ball[nb++] : other[no++]) = p;
  BallContact b;
  b.balls = static_cast<int>(nb);
  for (size_t i = 0; i < nb; ++i)
    for (size_t j = 0; j < no; ++j)
      b.ratio = std::max(b.ratio, CGAL::to_double(sqRadius(*ball[i], *other[j])) / ball[i]->weight());
  if (nb == 2)
    b.ballsMeet = compare(*ball[0], *ball[1], 0.0) != CGAL::LARGER;
  else if (nb == 3)
    b.ballsMeet = compare(*ball[0], *ball[1], *ball[2], 0.0) != CGAL::LARGER;
  else if (nb == 4)
    b.ballsMeet = compare(*ball[0], *ball[1], *ball[2], *ball[3], 0.0) != CGAL::LARGER;
  return b;
}

/// Below this radius-edge bound the interface sliver rule has a size floor, and the radius-edge
/// rule one more (MaterialCellCriterion).
constexpr double kSliverFloorRadiusEdge = 1.2;

/// The sliver bound of cells with all four vertices on interfaces or feature lines
/// (MesherOptions::enclosedSliverAngle, -1: the quality window's lower bound).
inline double enclosedSliverAngle(const MesherOptions& options)
{
  return options.enclosedSliverAngle < 0.0 ? options.improvementMinAngle : options.enclosedSliverAngle;
}

/// Below kSliverFloorRadiusEdge, cells with a circumradius under the finest size bound of any
/// material (cell, facet or edge size) divided by this are not refined for their radius-edge
/// ratio: see MaterialCellCriterion. Runs of the generated bone/implant case that end at
/// radius-edge 1.1 without it keep every cell above it (circumradius 0.024 mm and more against a
/// floor of 0.016: the same meshes with it); with 64 a run it stops made twice the vertices.
constexpr double kShapeFloorDivisor = 32.0;

/// The circumradius below which kShapeFloorDivisor's rule applies: 0 (none) when no material has
/// a size bound.
inline double shapeFloorRadius(const MaterialCriteria& c)
{
  double finest = std::numeric_limits<double>::infinity();
  auto take = [&finest](const MeshCriteria::Values& v) {
    for (double size : { v.cellSize, v.facetSize, v.edgeSize })
      if (size > 0)
        finest = std::min(finest, size);
  };
  take(c.globalValues());
  for (const auto& entry : c.perMaterial)
    take(c.of(entry.first));
  return std::isfinite(finest) ? finest / kShapeFloorDivisor : 0.0;
}

/// Per-material cell criteria: radius-edge ratio and circumradius bound of the cell's material
/// (the material of its circumcentre, set by Mesh_3 before the criteria are asked).
template <class Tr>
class MaterialCellCriterion
  : public CGAL::Mesh_3::Abstract_criterion<Tr, typename MesherCriteria<Tr>::Cell_criteria::Visitor>
{
protected:
  using Visitor = typename MesherCriteria<Tr>::Cell_criteria::Visitor;
  using Base = CGAL::Mesh_3::Abstract_criterion<Tr, Visitor>;
  using Quality = typename Base::Quality;
  using Is_bad = typename Base::Is_bad;

public:
  /// `oracle`: when given, the label rule below applies (the materials of the cells' centroids).
  /// `enclosedSliverAngle`: the bound of the sliver rule for cells with all four vertices on
  /// interfaces or feature lines (at least `interfaceSliverAngle`).
  MaterialCellCriterion(const MaterialCriteria& c, double sliverAngle, double interfaceSliverAngle,
    const HierarchicalOracle* oracle = nullptr, double enclosedSliverAngle = 0.0)
    : criteria_(c)
    , anySliverAngle_(sliverAngle)
    , interfaceSliverAngle_(interfaceSliverAngle)
    , enclosedSliverAngle_(std::max(enclosedSliverAngle, interfaceSliverAngle))
    , cosAnySliverAngle_(std::cos(sliverAngle * M_PI / 180.0))
    , cosInterfaceSliverAngle_(std::cos(interfaceSliverAngle * M_PI / 180.0))
    , cosEnclosedSliverAngle_(std::cos(enclosedSliverAngle_ * M_PI / 180.0))
    , shapeFloor_(shapeFloorRadius(c))
    , oracle_(oracle)
    , finestFacetDistance_(c.finestFacetDistance())
  {
  }

protected:
  void do_accept(Visitor& v) const override { v.visit(*this); }
  MaterialCellCriterion* do_clone() const override { return new MaterialCellCriterion(*this); }
  Is_bad do_is_bad(const Tr& tr, const typename Tr::Cell_handle& c) const override
  {
    const MeshCriteria::Values& m = criteria_.of(materialOf(c->subdomain_index()));
    const typename Tr::Weighted_point &wp = tr.point(c, 0), &wq = tr.point(c, 1), &wr = tr.point(c, 2), &ws = tr.point(c, 3);
    const auto &p = wp.point(), &q = wq.point(), &r = wr.point(), &s = ws.point();
    // CGAL's rules next to protecting balls (Cell_criteria_visitor_with_features): no shape
    // criterion on a cell with one ball or with balls that meet, no size bound on a small one.
    const BallContact near = ballContact<4, Tr>(tr, { &wp, &wq, &wr, &ws });
    const double sqRadius = CGAL::squared_radius(p, q, r, s);
    // Below radius-edge 1.2, no radius-edge rule on cells far below every size bound: where two
    // interfaces meet at a small angle along a curve that is no feature line (a cut plane
    // grazing an implant face on a voxel boundary, 14 degrees), radius-edge 1.1 refined the
    // cells around one point of that curve down to 1e-11 mm, sequential and parallel alike, into
    // the vertex budget with micro tetrahedra. The sliver rules still apply (with them off there
    // too, 1-4 degrees were left for the optimisers, which did not always lift them to 8.7).
    const bool belowShapeFloor = m.cellRadiusEdgeRatio > 0 && m.cellRadiusEdgeRatio < kSliverFloorRadiusEdge &&
      sqRadius < squared(shapeFloor_);
    const bool shapeExempt = belowShapeFloor || near.exempt(std::numeric_limits<double>::infinity());
    double worst = 1.0; // quality: bound / value, below 1 is bad
    if (m.cellSize > 0 && sqRadius > squared(m.cellSize) && !near.exempt(1.0))
      worst = std::min(worst, squared(m.cellSize) / sqRadius);
    if (m.cellRadiusEdgeRatio > 0 && !shapeExempt)
    {
      const double sqEdge = std::min({ CGAL::squared_distance(p, q), CGAL::squared_distance(p, r),
        CGAL::squared_distance(p, s), CGAL::squared_distance(q, r), CGAL::squared_distance(q, s),
        CGAL::squared_distance(r, s) });
      const double bound = squared(m.cellRadiusEdgeRatio) * sqEdge;
      if (sqRadius > bound)
        worst = std::min(worst, bound / sqRadius);
    }
    // Slivers: radius-edge refinement leaves them (even flat ones: four cocircular points have a
    // small circumradius), the optimisers remove most of them afterwards. Two rules refine them
    // here instead, not next to protecting balls (weighted vertices: the refinement point falls
    // in a ball and refinement never ends):
    // - any tetrahedron below `sliverAngle` (small by default: at radius-edge 1.3 a bound of 9
    //   degrees costs about 13% more tetrahedra; at 1.1 even 1 degree changes the counts a lot);
    // - with at least three vertices on interfaces or feature lines, below `interfaceSliverAngle`:
    //   the perturber and the exuder cannot fix these (those vertices only slide on their interface
    //   or stay on their line; seen: three points of a feature line and one free vertex). Two would
    //   be better for the angles (worst of 25 generated bone/implant cases at radius-edge 1.3: 10.9
    //   instead of 6.6 deg, +9% tets), but then radius-edge 1.1 no longer ends (three cases ran
    //   into a 300k-vertex budget that they met at 72k-180k with three).
    // - below radius-edge 1.2, the second rule only for cells with a circumradius of at least 1/8
    //   of their material's cell size: the circumcentre of a flat cell on an interface lies next to
    //   that interface, its insertion makes smaller interface slivers, and at radius-edge 1.1 that
    //   converged onto single points of the interfaces (a generated bone/implant case: 288k
    //   vertices, edges down to 0.005 mm for cell size 3; 50k with the floor). Smaller ones are
    //   left to the optimisers. Measured on 15 generated cases: a floor at 1/8 of the finest
    //   material's size let the cascades run on (up to 846k tets) and left slivers of 2 degrees;
    //   at radius-edge 1.3 the rule ends without a floor, and the floor left 5-degree slivers.
    // - with all four vertices on interfaces or feature lines, the same up to
    //   `enclosedSliverAngle` (the quality step's lower bound): that step moves no vertex where
    //   interfaces meet nor flips an interface triangle, so such a cell on a cut rim or a crease
    //   stayed at 11-13 degrees (generated CAD assemblies: median min 14.7 -> 15.0 degrees, 1-5 %
    //   more tetrahedra; the bone/implant study at radius-edge 1.1 ends as before).
    auto onInterface = [&](int i) { return c->vertex(i)->in_dimension() < 3; };
    auto weighted = [&](int i) { return tr.point(c, i).weight() != 0; };
    const int interfaceVertices = onInterface(0) + onInterface(1) + onInterface(2) + onInterface(3);
    const bool belowFloor = m.cellRadiusEdgeRatio > 0 && m.cellRadiusEdgeRatio < kSliverFloorRadiusEdge &&
      m.cellSize > 0 && sqRadius < squared(m.cellSize / 8.0);
    // the bound and its cosine, chosen together
    double sliverBound = anySliverAngle_, cosBound = cosAnySliverAngle_;
    if (interfaceVertices >= 3 && !belowFloor)
    {
      const bool enclosed = interfaceVertices == 4;
      const double bound = enclosed ? enclosedSliverAngle_ : interfaceSliverAngle_;
      if (bound > sliverBound)
      {
        sliverBound = bound;
        cosBound = enclosed ? cosEnclosedSliverAngle_ : cosInterfaceSliverAngle_;
      }
    }
    if (sliverBound > 0 && worst >= 1.0 && !(weighted(0) || weighted(1) || weighted(2) || weighted(3)))
    {
      // most cells are above the bound (92 % of those asked on the label map at h 4): squared
      // cosines say so without the angle's square roots, divisions and acos (~340 instructions
      // instead of ~480); the angle itself only where it may decide
      const Vec3 vp = toVec(p), vq = toVec(q), vr = toVec(r), vs = toVec(s);
      if (!dihedralAnglesCertainlyAtLeast(vp, vq, vr, vs, cosBound))
      {
        const double a = minDihedralAngle(vp, vq, vr, vs);
        if (a < sliverBound)
          worst = 0.99 * a / sliverBound;
      }
    }
    if (worst >= 1.0 && oracle_ && !(weighted(0) || weighted(1) || weighted(2) || weighted(3)))
      worst = labelQuality(c, p, q, r, s);
    return worst < 1.0 ? Is_bad(Quality(worst)) : Is_bad();
  }

  /// The label rule: a cell with all four vertices on interfaces or feature lines whose centroid
  /// lies in another material than its circumcentre (which gave it its material) spans a part it
  /// does not belong to. At an acute edge of a part (an 18.4 degree wedge, every edge a feature
  /// line) the restricted Delaunay surface met every facet criterion, yet cells from one face to
  /// the other had their circumcentres outside the wedge: 84 housing cells inside it, -2.6 % of
  /// its volume, unreported (the facet distance is measured along the facets' dual edges, which
  /// such facets pass). Refining these cells (their circumcentres encroach the facets across the
  /// part, which the facet level then splits on the surface) samples the faces until the labels
  /// agree. Only cells that reach across by more than the finer facet distance of the two
  /// materials (acrossBoundaryBy): a thinner cell, or one across a layer of the other material
  /// thinner than itself, misplaces the boundary by less than the facet criterion allows, and near
  /// the edge itself the rule would refine towards it without end. Measured alternatives
  /// (docs/MESHER.md): the longest edge instead of the smallest altitude cost up to 4.9x the
  /// tetrahedra of a CAD part; the altitude without the layer test 1.6x those of a label map.
  double labelQuality(const typename Tr::Cell_handle& c, const K::Point_3& p, const K::Point_3& q,
    const K::Point_3& r, const K::Point_3& s) const
  {
    if (!(finestFacetDistance_ > 0))
      return 1.0;
    for (int i = 0; i < 4; ++i)
      if (c->vertex(i)->in_dimension() >= 3)
        return 1.0;
    const Vec3 a = toVec(p), b = toVec(q), d = toVec(r), e = toVec(s);
    const double height = smallestAltitude(a, b, d, e);
    if (height <= finestFacetDistance_) // no material's bound is finer: spare the oracle's queries
      return 1.0;
    const HierarchicalOracle& oracle = *oracle_;
    const double by = acrossBoundaryBy(
      a, b, d, e, materialOf(c->subdomain_index()), [this](int material) { return criteria_.of(material).facetDistance; },
      [&oracle](const Vec3& x) { return oracle.material(x); });
    return by > 0 ? 0.5 * by / height : 1.0;
  }

private:
  MaterialCriteria::Resolved criteria_;
  double anySliverAngle_;
  double interfaceSliverAngle_;
  double enclosedSliverAngle_;
  double cosAnySliverAngle_;       ///< cosines of the three bounds (dihedralAnglesCertainlyAtLeast)
  double cosInterfaceSliverAngle_;
  double cosEnclosedSliverAngle_;
  double shapeFloor_; ///< shapeFloorRadius
  const HierarchicalOracle* oracle_; ///< the label rule's (labelQuality), or none
  double finestFacetDistance_;       ///< of any material (0: none): no cell below it is asked
};

/// Per-material facet criteria (angle, surface Delaunay ball radius, centre-to-surface distance).
/// An interface facet takes the stricter bound of the materials on its two sides.
template <class Tr>
class MaterialFacetCriterion
  : public CGAL::Mesh_3::Abstract_criterion<Tr, typename MesherCriteria<Tr>::Facet_criteria::Visitor>
{
protected:
  using Visitor = typename MesherCriteria<Tr>::Facet_criteria::Visitor;
  using Base = CGAL::Mesh_3::Abstract_criterion<Tr, Visitor>;
  using Quality = typename Base::Quality;
  using Is_bad = typename Base::Is_bad;

public:
  explicit MaterialFacetCriterion(const MaterialCriteria& c)
    : criteria_(c)
  {
    // every facet asked for sin^2 of its angle bound (a libm sin a facet, ~2 % of a coarse label
    // map's refinement): the bounds of the materials' angles, computed once
    addAngleBound(c.globalValues().facetAngle);
    for (const auto& entry : c.perMaterial)
      addAngleBound(c.of(entry.first).facetAngle);
  }

protected:
  void do_accept(Visitor& v) const override { v.visit(*this); }
  MaterialFacetCriterion* do_clone() const override { return new MaterialFacetCriterion(*this); }
  Is_bad do_is_bad(const Tr& tr, const typename Tr::Facet& f) const override
  {
    const auto patch = f.first->surface_patch_index(f.second);
    const MeshCriteria::Values& a = criteria_.of(materialOf(patch.first));
    const MeshCriteria::Values& b = criteria_.of(materialOf(patch.second));
    auto strict = [](double x, double y) { return x > 0 && y > 0 ? std::min(x, y) : std::max(x, y); };
    const double angle = std::max(a.facetAngle, b.facetAngle);
    const double size = strict(a.facetSize, b.facetSize);
    const double distance = strict(a.facetDistance, b.facetDistance);

    // As CGAL's standard facet criteria, with weighted points (protecting balls have weights).
    const typename Tr::Weighted_point& w1 = tr.point(f.first, (f.second + 1) & 3);
    const typename Tr::Weighted_point& w2 = tr.point(f.first, (f.second + 2) & 3);
    const typename Tr::Weighted_point& w3 = tr.point(f.first, (f.second + 3) & 3);
    const K::Point_3& p1 = w1.point();
    const K::Point_3& p2 = w2.point();
    const K::Point_3& p3 = w3.point();
    const K::Point_3& centre = f.first->get_facet_surface_center(f.second);
    // CGAL's bounds on the ratio (Facet_criterion_visitor_with_features): angle, size, distance.
    const BallContact near = ballContact<3, Tr>(tr, { &w1, &w2, &w3 });
    double worst = 1.0;
    if (angle > 0 && !near.exempt(1.0))
    {
      // sin^2 of the smallest angle: 4 area^2 min(d^2) / (d12^2 d13^2 d23^2)
      const double d12 = CGAL::squared_distance(p1, p2), d13 = CGAL::squared_distance(p1, p3),
                   d23 = CGAL::squared_distance(p2, p3);
      const double sqSin = 4.0 * CGAL::squared_area(p1, p2, p3) * std::min({ d12, d13, d23 }) / (d12 * d13 * d23);
      const double bound = angleBound(angle);
      if (sqSin < bound)
        worst = std::min(worst, sqSin / bound);
    }
    if (size > 0 && !near.exempt(0.64))
    {
      const double sqRadius = tr.min_squared_distance(p1, centre);
      if (sqRadius > squared(size))
        worst = std::min(worst, squared(size) / sqRadius);
    }
    if (distance > 0 && !near.exempt(0.04))
    {
      const K::Point_3 c = tr.geom_traits().construct_weighted_circumcenter_3_object()(w1, w2, w3);
      const double sqDist = tr.min_squared_distance(c, centre);
      if (sqDist > squared(distance))
        worst = std::min(worst, squared(distance) / sqDist);
    }
    return worst < 1.0 ? Is_bad(Quality(worst)) : Is_bad();
  }

private:
  static double sqSinBound(double angle) { return squared(std::sin(angle * M_PI / 180.0)); }
  void addAngleBound(double angle)
  {
    for (int i = 0; i < angles_; ++i)
      if (angleBounds_[i].first == angle)
        return;
    if (angles_ < static_cast<int>(angleBounds_.size()))
      angleBounds_[angles_++] = { angle, sqSinBound(angle) };
  }
  /// sin^2 of `angle` (degrees): the value computed once for a material's angle, else computed.
  double angleBound(double angle) const
  {
    for (int i = 0; i < angles_; ++i)
      if (angleBounds_[i].first == angle)
        return angleBounds_[i].second;
    return sqSinBound(angle);
  }

  MaterialCriteria::Resolved criteria_;
  std::array<std::pair<double, double>, 8> angleBounds_{}; ///< (angle, sin^2 of it), the first angles_
  int angles_ = 0;
};
/// The mesher's criteria: ours per material (MaterialFacetCriterion, MaterialCellCriterion) and
/// CGAL's topology criterion (facet vertices on the surface, T2); `edges` bounds the protecting
/// balls (the sequential mesher's stops its feature protection on time: StoppableEdgeSize);
/// `sliverAngle` the angle below which any cell is refined (MesherOptions::sliverAngle, or the
/// conforming one where refinement points are picked); `oracle` the label rule's
/// (MaterialCellCriterion::labelQuality).
template <class Tr>
MesherCriteria<Tr> materialMeshCriteria(const MesherOptions& options,
  const typename MesherCriteria<Tr>::Edge_criteria& edges, double sliverAngle, const HierarchicalOracle* oracle)
{
  using Criteria = MesherCriteria<Tr>;
  // no CGAL size, angle, distance or radius-edge criterion (bounds 0): the mesher's visitors
  // (CellCriteriaVisitor, FacetCriteriaVisitor) keep CGAL's ball rules for the other criteria only
  typename Criteria::Facet_criteria facetCriteria(0.0, 0.0, 0.0, CGAL::FACET_VERTICES_ON_SURFACE);
  typename Criteria::Cell_criteria cellCriteria(0.0, 0.0);
  Criteria criteria(edges, facetCriteria, cellCriteria);
  criteria.add_facet_criterion(new MaterialFacetCriterion<Tr>(options.criteria));
  criteria.add_cell_criterion(
    new MaterialCellCriterion<Tr>(options.criteria, sliverAngle, options.interfaceSliverAngle, oracle,
      enclosedSliverAngle(options)));
  return criteria;
}

/// Balls (centre, radius) where the finishing round after the vertex budget applies the run's
/// criteria in full: around the constrained sub-segments that no cell of the complex holds yet.
/// Asked for every vertex of every facet and cell the round looks at: the balls are binned in a
/// grid of the largest radius, so a query looks at the balls of one bin.
class CriteriaRegion
{
public:
  void add(const Vec3& centre, double radius)
  {
    balls_.push_back({ centre, radius });
    bins_.clear();
  }
  size_t size() const { return balls_.size(); }
  bool empty() const { return balls_.empty(); }

  /// Bins the balls (after the last add, before the queries).
  void index()
  {
    bins_.clear();
    bin_ = 0.0;
    for (const auto& b : balls_)
      bin_ = std::max(bin_, b.second);
    if (!(bin_ > 0.0))
      bin_ = 1.0;
    for (size_t i = 0; i < balls_.size(); ++i)
    {
      const auto lo = cellOf(balls_[i].first - balls_[i].second * Vec3{ 1, 1, 1 });
      const auto hi = cellOf(balls_[i].first + balls_[i].second * Vec3{ 1, 1, 1 });
      for (long long x = lo[0]; x <= hi[0]; ++x)
        for (long long y = lo[1]; y <= hi[1]; ++y)
          for (long long z = lo[2]; z <= hi[2]; ++z)
            bins_[key({ x, y, z })].push_back(i);
    }
  }

  bool contains(const Vec3& p) const
  {
    if (balls_.empty())
      return false;
    const auto it = bins_.find(key(cellOf(p)));
    if (it == bins_.end())
      return false;
    return std::any_of(it->second.begin(), it->second.end(),
      [&](size_t i) { return norm(p - balls_[i].first) <= balls_[i].second; });
  }
  /// One of the element's vertices lies in a ball.
  template <class Tr, size_t N>
  bool touches(const std::array<const typename Tr::Weighted_point*, N>& v) const
  {
    return std::any_of(v.begin(), v.end(), [&](const typename Tr::Weighted_point* p) { return contains(toVec(p->point())); });
  }

private:
  std::array<long long, 3> cellOf(const Vec3& p) const
  {
    return { static_cast<long long>(std::floor(p.x / bin_)), static_cast<long long>(std::floor(p.y / bin_)),
      static_cast<long long>(std::floor(p.z / bin_)) };
  }
  static unsigned long long key(const std::array<long long, 3>& c)
  {
    // 21 bits per axis: the balls lie in the domain's box, a few thousand bins across at most
    auto bits = [](long long v) { return static_cast<unsigned long long>(v) & ((1ull << 21) - 1); };
    return bits(c[0]) | bits(c[1]) << 21 | bits(c[2]) << 42;
  }

  std::vector<std::pair<Vec3, double>> balls_;
  double bin_ = 1.0;
  std::unordered_map<unsigned long long, std::vector<size_t>> bins_;
};

/// The run's cell criterion, asked only of cells with a vertex in `region`.
template <class Tr>
class RegionalCellCriterion : public MaterialCellCriterion<Tr>
{
  using Base = MaterialCellCriterion<Tr>;

public:
  RegionalCellCriterion(std::shared_ptr<const CriteriaRegion> region, const MaterialCriteria& c, double sliverAngle,
    double interfaceSliverAngle, double enclosedSliverAngle)
    : Base(c, sliverAngle, interfaceSliverAngle, nullptr, enclosedSliverAngle)
    , region_(std::move(region))
  {
  }

protected:
  RegionalCellCriterion* do_clone() const override { return new RegionalCellCriterion(*this); }
  typename Base::Is_bad do_is_bad(const Tr& tr, const typename Tr::Cell_handle& c) const override
  {
    if (!region_->template touches<Tr, 4>({ &tr.point(c, 0), &tr.point(c, 1), &tr.point(c, 2), &tr.point(c, 3) }))
      return typename Base::Is_bad();
    return Base::do_is_bad(tr, c);
  }

private:
  std::shared_ptr<const CriteriaRegion> region_;
};

/// The run's facet criterion, asked only of facets with a vertex in `region`.
template <class Tr>
class RegionalFacetCriterion : public MaterialFacetCriterion<Tr>
{
  using Base = MaterialFacetCriterion<Tr>;

public:
  RegionalFacetCriterion(std::shared_ptr<const CriteriaRegion> region, const MaterialCriteria& c)
    : Base(c)
    , region_(std::move(region))
  {
  }

protected:
  RegionalFacetCriterion* do_clone() const override { return new RegionalFacetCriterion(*this); }
  typename Base::Is_bad do_is_bad(const Tr& tr, const typename Tr::Facet& f) const override
  {
    if (!region_->template touches<Tr, 3>({ &tr.point(f.first, (f.second + 1) & 3),
          &tr.point(f.first, (f.second + 2) & 3), &tr.point(f.first, (f.second + 3) & 3) }))
      return typename Base::Is_bad();
    return Base::do_is_bad(tr, f);
  }

private:
  std::shared_ptr<const CriteriaRegion> region_;
};

/// The criteria of the finishing round after the vertex budget (RefinementRounds::finishAfterBudget):
/// what a valid mesh needs, not what makes it fine. Everywhere: CGAL's topology criterion (every
/// restricted facet has its three vertices on the surface, T2: the boundary stays a restricted
/// Delaunay surface) and the rule that refines any cell below `sliverAngle` (flat tetrahedra, at
/// picked points where the cell level picks); no angle, size, distance, radius-edge or
/// interface-sliver bound. In `region` (balls around the constrained sub-segments no cell of the
/// complex holds) the run's own criteria (`options`, `runSliverAngle`): splitting such a
/// sub-segment alone does not bring it into the complex where the surface around it is still
/// coarse (its cells' circumcentres stay outside, and the section-5 rule splits it down to the
/// split floor); the full criteria refine there as a finished run does. The segment level has
/// no criterion of its own to relax (a sub-segment is split when encroached, refused a point, or
/// missing from the complex). `edges` is the run's (only feature protection reads it).
template <class Tr>
MesherCriteria<Tr> validityMeshCriteria(const MesherOptions& options,
  const typename MesherCriteria<Tr>::Edge_criteria& edges, double sliverAngle, double runSliverAngle,
  std::shared_ptr<const CriteriaRegion> region)
{
  using Criteria = MesherCriteria<Tr>;
  typename Criteria::Facet_criteria facetCriteria(0.0, 0.0, 0.0, CGAL::FACET_VERTICES_ON_SURFACE);
  typename Criteria::Cell_criteria cellCriteria(0.0, 0.0);
  Criteria criteria(edges, facetCriteria, cellCriteria);
  MaterialCriteria unbounded; // every value 0: no bound (MeshCriteria: values <= 0 mean none)
  for (int k = 0; k < MeshCriteria::kCount; ++k)
    unbounded.global[k] = 0.0;
  criteria.add_cell_criterion(new MaterialCellCriterion<Tr>(unbounded, sliverAngle, 0.0));
  if (region && !region->empty())
  {
    criteria.add_facet_criterion(new RegionalFacetCriterion<Tr>(region, options.criteria));
    criteria.add_cell_criterion(
      new RegionalCellCriterion<Tr>(region, options.criteria, runSliverAngle, options.interfaceSliverAngle,
        enclosedSliverAngle(options)));
  }
  return criteria;
}
}
