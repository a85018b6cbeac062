// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace omesh
{
/// Delaunay-refinement criteria (paper section 2 / CGAL Mesh_3): the one criteria type of every
/// level (defaults, global, per domain, per material). A value of 0 means "no bound"; an empty
/// field (std::nullopt) means "not set here": the next less specific level's value counts. Negative
/// values are errors (check()): a typed "-2" must not pass as "no bound".
///
/// The merge rule (MaterialCriteria::of): defaults < global < per domain < per material, the
/// more specific value wins. "Per domain" are a domain's own criteria, which apply to each material
/// the domain gives (every label of a label map); "per material" name one material id (the
/// tetrahedralizer's table, the scene's "mesh.materials"). Two sources of one level that give one
/// material's criterion different values are a contradiction: CriteriaLevel::add throws.
/// EdgeSize, the bound of the constrained segments' pieces, has one more level, per feature:
/// global < per material < per feature. A feature line's own value (FeatureSegments::edgeSizes:
/// the feature polydata's "EdgeSize" cell array, a scene feature entry's "edge_size") wins; else
/// the finest EdgeSize set by the materials the line separates or lies in (a surface domain's own
/// EdgeSize thus applies to its sharp edges); else the global one (featureEdgeSize in
/// FeatureEdgeSizes.h). One line given two different values is a contradiction
/// (mergeFeatureSegments throws).
struct MeshCriteria
{
  std::optional<double> facetAngle;          ///< lower bound of facet angles, degrees (<= 30 for termination)
  std::optional<double> facetSize;           ///< upper bound of the surface Delaunay ball radius
  std::optional<double> facetDistance;       ///< upper bound of facet-centre-to-surface distance
  std::optional<double> cellSize;            ///< upper bound of the tetrahedron circumradius
  std::optional<double> cellRadiusEdgeRatio; ///< upper bound of circumradius / shortest edge (>= 2 guaranteed)
  std::optional<double> edgeSize;            ///< upper bound of constrained-segment length

  static constexpr int kCount = 6;
  /// Names in field order: the VTK properties ("FacetAngle") and the scene keys ("facet_angle").
  static const std::array<const char*, kCount>& propertyNames();
  static const std::array<const char*, kCount>& sceneKeys();

  /// The defaults, the one source of them (the VTK filter, the plugin XML, the scene loader and
  /// the command line take theirs from here): facet angle 25, radius-edge ratio 3, no size bound.
  static MeshCriteria defaults();
  /// Nothing set (every field inherits). Kept for the tests' readability.
  static MeshCriteria inheritAll() { return {}; }

  std::optional<double>& operator[](int k);
  const std::optional<double>& operator[](int k) const;

  /// This, with every unset field taken from `base`.
  MeshCriteria over(const MeshCriteria& base) const;

  /// Resolved values: what the mesher reads, every field set (unset ones from defaults()).
  struct Values
  {
    double facetAngle, facetSize, facetDistance, cellSize, cellRadiusEdgeRatio, edgeSize;
  };
  Values values() const;

  /// The VTK layer's spelling of "not set".
  static constexpr double kUnset = -1.0;
  /// From six numbers as the VTK layer spells them: exactly kUnset = not set; every other value is
  /// kept (a NaN or another negative one then fails check(), which names it).
  static MeshCriteria fromVtk(const std::array<double, kCount>& v);
  /// Throws InputError when a set field is NaN, infinite or negative, naming it and `who`.
  void check(const std::string& who) const;
};

/// Global criteria plus per-material ones, merged by the rule above.
struct MaterialCriteria
{
  MeshCriteria global = MeshCriteria::defaults();
  std::map<int, MeshCriteria> perMaterial; ///< per domain and per material already merged

  /// Material m's resolved criteria: perMaterial[m] over global over the defaults.
  MeshCriteria::Values of(int material) const;
  MeshCriteria::Values globalValues() const { return global.values(); }
  /// The smallest facet distance of any material; 0 when none has one.
  double finestFacetDistance() const;

  /// Every material's resolved criteria, computed once: the mesher's criteria ask for them per
  /// facet and cell (of() resolving each time costs ~4 % of a coarse label map's refinement).
  class Resolved
  {
  public:
    explicit Resolved(const MaterialCriteria& c);
    /// The same values as MaterialCriteria::of(material).
    const MeshCriteria::Values& of(int material) const
    {
      if (perMaterial_.empty())
        return global_;
      auto it = perMaterial_.find(material);
      return it == perMaterial_.end() ? global_ : it->second;
    }

  private:
    MeshCriteria::Values global_;
    std::map<int, MeshCriteria::Values> perMaterial_;
  };
};

/// One level of per-material criteria (the domains' or the per-material table's), remembering
/// where each value came from so that a contradiction names both sources.
class CriteriaLevel
{
public:
  /// Adds `c` (its set fields) for `material`, from `source` ("domain 'implant'"). Throws
  /// InputError when a field already has a different value at this level:
  /// "criteria: material 3 gets CellSize 1 from domain 'a' and 2 from domain 'b' (...)".
  void add(int material, const MeshCriteria& c, const std::string& source);
  const std::map<int, MeshCriteria>& criteria() const { return criteria_; }

private:
  std::map<int, MeshCriteria> criteria_;
  std::map<std::pair<int, int>, std::string> sources_;
};

/// `global` with the levels on top, least specific first (the domains', then the table's).
MaterialCriteria mergeCriteria(const MeshCriteria& global, const std::vector<const CriteriaLevel*>& levels);

/// Termination and sizing warnings for `c`; throws InputError for NaN or infinite values.
void checkCriteria(const MaterialCriteria& c, std::vector<std::string>& warnings);
}
