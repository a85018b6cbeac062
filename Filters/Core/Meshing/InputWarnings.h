// SPDX-License-Identifier: GPL-3.0-or-later
// Warnings about the inputs as a whole, before and after meshing: slips that would otherwise mesh
// silently (a hidden domain, inputs in other units or frames, a material that vanished) and what
// the surfaces' inside tests repaired.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;
struct TetMesh;

/// Warnings for the domains no point of which reaches the mesh: every point sampled inside the
/// domain's bounds (20 x 20 x 20) that the domain contains belongs to a higher-priority domain.
std::vector<std::string> hiddenDomainWarnings(const HierarchicalOracle& oracle);

/// Warnings for inputs that look placed in different frames or units: two bounded material
/// domains whose bounding boxes differ in size by kScaleWarningRatio or more (metres and
/// millimetres), or a group of inputs whose boxes overlap none of the others' in
/// kOverlapWarningShare of the smaller box or more (apart, or barely overlapping: a surface in
/// another frame than the label map). Boxes that share a face or an edge overlap across it (parts
/// meeting on purpose), and a group may hang together through a third input (two implant parts
/// in a bone).
std::vector<std::string> inputPlacementWarnings(const HierarchicalOracle& oracle);
constexpr double kScaleWarningRatio = 100.0;
constexpr double kOverlapWarningShare = 0.05;

/// Warnings for the materials of `oracle` (the labels of a label map) that have no tetrahedron in
/// the mesh although their input is not empty: `tetsPerMaterial` counts the mesh's tetrahedra.
std::vector<std::string> vanishedMaterialWarnings(
  const HierarchicalOracle& oracle, const std::map<int, std::size_t>& tetsPerMaterial);

/// The surface domains' own warnings (what their inside test repaired: holes, non-manifold
/// edges, intersecting triangles), each of a winding-number surface followed, given the mesh, by
/// how far its material's boundary and the input surface lie apart (SurfaceDeviation).
std::vector<std::string> surfaceWarnings(const HierarchicalOracle& oracle, const TetMesh* mesh = nullptr);

/// The domains' own warnings (surfaceWarnings without a mesh), then hiddenDomainWarnings.
std::vector<std::string> domainWarnings(const HierarchicalOracle& oracle);
}
