// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "TetMesh.h"

#include <vector>

namespace omesh
{
/// Reorders the tetrahedra of `mesh` (with their materials) by their smallest point id, a stable
/// counting sort: where the points come in space order (the mesher numbers them along a Hilbert
/// curve), so do the tetrahedra, and every pass over the mesh after it reads points nearly in
/// order. Needs valid point ids; call it before anything indexes the tetrahedra (segments located,
/// defects, separating faces). With `renumber`, the corners are ids into it (corner v is point
/// (*renumber)[v]) and come out renumbered.
void orderTetsByPoints(TetMesh& mesh, const std::vector<int>* renumber = nullptr);
}
