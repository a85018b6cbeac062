// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "BoundingBox.h"
#include "Vec3.h"

#include <array>
#include <string>
#include <vector>

namespace omesh
{
/// Material id for "not in any material". Material ids are >= 0.
constexpr int kOutside = -1;

/// A sharp edge of one input's own boundary (a box's edge, a finite cylinder's rim, a surface's
/// sharp edge), given exactly: `points` lie on it in order (a closed crease repeats its first point
/// last); between them it is straight (box, surface) or a curve whose chords keep within the sagitta
/// asked for (cylinder rims). `normals[k]` are the two faces' outward unit normals beside chord k.
struct Crease
{
  std::vector<Vec3> points;
  std::vector<std::array<Vec3, 2>> normals;
  /// 180 degrees minus the angle between the two faces' normals (a box: 90, the dihedral angle
  /// inside a convex crease), the smallest along the crease.
  double dihedral = 90.0;
  bool closed() const
  {
    return points.size() > 2 && points.front().x == points.back().x && points.front().y == points.back().y &&
      points.front().z == points.back().z;
  }
};

/// The first change of a domain's material along a segment ab, as the domain itself shows it
/// (Domain::firstChange).
struct ShownChange
{
  bool found = false;    ///< the material changes along ab
  double t = 0.0;        ///< where it first changes (a parameter on ab, as the crossings')
  int before = kOutside; ///< the material at a
  int after = kOutside;  ///< the material just past t
};

/// One input of the hierarchical oracle: a region of space that assigns materials to the points it
/// contains. Implementations must be safe to query from several threads at once (const queries).
/// A plane across which a domain's boundary may bend: a point on it and its normal (not unit).
struct BendPlane
{
  Vec3 point;
  Vec3 normal;
};

class Domain
{
public:
  virtual ~Domain() = default;

  /// Material id at p, or kOutside when the domain does not contain p. Boundary points count as
  /// contained (the domain is a closed set).
  virtual int material(const Vec3& p) const = 0;

  /// Appends to `ts` parameters t in [0, 1] of segment a + t (b - a) where this domain's material
  /// may change. Every true change must be listed (a superset is allowed): the oracle evaluates the
  /// combined labelling between consecutive candidates, which makes intersection exact.
  virtual void crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const = 0;
  /// As crossings(), for a caller that needs only the first `changes` true changes: a domain may
  /// stop its search after them, listing a candidate after the last one up to which the material
  /// after it holds (the oracle of one domain asks for its first change). Returns true only when
  /// it has shown, without sampling, that its material is the same everywhere on [a, b] (the oracle
  /// of one domain then skips its own checks at the candidates' midpoints and at b); false when it
  /// cannot tell.
  virtual bool firstCrossings(const Vec3& a, const Vec3& b, std::vector<double>& ts, int changes) const
  {
    (void)changes;
    crossings(a, b, ts);
    return false;
  }
  /// For the oracle of this domain alone (not a cut): the material at a and the first change
  /// along ab, where the domain can show them without sampling and without the oracle's checks
  /// (true: `shown` filled, exactly what the oracle's checks of the candidates would give up to
  /// rounding); otherwise false, with ts and the return value `candidatesShown` of
  /// firstCrossings(a, b, ts, 1).
  virtual bool firstChange(const Vec3& a, const Vec3& b, ShownChange& shown, std::vector<double>& ts,
    bool& candidatesShown) const
  {
    (void)shown;
    candidatesShown = firstCrossings(a, b, ts, 1);
    return false;
  }

  /// World bounds of the contained region; unbounded domains (half-spaces, infinite cylinders)
  /// return false from bounded().
  virtual BoundingBox bounds() const = 0;
  virtual bool bounded() const { return true; }

  /// Short kind name used in messages and metadata ("Surface", "LabelMap", "Sphere", ...).
  virtual const char* kind() const = 0;

  /// Material ids this domain can return (for per-material reports).
  virtual std::vector<int> materials() const = 0;

  /// The creases of this domain's own boundary where its faces' normals differ by more than
  /// `featureAngle` degrees; curved ones sampled with chords within `sagitta` of them. Smooth
  /// shapes (spheres, half-spaces, label maps: their voxel staircase is no crease) have none.
  virtual std::vector<Crease> creases(double featureAngle, double sagitta) const
  {
    (void)featureAngle, (void)sagitta;
    return {};
  }

  /// Appends the planes segment ab crosses (point: the crossing) along which this domain's
  /// boundaries are continuous but not smooth, so that curves on them turn there: a label map's
  /// trilinear cells meet at the planes through its voxel centres, its staircase turns at voxel
  /// faces. Smooth shapes have none; the creases of surfaces and boxes are creases().
  virtual void bendPlanes(const Vec3& a, const Vec3& b, std::vector<BendPlane>& planes) const
  {
    (void)a, (void)b, (void)planes;
  }

  const std::string& name() const { return name_; }
  void setName(const std::string& n) { name_ = n; }

  /// A cut domain turns the points it contains into "outside" for itself and every domain of lower
  /// priority (paper section 3.1).
  bool isCut() const { return cut_; }
  void setCut(bool c) { cut_ = c; }

protected:
  /// Helper for single-material kinds.
  static void checkMaterialId(int id, const std::string& who);

private:
  std::string name_;
  bool cut_ = false;
};
}
