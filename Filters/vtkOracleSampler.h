// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkOracleSampler
 * @brief Samples the hierarchical oracle on a grid: how a user sees the combined domain.
 *
 * Input: the output of vtkHierarchicalOracle (or a single domain). Output: vtkImageData with the
 * point array "Material" (int): the oracle's material at each grid point, -1 outside. Field data
 * "MaterialVolume" estimates each material's volume (sample count x sample spacing volume; each
 * sample stands for the cell of one spacing around it, so a material touching the sampled box's
 * faces is overcounted by up to d/(d-1) per axis) with "MaterialIds" alongside.
 *
 * @sa vtkHierarchicalOracle vtkSampleFunction
 */
#ifndef vtkOracleSampler_h
#define vtkOracleSampler_h

#include "OracleMeshFiltersModule.h"

#include <vtkImageAlgorithm.h>

class ORACLEMESHFILTERS_EXPORT vtkOracleSampler : public vtkImageAlgorithm
{
public:
  static vtkOracleSampler* New();
  vtkTypeMacro(vtkOracleSampler, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Grid points per axis. Default 64 x 64 x 64.
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

  ///@{
  /// Sampled region (xmin, xmax, ymin, ymax, zmin, zmax). Default (0, -1, 0, -1, 0, -1): the oracle's
  /// bounding box, i.e. the union of its non-cut domains; any other min > max is refused.
  vtkSetVector6Macro(Bounds, double);
  vtkGetVector6Macro(Bounds, double);
  ///@}

protected:
  vtkOracleSampler();
  ~vtkOracleSampler() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Dimensions[3] = { 64, 64, 64 };
  double Bounds[6] = { 0, -1, 0, -1, 0, -1 };

private:
  vtkOracleSampler(const vtkOracleSampler&) = delete;
  void operator=(const vtkOracleSampler&) = delete;
};

#endif
