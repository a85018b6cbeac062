// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkHierarchicalOracle
 * @brief Orders oracle domains by priority: the first connected domain has the highest priority.
 *
 * One repeatable input: the outputs of vtkSurfaceDomain, vtkLabelMapDomain, vtkSphereDomain and
 * vtkImplicitDomain. A point belongs to the material of the first domain that contains it; a cut
 * domain that contains it makes it outside (paper section 3.1). The output is a
 * vtkMultiBlockDataSet with one block per domain in priority order (each block the domain's dataset
 * with its description in field data; block names are the domain names), from which downstream
 * filters rebuild the oracle exactly. This filter does no geometry work; it checks that every
 * input is a domain of a fitting data type.
 *
 * @warning The order of the inputs is the priority: reconnecting them reorders the materials'
 * precedence.
 *
 * @sa vtkSurfaceDomain vtkLabelMapDomain vtkSphereDomain vtkImplicitDomain
 * vtkFeaturePreservingTetrahedralizer vtkOracleSampler
 */
#ifndef vtkHierarchicalOracle_h
#define vtkHierarchicalOracle_h

#include "OracleMeshFiltersModule.h"

#include <vtkMultiBlockDataSetAlgorithm.h>

class ORACLEMESHFILTERS_EXPORT vtkHierarchicalOracle : public vtkMultiBlockDataSetAlgorithm
{
public:
  static vtkHierarchicalOracle* New();
  vtkTypeMacro(vtkHierarchicalOracle, vtkMultiBlockDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkHierarchicalOracle();
  ~vtkHierarchicalOracle() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkHierarchicalOracle(const vtkHierarchicalOracle&) = delete;
  void operator=(const vtkHierarchicalOracle&) = delete;
};

#endif
