// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSphereDomain
 * @brief An exact sphere (ball) as one material of the hierarchical oracle (a source).
 *
 * The oracle uses the exact ball |p - Center| <= Radius; the output polydata is a tessellation for
 * display only (Resolution), carrying the domain description in its field data.
 */
#ifndef vtkSphereDomain_h
#define vtkSphereDomain_h

#include "OracleMeshFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

class ORACLEMESHFILTERS_EXPORT vtkSphereDomain : public vtkPolyDataAlgorithm
{
public:
  static vtkSphereDomain* New();
  vtkTypeMacro(vtkSphereDomain, vtkPolyDataAlgorithm);
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
  /// Material id (>= 0). Default 1.
  vtkSetMacro(MaterialId, int);
  vtkGetMacro(MaterialId, int);
  ///@}

  ///@{
  /// Material (and domain) name. Default "Sphere".
  vtkSetStringMacro(MaterialName);
  vtkGetStringMacro(MaterialName);
  ///@}

  ///@{
  /// When on, the ball is removed from this and every lower-priority domain. Default off.
  vtkSetMacro(Cut, bool);
  vtkGetMacro(Cut, bool);
  vtkBooleanMacro(Cut, bool);
  ///@}

  ///@{
  /// Tessellation resolution of the displayed sphere (theta and phi). Default 32.
  vtkSetClampMacro(Resolution, int, 4, 1024);
  vtkGetMacro(Resolution, int);
  ///@}

protected:
  vtkSphereDomain();
  ~vtkSphereDomain() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Center[3] = { 0.0, 0.0, 0.0 };
  double Radius = 1.0;
  int MaterialId = 1;
  char* MaterialName = nullptr;
  bool Cut = false;
  int Resolution = 32;

private:
  vtkSphereDomain(const vtkSphereDomain&) = delete;
  void operator=(const vtkSphereDomain&) = delete;
};

#endif
