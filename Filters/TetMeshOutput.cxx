// SPDX-License-Identifier: GPL-3.0-or-later
#include "TetMeshOutput.h"

#include "FieldDataKeys.h"
#include "MeshQuality.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>

namespace
{
vtkSmartPointer<vtkPoints> toPoints(const std::vector<omesh::Vec3>& pts)
{
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), pts[i].x, pts[i].y, pts[i].z);
  return points;
}
}

void TetMeshOutput::FillGrid(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh,
  const omesh::QuadraticTetMesh* quadratic, const std::vector<std::string>& inputWarnings)
{
  grid->SetPoints(toPoints(quadratic ? quadratic->points : mesh.points));
  AddTetrahedra(grid, mesh, quadratic);
  vtkNew<vtkIntArray> dimension;
  dimension->SetName(omesh::keys::DIMENSION);
  for (int d : quadratic ? quadratic->pointDimension : mesh.pointDimension)
    dimension->InsertNextValue(d);
  grid->GetPointData()->AddArray(dimension);
  AddStatistics(grid->GetFieldData(), mesh.statistics);
  AddStrings(grid->GetFieldData(), omesh::keys::WARNINGS, mesh.warnings);
  // The inputs' warnings again (frames, units, materials or labels that vanished): the ones the
  // command line's --strict turns into a failure.
  AddStrings(grid->GetFieldData(), omesh::keys::INPUT_WARNINGS, inputWarnings);
}

void TetMeshOutput::AddTetrahedra(
  vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh, const omesh::QuadraticTetMesh* quadratic)
{
  const vtkIdType nodes = quadratic ? 10 : 4;
  vtkNew<vtkCellArray> tets;
  tets->AllocateExact(static_cast<vtkIdType>(mesh.tets.size()), nodes * static_cast<vtkIdType>(mesh.tets.size()));
  vtkNew<vtkIntArray> material;
  material->SetName(omesh::keys::MATERIAL);
  vtkNew<vtkDoubleArray> dihedral;
  dihedral->SetName(omesh::keys::MIN_DIHEDRAL_ANGLE);
  vtkNew<vtkDoubleArray> largest;
  largest->SetName(omesh::keys::MAX_DIHEDRAL_ANGLE);
  vtkNew<vtkDoubleArray> ratio;
  ratio->SetName(omesh::keys::RADIUS_EDGE_RATIO);
  const auto& P = mesh.points;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
  {
    auto k = mesh.tets[t];
    if (omesh::signedVolume(P[k[0]], P[k[1]], P[k[2]], P[k[3]]) < 0)
      std::swap(k[0], k[1]);
    vtkIdType ids[10] = { k[0], k[1], k[2], k[3] };
    if (quadratic)
      std::copy(quadratic->tets[t].begin(), quadratic->tets[t].end(), ids);
    tets->InsertNextCell(nodes, ids);
    material->InsertNextValue(mesh.tetMaterial[t]);
    dihedral->InsertNextValue(omesh::minDihedralAngle(P[k[0]], P[k[1]], P[k[2]], P[k[3]]));
    largest->InsertNextValue(omesh::maxDihedralAngle(P[k[0]], P[k[1]], P[k[2]], P[k[3]]));
    ratio->InsertNextValue(omesh::radiusEdgeRatio(P[k[0]], P[k[1]], P[k[2]], P[k[3]]));
  }
  grid->SetCells(quadratic ? VTK_QUADRATIC_TETRA : VTK_TETRA, tets);
  if (mesh.tetDefects.size() == mesh.tets.size())
  {
    vtkNew<vtkUnsignedCharArray> defects; // bits as vtkMeshValidityCheck's
    defects->SetName(omesh::keys::DEFECTS);
    defects->SetNumberOfTuples(static_cast<vtkIdType>(mesh.tets.size()));
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      defects->SetValue(static_cast<vtkIdType>(t), mesh.tetDefects[t]);
    grid->GetCellData()->AddArray(defects);
  }
  grid->GetCellData()->AddArray(material);
  grid->GetCellData()->SetScalars(material);
  grid->GetCellData()->AddArray(dihedral);
  grid->GetCellData()->AddArray(largest);
  grid->GetCellData()->AddArray(ratio);
}

void TetMeshOutput::FillInterfaces(vtkPolyData* interfaces, const omesh::TetMesh& mesh, vtkUnstructuredGrid* grid)
{
  interfaces->SetPoints(grid->GetPoints());
  vtkNew<vtkCellArray> tris;
  vtkNew<vtkIntArray> sides;
  sides->SetName(omesh::keys::MATERIALS);
  sides->SetNumberOfComponents(2);
  for (size_t f = 0; f < mesh.interfaceTriangles.size(); ++f)
  {
    const auto& t = mesh.interfaceTriangles[f];
    const vtkIdType ids[3] = { t[0], t[1], t[2] };
    tris->InsertNextCell(3, ids);
    const int m[2] = { mesh.interfaceMaterials[f][0], mesh.interfaceMaterials[f][1] };
    sides->InsertNextTypedTuple(m);
  }
  interfaces->SetPolys(tris);
  interfaces->GetCellData()->AddArray(sides);
}

void TetMeshOutput::FillSegments(vtkPolyData* segments, const omesh::TetMesh& mesh, const omesh::FeatureSelection& selection)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> present;
  present->SetName(omesh::keys::PRESENT);
  vtkNew<vtkIntArray> input;
  input->SetName(omesh::keys::INPUT_SEGMENT);
  vtkNew<vtkIntArray> origin;
  origin->SetName(omesh::keys::ORIGIN);
  vtkNew<vtkIntArray> separates;
  separates->SetName(omesh::keys::MATERIALS);
  separates->SetNumberOfComponents(4);
  for (const auto& s : mesh.segments)
  {
    const vtkIdType ids[2] = { points->InsertNextPoint(s.a.x, s.a.y, s.a.z), points->InsertNextPoint(s.b.x, s.b.y, s.b.z) };
    lines->InsertNextCell(2, ids);
    present->InsertNextValue(s.present ? 1 : 0);
    input->InsertNextValue(s.input);
    const bool tagged = s.input >= 0 && static_cast<std::size_t>(s.input) < selection.origin.size();
    const omesh::FeatureSelection::Origin o = tagged ? selection.origin[s.input] : omesh::FeatureSelection::Origin{};
    origin->InsertNextValue(o.automatic ? 1 : 0);
    separates->InsertNextTypedTuple(o.materials.data());
  }
  segments->SetPoints(points);
  segments->SetLines(lines);
  segments->GetCellData()->AddArray(present);
  segments->GetCellData()->SetScalars(present);
  segments->GetCellData()->AddArray(input);
  segments->GetCellData()->AddArray(origin);
  segments->GetCellData()->AddArray(separates);
}

void TetMeshOutput::AddStatistics(vtkFieldData* fieldData, const std::map<std::string, double>& statistics)
{
  vtkNew<vtkStringArray> names;
  names->SetName(omesh::keys::STATISTIC_NAMES);
  vtkNew<vtkDoubleArray> values;
  values->SetName(omesh::keys::STATISTIC_VALUES);
  for (const auto& [name, value] : statistics)
  {
    names->InsertNextValue(name);
    values->InsertNextValue(value);
  }
  fieldData->AddArray(names);
  fieldData->AddArray(values);
}

void TetMeshOutput::AddStrings(vtkFieldData* fieldData, const char* name, const std::vector<std::string>& strings)
{
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  for (const auto& s : strings)
    array->InsertNextValue(s);
  fieldData->AddArray(array);
}
