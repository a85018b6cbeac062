// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSphereDomain
 * @brief An exact sphere (ball) as one material of the hierarchical oracle (a source).
 *
 * The oracle uses the exact ball |p - Center| <= Radius; the output polydata is a tessellation for
 * display only (Resolution), carrying the domain description in its field data.
 *
 * @sa vtkImplicitDomain vtkSingleMaterialDomain vtkHierarchicalOracle vtkSphereSource
 */
#ifndef vtkSphereDomain_h
#define vtkSphereDomain_h

#include "OracleMeshFiltersModule.h"

#include "vtkSingleMaterialDomain.h"

class ORACLEMESHFILTERS_EXPORT vtkSphereDomain : public vtkSingleMaterialDomain
{
public:
  static vtkSphereDomain* New();
  vtkTypeMacro(vtkSphereDomain, vtkSingleMaterialDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Centre of the ball. Default (0, 0, 0).
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  ///@}

  ///@{
  /// Radius (> 0). Default 1.
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /// Tessellation resolution of the displayed sphere (theta and phi). Default 32.
  vtkSetClampMacro(Resolution, int, 4, 1024);
  vtkGetMacro(Resolution, int);
  ///@}

protected:
  vtkSphereDomain();
  ~vtkSphereDomain() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double Radius = 1.0;
  int Resolution = 32;

private:
  vtkSphereDomain(const vtkSphereDomain&) = delete;
  void operator=(const vtkSphereDomain&) = delete;
};

#endif
