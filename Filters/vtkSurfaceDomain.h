// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSurfaceDomain
 * @brief A closed triangle surface as one material of the hierarchical oracle.
 *
 * Input: vtkPolyData of triangles bounding a volume (every edge shared by exactly two triangles).
 * Output: the same surface, with the domain description in its field data (README, "Domain
 * format"). A surface that is empty, has non-triangle polygons or strips, NaN coordinates, or open or
 * non-manifold edges is rejected with an error that names the offending edges.
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

protected:
  vtkSurfaceDomain();
  ~vtkSurfaceDomain() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkSurfaceDomain(const vtkSurfaceDomain&) = delete;
  void operator=(const vtkSurfaceDomain&) = delete;
};

#endif
