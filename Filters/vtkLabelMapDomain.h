// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkLabelMapDomain
 * @brief A label map (segmented image) as materials of the hierarchical oracle.
 *
 * Input: vtkImageData with an integer label array, point or cell data, chosen with
 * SetInputArrayToProcess(0, 0, 0, association, name). Unnamed (the default), the label array is
 * picked: the one integer point array (of several, the active point scalars; else an error naming
 * them), else the point scalars, else the one integer cell array or the cell scalars. Every label other than BackgroundLabel is a material whose id is the label.
 * With point data each point is the centre of its voxel (as in ITK and CGAL's Image_3); with cell
 * data each cell is a voxel. The image's direction matrix is honoured.
 * Output: the same image with the domain description in its field data.
 *
 * @warning With Smooth interpolation the filters that build the oracle from this domain (the
 * tetrahedralizer, the sampler, the feature lines) first smooth the labels' interfaces: on a large
 * image that takes seconds, with their progress and abort.
 *
 * @sa vtkHierarchicalOracle vtkSurfaceDomain vtkImageData
 */
#ifndef vtkLabelMapDomain_h
#define vtkLabelMapDomain_h

#include "OracleMeshFiltersModule.h"

#include <vtkImageAlgorithm.h>

#include <map>
#include <string>

class ORACLEMESHFILTERS_EXPORT vtkLabelMapDomain : public vtkImageAlgorithm
{
public:
  static vtkLabelMapDomain* New();
  vtkTypeMacro(vtkLabelMapDomain, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The label that is not a material. Default 0.
  vtkSetMacro(BackgroundLabel, int);
  vtkGetMacro(BackgroundLabel, int);
  ///@}

  enum InterpolationModes
  {
    NEAREST = 0,   ///< each voxel owns its box: material boundaries are voxel staircases
    TRILINEAR = 1, ///< the label with the largest trilinear indicator (as CGAL's image domains)
    SMOOTH = 2     ///< trilinear with voxel weights fitted to smooth boundaries below the voxel size
  };
  ///@{
  /// How labels are read between voxel centres. Default SMOOTH: interfaces below the voxel size
  /// (TRILINEAR follows the voxels more closely; NEAREST's staircases force flat tetrahedra on
  /// the interfaces).
  vtkSetMacro(Interpolation, int); // another value: an error at the next update
  vtkGetMacro(Interpolation, int);
  void SetInterpolationToNearest() { this->SetInterpolation(NEAREST); }
  void SetInterpolationToTrilinear() { this->SetInterpolation(TRILINEAR); }
  void SetInterpolationToSmooth() { this->SetInterpolation(SMOOTH); }
  ///@}

  ///@{
  /// When on, every labelled voxel is removed from this and lower-priority domains. Default off.
  vtkSetMacro(Cut, bool);
  vtkGetMacro(Cut, bool);
  vtkBooleanMacro(Cut, bool);
  ///@}

  ///@{
  /// Domain name shown in reports. Default "LabelMap".
  vtkSetStringMacro(DomainName);
  vtkGetStringMacro(DomainName);
  ///@}

  ///@{
  /// Optional material names per label ("cortical bone" for label 1...).
  void SetLabelName(int label, const char* name);
  const char* GetLabelName(int label);
  void ClearLabelNames();
  ///@}

  ///@{
  /// Optional mesh criteria for every label of this map, as on
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
  vtkLabelMapDomain();
  ~vtkLabelMapDomain() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int BackgroundLabel = 0;
  int Interpolation = SMOOTH;
  double FacetAngle = -1;
  double FacetSize = -1;
  double FacetDistance = -1;
  double CellSize = -1;
  double CellRadiusEdgeRatio = -1;
  double EdgeSize = -1;
  bool Cut = false;
  char* DomainName = nullptr;
  std::map<int, std::string> LabelNames;

private:
  vtkLabelMapDomain(const vtkLabelMapDomain&) = delete;
  void operator=(const vtkLabelMapDomain&) = delete;
};

#endif
