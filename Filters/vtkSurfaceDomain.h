// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSurfaceDomain
 * @brief A closed triangle surface as one material of the hierarchical oracle.
 *
 * Input: vtkPolyData of polygons bounding a volume. Polygons, quads and strips are triangulated
 * (vtkTriangleFilter) and points closer than MergeTolerance x the bounding-box diagonal are merged
 * (unwelded corners, as STL and many exporters write them); with InsideTest Automatic, unwelded
 * seams beyond that tolerance are welded too (omesh::weldSeams: border edges that pair up, at most
 * 1/1000 of the diagonal apart). Output: the triangulated, merged surface, with the domain
 * description in its field data (docs/REFERENCE.md, "Domain format"); its sharp edges are what
 * vtkFeatureEdges should be given (the input's unwelded corners have none).
 *
 * InsideTest Automatic (default) meshes what it is given: a closed, manifold surface free of
 * self-intersections is tested by exact ray parity, anything else (holes, borders, non-manifold
 * edges, self-intersections, overlapping shells, unwelded pieces) by the generalized winding number,
 * with a warning in the mesher's input warnings naming what was found. Closed refuses open or
 * non-manifold edges (with the holes' sizes and places) and, unless AllowSelfIntersections, the
 * first intersecting pair of triangles; WindingNumber accepts holes with a warning. Any other data
 * type on the port, an empty surface, NaN, infinite or absurd (beyond 1e15) coordinates, and a
 * surface that encloses no volume (an open patch, a plane) are errors naming the domain.
 *
 * @warning Surfaces with holes, borders or self-intersections are meshed by the winding number
 * under the automatic inside test, with a warning naming what was found: a mesh of such a surface
 * follows the surface where it exists and closes its holes.
 *
 * @sa vtkHierarchicalOracle vtkLabelMapDomain vtkSingleMaterialDomain vtkFeatureEdges
 */
#ifndef vtkSurfaceDomain_h
#define vtkSurfaceDomain_h

#include "OracleMeshFiltersModule.h"

#include "vtkSingleMaterialDomain.h"

#include <string>

class ORACLEMESHFILTERS_EXPORT vtkSurfaceDomain : public vtkSingleMaterialDomain
{
public:
  static vtkSurfaceDomain* New();
  vtkTypeMacro(vtkSurfaceDomain, vtkSingleMaterialDomain);

  ///@{
  /// Points closer than this fraction of the surface's bounding-box diagonal are merged before the
  /// closedness check. Default 1e-6 (single-precision exports round at about 1e-7); 0 merges only
  /// identical points; values outside [0, 1] are an error at the next update.
  vtkSetMacro(MergeTolerance, double);
  vtkGetMacro(MergeTolerance, double);
  ///@}

  ///@{
  /// With InsideTest Closed or WindingNumber: accept a surface that intersects itself (else
  /// refused, naming the first intersecting pair of triangles): the inside test then decides where
  /// the surface overlaps itself (ray parity for Closed, where it overlaps an even number of times
  /// it is outside; the winding number counts such places inside). Automatic accepts it anyway.
  vtkSetMacro(AllowSelfIntersections, bool);
  vtkGetMacro(AllowSelfIntersections, bool);
  vtkBooleanMacro(AllowSelfIntersections, bool);
  ///@}

  enum InsideTests
  {
    CLOSED = 0,         ///< the surface must be closed; ray parity
    WINDING_NUMBER = 1, ///< generalized winding number > 1/2: holes and borders are closed smoothly
    AUTOMATIC = 2       ///< CLOSED where the surface has no defect, else WINDING_NUMBER with a warning
  };
  ///@{
  /// How inside is decided: Automatic (default, see the class comment), Closed (every edge must be
  /// shared by two triangles) or WindingNumber (fTetWild's generalized winding number; surfaces
  /// with holes are accepted with a warning naming the holes). Other values are an error at the
  /// next update.
  vtkSetMacro(InsideTest, int);
  vtkGetMacro(InsideTest, int);
  void SetInsideTestToClosed() { this->SetInsideTest(CLOSED); }
  void SetInsideTestToWindingNumber() { this->SetInsideTest(WINDING_NUMBER); }
  void SetInsideTestToAutomatic() { this->SetInsideTest(AUTOMATIC); }
  ///@}

protected:
  vtkSurfaceDomain();
  ~vtkSurfaceDomain() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MergeTolerance = 1e-6;
  bool AllowSelfIntersections = false;
  int InsideTest = AUTOMATIC;

private:
  vtkSurfaceDomain(const vtkSurfaceDomain&) = delete;
  void operator=(const vtkSurfaceDomain&) = delete;
};

#endif
