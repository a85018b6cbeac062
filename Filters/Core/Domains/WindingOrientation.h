// SPDX-License-Identifier: GPL-3.0-or-later
// A triangle soup made ready for the generalized winding number (SurfaceDomain's WindingNumber
// inside test): every connected component turned to face out of the solid, and a soup that
// encloses no volume refused. Kept apart from SurfaceDomain.cxx, the unit that instantiates CGAL.
#pragma once

#include <string>

namespace omesh
{
struct TriangleSurface;
class WindingNumber;

/// Orients every connected component of an oriented soup for the winding number:
/// orient_polygon_soup makes each component consistent but picks its side at random. A closed
/// component is turned to bound a positive volume, then flipped again if it lies inside an odd
/// number of other components (the inner wall of a hollow part bounds a cavity: its triangles face
/// inward). An open one (a patch, a piece of an unwelded soup, down to a lone triangle) bounds no
/// volume to go by: it takes the side most of its area had in the input (`input`, whose triangle i
/// is soup's triangle i), then all open pieces together the side that bounds a positive volume
/// (pieces of one solid stay consistent, a soup given inside out is turned). Nesting is tested for
/// up to 64 components (beyond, all face outward).
void orientComponentsForWinding(TriangleSurface& soup, const TriangleSurface& input);

/// Throws InputError naming `who` when the winding number exceeds 1/2 nowhere near the surface: a
/// lone open patch or a plane encloses nothing (its winding number only approaches 1/2 on the side
/// its triangles face away from). Probes just off both sides of up to 4096 triangles (a thousandth
/// of the triangle's size away, where the triangle itself adds almost 1/2).
void refuseIfNoVolume(const WindingNumber& w, const TriangleSurface& soup, const std::string& who);
}
