// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSurfaceDomain
 * @brief A closed triangle surface as one material of the hierarchical oracle.
 *
 * Input: vtkPolyData of polygons bounding a volume. Polygons, quads and strips are triangulated
 * (vtkTriangleFilter) and points closer than MergeTolerance x the bounding-box diagonal are merged
 * (unwelded corners, as STL and many exporters write them) before the check that every edge is
 * shared by exactly two triangles. Output: the triangulated, merged surface, with the domain
 * description in its field data (README, "Domain format"). Any other data type on the port, an empty
 * surface, NaN, infinite or absurd (beyond 1e15) coordinates, open or non-manifold edges (with the
 * holes' sizes and places) and self-intersections (with the first intersecting pair of triangles)
 * are rejected with an error that names the domain and the offending points, edges or triangles.
 * InsideTest WindingNumber accepts surfaces with holes and borders (a warning lists the holes);
 * AllowSelfIntersections accepts surfaces that cross themselves.
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
  /// closedness check. Default 1e-9; 0 merges only identical points; values outside [0, 1] are an
  /// error at the next update.
  vtkSetMacro(MergeTolerance, double);
  vtkGetMacro(MergeTolerance, double);
  ///@}

  ///@{
  /// Accept a surface that intersects itself (refused by default, naming the first intersecting
  /// pair of triangles): the inside test then decides where the surface overlaps itself (ray
  /// parity for Closed, where it overlaps an even number of times it is outside; the winding number
  /// counts such places inside).
  vtkSetMacro(AllowSelfIntersections, bool);
  vtkGetMacro(AllowSelfIntersections, bool);
  vtkBooleanMacro(AllowSelfIntersections, bool);
  ///@}

  enum InsideTests
  {
    CLOSED = 0,        ///< the surface must be closed; ray parity
    WINDING_NUMBER = 1 ///< generalized winding number > 1/2: holes and borders are closed smoothly
  };
  ///@{
  /// How inside is decided: Closed (default: every edge must be shared by two triangles) or
  /// WindingNumber (fTetWild's generalized winding number; surfaces with holes are accepted with a
  /// warning naming the holes). Other values are an error at the next update.
  vtkSetMacro(InsideTest, int);
  vtkGetMacro(InsideTest, int);
  void SetInsideTestToClosed() { this->SetInsideTest(CLOSED); }
  void SetInsideTestToWindingNumber() { this->SetInsideTest(WINDING_NUMBER); }
  ///@}

protected:
  vtkSurfaceDomain();
  ~vtkSurfaceDomain() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MergeTolerance = 1e-9;
  bool AllowSelfIntersections = false;
  int InsideTest = CLOSED;

private:
  vtkSurfaceDomain(const vtkSurfaceDomain&) = delete;
  void operator=(const vtkSurfaceDomain&) = delete;
};

#endif
