// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSingleMaterialDomain
 * @brief Base of the oracle domains that hold one material: surfaces, spheres, implicit shapes.
 *
 * Holds the properties they share (MaterialId, MaterialName, Cut) and writes them into the domain
 * description. Not instantiable.
 *
 * @sa vtkSurfaceDomain vtkSphereDomain vtkImplicitDomain vtkHierarchicalOracle
 */
#ifndef vtkSingleMaterialDomain_h
#define vtkSingleMaterialDomain_h

#include "OracleMeshFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

#include <string>

struct OracleDomainMetadata;

class ORACLEMESHFILTERS_EXPORT vtkSingleMaterialDomain : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkSingleMaterialDomain, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Material id (>= 0) of the points inside the domain. Default 1.
  vtkSetMacro(MaterialId, int);
  vtkGetMacro(MaterialId, int);
  ///@}

  ///@{
  /// Material (and domain) name, shown in reports and messages.
  vtkSetStringMacro(MaterialName);
  vtkGetStringMacro(MaterialName);
  ///@}

  ///@{
  /// When on, the inside is removed from this and every lower-priority domain.
  vtkSetMacro(Cut, bool);
  vtkGetMacro(Cut, bool);
  vtkBooleanMacro(Cut, bool);
  ///@}

  ///@{
  /// Optional mesh criteria for this domain's material(s), as on
  /// vtkFeaturePreservingTetrahedralizer; -1 (the default) = use the tetrahedralizer's; other negative values are refused.
  /// The tetrahedralizer's SetMaterialCriteria overrides these; where two domains give one
  /// material different values, the update of the tetrahedralizer fails naming both (MeshCriteria.h).
  vtkSetMacro(FacetAngle, double);
  vtkGetMacro(FacetAngle, double);
  vtkSetMacro(FacetSize, double);
  vtkGetMacro(FacetSize, double);
  vtkSetMacro(FacetDistance, double);
  vtkGetMacro(FacetDistance, double);
  vtkSetMacro(CellSize, double);
  vtkGetMacro(CellSize, double);
  vtkSetMacro(CellRadiusEdgeRatio, double);
  vtkGetMacro(CellRadiusEdgeRatio, double);
  vtkSetMacro(EdgeSize, double);
  vtkGetMacro(EdgeSize, double);
  ///@}

protected:
  vtkSingleMaterialDomain();
  ~vtkSingleMaterialDomain() override;

  /// How errors name this filter: "vtkSphereDomain 'screw'".
  std::string Describe();
  /// Fills kind, name, material and cut of a domain description.
  void FillMetadata(const char* kind, OracleDomainMetadata& md);

  int MaterialId = 1;
  char* MaterialName = nullptr;
  bool Cut = false;
  double FacetAngle = -1;
  double FacetSize = -1;
  double FacetDistance = -1;
  double CellSize = -1;
  double CellRadiusEdgeRatio = -1;
  double EdgeSize = -1;

private:
  vtkSingleMaterialDomain(const vtkSingleMaterialDomain&) = delete;
  void operator=(const vtkSingleMaterialDomain&) = delete;
};

#endif
