// SPDX-License-Identifier: GPL-3.0-or-later
// The measures used everywhere (docs/DESIGN.md, "Invariants and measures"), defined once.
#pragma once

#include "FeatureSegments.h"
#include "TetMesh.h"

#include <map>

namespace omesh
{
/// Smallest of the six dihedral angles of tetrahedron abcd, in degrees (0 for a flat one).
double minDihedralAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Cosine of the smallest dihedral angle of abcd (1 for a flat one): minDihedralAngle is its acos
/// in degrees, so the smallest angle of many tetrahedra needs one acos, of the largest cosine.
double largestDihedralCosine(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Largest of the six dihedral angles of tetrahedron abcd, in degrees (180 for a flat one): near
/// 180 degrees spoils gradients and stresses as much as small angles spoil the conditioning.
double maxDihedralAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Smallest and largest dihedral angle of abcd in degrees, from one set of face normals (the same
/// values as minDihedralAngle and maxDihedralAngle); false for a tetrahedron with a degenerate face.
bool dihedralAngleRange(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& smallest, double& largest);

/// Whether every dihedral angle of abcd is certainly at least the angle whose cosine is
/// `cosBound`, i.e. minDihedralAngle(a, b, c, d) is at least that angle in degrees: the same face
/// normals, compared squared against the bound with a margin (1e-9 in the cosine) far beyond the
/// rounding of minDihedralAngle's square roots, divisions and acos, which this skips. False when
/// it cannot tell (near the bound, a flat face, cosBound <= 0): then ask minDihedralAngle.
bool dihedralAnglesCertainlyAtLeast(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double cosBound);

/// Shape measures of one tetrahedron as finite-element preprocessors report them (the Python
/// report's shape.py computes the same from the corners alone): 1 for the regular tetrahedron but
/// for the angles (70.53 degrees) and radiusEdge (0.61); a flat one gets 0 (180 for maxDihedral).
struct TetShape
{
  double minDihedral = 0.0, maxDihedral = 180.0; ///< degrees: minDihedralAngle, maxDihedralAngle
  double radiusRatio = 0.0; ///< 3 x inradius / circumradius (Gmsh's gamma)
  double meanRatio = 0.0;   ///< 12 (3 |V|)^(2/3) / sum of the squared edge lengths
  double edgeRatio = 0.0;   ///< shortest / longest edge
  double radiusEdge = 0.0;  ///< radiusEdgeRatio
  double volume = 0.0;      ///< |signedVolume|
  double longestEdge = 0.0;
};

/// Every TetShape measure of abcd from one set of face normals and edge lengths (minDihedral,
/// maxDihedral and radiusEdge equal minDihedralAngle, maxDihedralAngle and radiusEdgeRatio to the
/// bit).
TetShape tetShape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
/// The same with the volume known (|signedVolume| of these corners in any order).
TetShape tetShape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double volume);
/// The same with the edge lengths known too (edgeLengths of these corners in any order: the same
/// six values, as norms of differences are the same either way round).
TetShape tetShape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double volume, const double lengths[6]);

/// The six edge lengths of abcd: ab, ac, ad, bc, bd, cd (edge e and edge 5 - e are opposite).
void edgeLengths(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double l[6]);

/// Circumradius divided by the shortest edge (sqrt(6)/4 = 0.61 for the regular tetrahedron;
/// infinite for a flat one).
double radiusEdgeRatio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Circumcentre of tetrahedron abcd (NaN coordinates for a flat one).
Vec3 circumcenter(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Signed volume of abcd (positive when d is on the side of abc its normal (b-a)x(c-a) points to).
double signedVolume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Smallest of the four heights of abcd (3 |volume| / largest face area; 0 for a flat one): how
/// far the tetrahedron reaches from its largest face.
double smallestAltitude(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Volume of the tetrahedra of each material.
std::map<int, double> materialVolumes(const TetMesh& mesh);

/// The input segments cut at the mesh vertices lying on them (within `tolerance` x segment length),
/// each piece flagged present when its ends are joined by a tetrahedron edge, or when a tetrahedron
/// edge runs straight through the input points of degree 2 between it and the next vertices
/// (within `tolerance` x the edge's length: the chords between CGAL's protecting balls).
std::vector<TetMesh::Segment> locateFeatureSegments(
  const TetMesh& mesh, const FeatureSegments& features, double tolerance = 1e-6);

/// Fraction of the total length of the input segments that `pieces` (from locateFeatureSegments)
/// cover with present pieces.
double featureCoverage(const std::vector<TetMesh::Segment>& pieces, const FeatureSegments& features);
}
