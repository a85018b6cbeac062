// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkMeshValidityCheck
 * @brief What a finite-element code would reject in a tetrahedral mesh, on any vtkUnstructuredGrid.
 *
 * The same check the tetrahedralizer runs on every mesh it makes (core: omesh::checkMeshValidity),
 * on demand: duplicate vertices (closer than DuplicateTolerance x L), micro tetrahedra (longest
 * edge below MicroTolerance x L; L is the median edge, or the edge of a regular tetrahedron of
 * the mesh's mean volume where that is longer), flat tetrahedra (|volume| below
 * FlatTolerance x longest edge cubed), inverted tetrahedra (negative VTK orientation), faces shared
 * by more than two tetrahedra, cells with repeated or bad point ids. Quadratic tetrahedra are checked
 * on their corners (the curved shape is the tetrahedralizer's Jacobian check). Cells other than tetrahedra
 * are counted (NonTetrahedra) but not checked.
 *
 * Output: the input with the cell array "Defects" (bits: 1 duplicate vertex, 2 micro, 4 flat,
 * 8 inverted, 16 non-manifold face, 32 bad ids, 64 material mismatch) and field data
 * "ValidityNames" / "ValidityValues" (the counts, "validity.defects" their sum). A mesh with defects
 * also gives a warning naming them. GetNumberOfDefects() after an update.
 *
 * @sa vtkFeaturePreservingTetrahedralizer vtkMeshQuality vtkCellValidator
 */
#ifndef vtkMeshValidityCheck_h
#define vtkMeshValidityCheck_h

#include "OracleMeshFiltersModule.h"

#include <vtkUnstructuredGridAlgorithm.h>

class ORACLEMESHFILTERS_EXPORT vtkMeshValidityCheck : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkMeshValidityCheck* New();
  vtkTypeMacro(vtkMeshValidityCheck, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Thresholds relative to L (duplicates, micro) and the longest edge (flat) (defaults 1e-9, 1e-4, 1e-8); each in [0, 1],
  /// else the next update fails with an error naming it.
  vtkSetMacro(DuplicateTolerance, double);
  vtkGetMacro(DuplicateTolerance, double);
  vtkSetMacro(MicroTolerance, double);
  vtkGetMacro(MicroTolerance, double);
  vtkSetMacro(FlatTolerance, double);
  vtkGetMacro(FlatTolerance, double);
  ///@}

  /// Sum of the defect counts of the last update.
  vtkGetMacro(NumberOfDefects, vtkIdType);
  /// Cells that are not tetrahedra in the last input (not checked).
  vtkGetMacro(NonTetrahedra, vtkIdType);

protected:
  vtkMeshValidityCheck() = default;
  ~vtkMeshValidityCheck() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double DuplicateTolerance = 1e-9;
  double MicroTolerance = 1e-4;
  double FlatTolerance = 1e-8;
  vtkIdType NumberOfDefects = 0;
  vtkIdType NonTetrahedra = 0;

private:
  vtkMeshValidityCheck(const vtkMeshValidityCheck&) = delete;
  void operator=(const vtkMeshValidityCheck&) = delete;
};

#endif
