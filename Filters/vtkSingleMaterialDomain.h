// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkSingleMaterialDomain
 * @brief Base of the oracle domains that hold one material: surfaces, spheres, implicit shapes.
 *
 * Holds the properties they share (MaterialId, MaterialName, Cut) and writes them into the domain
 * description. Not instantiable.
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

private:
  vtkSingleMaterialDomain(const vtkSingleMaterialDomain&) = delete;
  void operator=(const vtkSingleMaterialDomain&) = delete;
};

#endif
