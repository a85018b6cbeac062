// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshCriteria.h"

#include "InputError.h"

#include <cmath>
#include <sstream>

namespace omesh
{
const std::array<const char*, MeshCriteria::kCount>& MeshCriteria::propertyNames()
{
  static const std::array<const char*, kCount> names = { "FacetAngle", "FacetSize", "FacetDistance", "CellSize",
    "CellRadiusEdgeRatio", "EdgeSize" };
  return names;
}

const std::array<const char*, MeshCriteria::kCount>& MeshCriteria::sceneKeys()
{
  static const std::array<const char*, kCount> keys = { "facet_angle", "facet_size", "facet_distance", "cell_size",
    "cell_radius_edge_ratio", "edge_size" };
  return keys;
}

MeshCriteria MeshCriteria::defaults()
{
  return { 25.0, 0.0, 0.0, 0.0, 3.0, 0.0 };
}

std::optional<double>& MeshCriteria::operator[](int k)
{
  std::optional<double>* fields[kCount] = { &facetAngle, &facetSize, &facetDistance, &cellSize, &cellRadiusEdgeRatio,
    &edgeSize };
  return *fields[k];
}

const std::optional<double>& MeshCriteria::operator[](int k) const
{
  return const_cast<MeshCriteria&>(*this)[k];
}

MeshCriteria MeshCriteria::over(const MeshCriteria& base) const
{
  MeshCriteria out = *this;
  for (int k = 0; k < kCount; ++k)
    if (!out[k])
      out[k] = base[k];
  return out;
}

MeshCriteria::Values MeshCriteria::values() const
{
  const MeshCriteria c = over(defaults());
  return { *c.facetAngle, *c.facetSize, *c.facetDistance, *c.cellSize, *c.cellRadiusEdgeRatio, *c.edgeSize };
}

MeshCriteria MeshCriteria::fromVtk(const std::array<double, kCount>& v)
{
  MeshCriteria c;
  for (int k = 0; k < kCount; ++k)
    if (v[k] != kUnset)
      c[k] = v[k];
  return c;
}

void MeshCriteria::check(const std::string& who) const
{
  for (int k = 0; k < kCount; ++k)
    if (const std::optional<double>& v = (*this)[k]; v && (!std::isfinite(*v) || *v < 0))
    {
      std::ostringstream o;
      o << who << ": " << propertyNames()[k] << " (" << sceneKeys()[k] << ") is " << *v
        << (std::isfinite(*v) ? ": it cannot be negative" : "")
        << " (0 means no bound; -1 or leaving it out means not set: the less specific level's value counts)";
      throw InputError(o.str());
    }
}

double MaterialCriteria::finestFacetDistance() const
{
  double finest = globalValues().facetDistance;
  for (const auto& entry : perMaterial)
    if (const double d = of(entry.first).facetDistance; d > 0 && (finest <= 0 || d < finest))
      finest = d;
  return finest > 0 ? finest : 0.0;
}

MeshCriteria::Values MaterialCriteria::of(int material) const
{
  auto it = perMaterial.find(material);
  return it == perMaterial.end() ? global.values() : it->second.over(global).values();
}

MaterialCriteria::Resolved::Resolved(const MaterialCriteria& c)
  : global_(c.global.values())
{
  for (const auto& entry : c.perMaterial)
    perMaterial_.emplace(entry.first, c.of(entry.first));
}

void CriteriaLevel::add(int material, const MeshCriteria& c, const std::string& source)
{
  MeshCriteria& mine = criteria_[material];
  for (int k = 0; k < MeshCriteria::kCount; ++k)
  {
    if (!c[k])
      continue;
    const auto key = std::make_pair(material, k);
    if (mine[k] && *mine[k] != *c[k])
    {
      std::ostringstream o;
      o << "criteria: material " << material << " gets " << MeshCriteria::propertyNames()[k] << " "
        << *mine[k] << " from " << sources_[key] << " and " << *c[k] << " from " << source
        << " (give it once; a per-material value overrides the domains')";
      throw InputError(o.str());
    }
    if (!mine[k])
    {
      mine[k] = c[k];
      sources_[key] = source;
    }
  }
}

MaterialCriteria mergeCriteria(const MeshCriteria& global, const std::vector<const CriteriaLevel*>& levels)
{
  MaterialCriteria out;
  out.global = global.over(MeshCriteria::defaults());
  for (const CriteriaLevel* level : levels) // least specific first: later levels win
    for (const auto& [m, c] : level->criteria())
    {
      auto it = out.perMaterial.find(m);
      out.perMaterial[m] = it == out.perMaterial.end() ? c : c.over(it->second);
    }
  return out;
}

void checkCriteria(const MaterialCriteria& c, std::vector<std::string>& warnings)
{
  c.global.check("global criteria");
  for (const auto& [material, m] : c.perMaterial)
    m.check("criteria of material " + std::to_string(material));
  // A material's termination warnings only where its value is its own (not the global one again).
  const MeshCriteria::Values g = c.globalValues();
  auto check = [&](const MeshCriteria::Values& m, const std::string& who, const MeshCriteria::Values* global) {
    if (m.facetAngle > 30.0 && !(global && global->facetAngle == m.facetAngle))
      warnings.push_back(who + ": FacetAngle " + std::to_string(m.facetAngle) +
        " > 30 degrees: refinement is not guaranteed to terminate");
    if (m.cellRadiusEdgeRatio > 0 && m.cellRadiusEdgeRatio < 2.0 &&
      !(global && global->cellRadiusEdgeRatio == m.cellRadiusEdgeRatio))
      warnings.push_back(who + ": CellRadiusEdgeRatio " + std::to_string(m.cellRadiusEdgeRatio) +
        " < 2: termination is not guaranteed (the run stops at MaximumNumberOfVertices)");
  };
  check(g, "global criteria", nullptr);
  for (const auto& [material, m] : c.perMaterial)
    check(c.of(material), "criteria of material " + std::to_string(material), &g);
  if (g.cellSize <= 0 && g.facetSize <= 0 && g.facetDistance <= 0)
  {
    bool sized = !c.perMaterial.empty();
    for (const auto& [material, m] : c.perMaterial)
      sized = sized && (c.of(material).cellSize > 0 || c.of(material).facetSize > 0);
    if (!sized)
      warnings.push_back("no size bound (CellSize, FacetSize, FacetDistance): the mesh follows only the shape criteria");
  }
}
}
