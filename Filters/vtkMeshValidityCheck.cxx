// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkMeshValidityCheck.h"

#include "FieldDataKeys.h"
#include "MeshValidity.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>

#include <algorithm>
#include <utility>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

vtkStandardNewMacro(vtkMeshValidityCheck);

namespace
{
/// The tetrahedra of `grid` (corners of the quadratic ones) as a core mesh; `tetCell` maps each back to its cell id.
omesh::TetMesh toTetMesh(vtkUnstructuredGrid* grid, std::vector<vtkIdType>& tetCell, vtkIdType& others)
{
  omesh::TetMesh mesh;
  const vtkIdType n = grid->GetNumberOfPoints();
  mesh.points.resize(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    grid->GetPoint(i, x);
    mesh.points[static_cast<size_t>(i)] = { x[0], x[1], x[2] };
  }
  vtkDataArray* material = grid->GetCellData()->GetArray(omesh::keys::MATERIAL);
  vtkDataArray* dimension = grid->GetPointData()->GetArray(omesh::keys::DIMENSION);
  if (dimension)
    for (vtkIdType i = 0; i < n; ++i)
      mesh.pointDimension.push_back(static_cast<int>(dimension->GetComponent(i, 0)));
  others = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    // a 10-node tetrahedron is checked on its corners (its straight-sided skeleton)
    if (grid->GetCellType(c) != VTK_TETRA && grid->GetCellType(c) != VTK_QUADRATIC_TETRA)
    {
      ++others;
      continue;
    }
    vtkIdType count;
    const vtkIdType* ids;
    grid->GetCellPoints(c, count, ids);
    mesh.tets.push_back({ static_cast<int>(ids[0]), static_cast<int>(ids[1]), static_cast<int>(ids[2]),
      static_cast<int>(ids[3]) });
    mesh.tetMaterial.push_back(material ? static_cast<int>(material->GetComponent(c, 0)) : 0);
    tetCell.push_back(c);
  }
  return mesh;
}

/// Points that no tetrahedron (linear or 10-node) has among its nodes.
std::size_t UnusedByTetrahedra(vtkUnstructuredGrid* grid, const std::vector<vtkIdType>& tetCell)
{
  std::vector<bool> used(static_cast<size_t>(grid->GetNumberOfPoints()), false);
  for (vtkIdType c : tetCell)
  {
    vtkIdType count;
    const vtkIdType* ids;
    grid->GetCellPoints(c, count, ids);
    for (vtkIdType k = 0; k < count; ++k)
      used[static_cast<size_t>(ids[k])] = true;
  }
  return static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
}
}

void vtkMeshValidityCheck::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DuplicateTolerance: " << this->DuplicateTolerance << "\n";
  os << indent << "MicroTolerance: " << this->MicroTolerance << "\n";
  os << indent << "FlatTolerance: " << this->FlatTolerance << "\n";
  os << indent << "NumberOfDefects: " << this->NumberOfDefects << "\n";
}

int vtkMeshValidityCheck::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  this->NumberOfDefects = 0;
  this->NonTetrahedra = 0;
  if (!input || !output)
  {
    vtkErrorMacro(<< "no input mesh");
    return 0;
  }
  for (const auto& [name, value] : { std::make_pair("DuplicateTolerance", this->DuplicateTolerance),
         std::make_pair("MicroTolerance", this->MicroTolerance), std::make_pair("FlatTolerance", this->FlatTolerance) })
    if (!(value >= 0.0 && value <= 1.0))
    {
      vtkErrorMacro(<< "vtkMeshValidityCheck: " << name << " " << value << " must be between 0 and 1");
      return 0;
    }
  output->ShallowCopy(input);
  std::vector<vtkIdType> tetCell;
  const omesh::TetMesh mesh = toTetMesh(input, tetCell, this->NonTetrahedra);
  if (mesh.tets.empty())
  {
    vtkErrorMacro(<< "the mesh has no tetrahedra (" << input->GetNumberOfCells() << " cells of other types)");
    return 0;
  }
  omesh::ValidityThresholds thresholds;
  thresholds.duplicate = this->DuplicateTolerance;
  thresholds.micro = this->MicroTolerance;
  thresholds.flat = this->FlatTolerance;
  std::vector<unsigned char> flags;
  omesh::MeshValidity v = omesh::checkMeshValidity(mesh, {}, thresholds, &flags);
  // The core sees the corners only; a 10-node tetrahedron's mid-edge nodes are used too.
  v.unusedVertices = UnusedByTetrahedra(input, tetCell);
  this->NumberOfDefects = static_cast<vtkIdType>(v.defects());

  vtkNew<vtkUnsignedCharArray> defects;
  defects->SetName(omesh::keys::DEFECTS);
  defects->SetNumberOfTuples(input->GetNumberOfCells());
  defects->FillValue(0);
  for (size_t t = 0; t < flags.size(); ++t)
    defects->SetValue(tetCell[t], flags[t]);
  output->GetCellData()->AddArray(defects);
  vtkNew<vtkStringArray> names;
  names->SetName(omesh::keys::VALIDITY_NAMES);
  vtkNew<vtkDoubleArray> values;
  values->SetName(omesh::keys::VALIDITY_VALUES);
  for (const auto& [name, value] : v.asStatistics())
  {
    names->InsertNextValue(name);
    values->InsertNextValue(value);
  }
  names->InsertNextValue(omesh::keys::VALIDITY_NON_TETRAHEDRA);
  values->InsertNextValue(static_cast<double>(this->NonTetrahedra));
  output->GetFieldData()->AddArray(names);
  output->GetFieldData()->AddArray(values);
  if (!v.valid())
    vtkWarningMacro(<< "mesh validity: " << v.describe());
  return 1;
}
