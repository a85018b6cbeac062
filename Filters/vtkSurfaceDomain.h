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
 * surface, NaN, infinite or absurd (beyond 1e15) coordinates, and open or non-manifold edges are
 * rejected with an error that names the domain and the offending points or edges.
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

protected:
  vtkSurfaceDomain();
  ~vtkSurfaceDomain() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MergeTolerance = 1e-9;

private:
  vtkSurfaceDomain(const vtkSurfaceDomain&) = delete;
  void operator=(const vtkSurfaceDomain&) = delete;
};

#endif
