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

#include <vtkPolyDataAlgorithm.h>

#include <string>

class ORACLEMESHFILTERS_EXPORT vtkSurfaceDomain : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceDomain* New();
  vtkTypeMacro(vtkSurfaceDomain, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Material id (>= 0) of the points inside the surface. Default 1.
  vtkSetMacro(MaterialId, int);
  vtkGetMacro(MaterialId, int);
  ///@}

  ///@{
  /// Material (and domain) name shown in reports. Default "Surface".
  vtkSetStringMacro(MaterialName);
  vtkGetStringMacro(MaterialName);
  ///@}

  ///@{
  /// When on, the inside is removed from this and every lower-priority domain. Default off.
  vtkSetMacro(Cut, bool);
  vtkGetMacro(Cut, bool);
  vtkBooleanMacro(Cut, bool);
  ///@}

protected:
  vtkSurfaceDomain();
  ~vtkSurfaceDomain() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int MaterialId = 1;
  char* MaterialName = nullptr;
  bool Cut = false;

private:
  vtkSurfaceDomain(const vtkSurfaceDomain&) = delete;
  void operator=(const vtkSurfaceDomain&) = delete;
};

#endif
