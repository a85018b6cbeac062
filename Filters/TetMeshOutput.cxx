// SPDX-License-Identifier: GPL-3.0-or-later
#include "TetMeshOutput.h"

#include "FieldDataKeys.h"
#include "MeshQuality.h"
#include "ShapeSummary.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
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
  double* xyz = vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0);
  for (const omesh::Vec3& p : pts)
  {
    *xyz++ = p.x;
    *xyz++ = p.y;
    *xyz++ = p.z;
  }
  return points;
}

template <typename Array>
vtkSmartPointer<Array> namedArray(const char* name, std::size_t values)
{
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  a->SetNumberOfValues(static_cast<vtkIdType>(values));
  return a;
}
}

omesh::TetShapeArrays TetShapeCellArrays::allocate(std::size_t n)
{
  this->minDihedral = namedArray<vtkDoubleArray>(omesh::keys::MIN_DIHEDRAL_ANGLE, n);
  this->maxDihedral = namedArray<vtkDoubleArray>(omesh::keys::MAX_DIHEDRAL_ANGLE, n);
  this->radiusEdge = namedArray<vtkDoubleArray>(omesh::keys::RADIUS_EDGE_RATIO, n);
  this->tetrahedra = n;
  omesh::TetShapeArrays buffers;
  buffers.minDihedral = this->minDihedral->GetPointer(0);
  buffers.maxDihedral = this->maxDihedral->GetPointer(0);
  buffers.radiusEdge = this->radiusEdge->GetPointer(0);
  return buffers;
}

void TetMeshOutput::FillGrid(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh,
  const omesh::QuadraticTetMesh* quadratic, const std::vector<std::string>& inputWarnings,
  const TetShapeCellArrays* shapes)
{
  grid->SetPoints(toPoints(quadratic ? quadratic->points : mesh.points));
  AddTetrahedra(grid, mesh, quadratic, shapes);
  const std::vector<int>& dimensions = quadratic ? quadratic->pointDimension : mesh.pointDimension;
  auto dimension = namedArray<vtkIntArray>(omesh::keys::DIMENSION, dimensions.size());
  std::copy(dimensions.begin(), dimensions.end(), dimension->GetPointer(0));
  grid->GetPointData()->AddArray(dimension);
  AddStatistics(grid->GetFieldData(), mesh.statistics);
  AddStrings(grid->GetFieldData(), omesh::keys::WARNINGS, mesh.warnings);
  // The inputs' warnings again (frames, units, materials or labels that vanished): the ones the
  // command line's --strict turns into a failure.
  AddStrings(grid->GetFieldData(), omesh::keys::INPUT_WARNINGS, inputWarnings);
}

void TetMeshOutput::AddTetrahedra(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh,
  const omesh::QuadraticTetMesh* quadratic, const TetShapeCellArrays* shapes)
{
  const std::size_t n = mesh.tets.size();
  const vtkIdType nodes = quadratic ? 10 : 4;
  // the cells' offsets and connectivity written in place, positively oriented
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(n) + 1);
  connectivity->SetNumberOfValues(nodes * static_cast<vtkIdType>(n));
  vtkIdType* offset = offsets->GetPointer(0);
  vtkIdType* ids = connectivity->GetPointer(0);
  const auto& P = mesh.points;
  for (std::size_t t = 0; t < n; ++t, ids += nodes)
  {
    offset[t] = nodes * static_cast<vtkIdType>(t);
    if (quadratic)
    {
      std::copy(quadratic->tets[t].begin(), quadratic->tets[t].end(), ids);
      continue;
    }
    auto k = mesh.tets[t];
    if (omesh::signedVolume(P[k[0]], P[k[1]], P[k[2]], P[k[3]]) < 0)
      std::swap(k[0], k[1]);
    std::copy(k.begin(), k.end(), ids);
  }
  offset[n] = nodes * static_cast<vtkIdType>(n);
  vtkNew<vtkCellArray> tets;
  tets->SetData(offsets, connectivity);
  grid->SetCells(quadratic ? VTK_QUADRATIC_TETRA : VTK_TETRA, tets);

  auto material = namedArray<vtkIntArray>(omesh::keys::MATERIAL, n);
  std::copy(mesh.tetMaterial.begin(), mesh.tetMaterial.begin() + static_cast<std::ptrdiff_t>(n), material->GetPointer(0));
  TetShapeCellArrays measured;
  if (!shapes || shapes->tetrahedra != n || !shapes->minDihedral)
  {
    omesh::summariseShapes(mesh, measured.allocate(n));
    shapes = &measured;
  }
  if (!mesh.separatingFaces.empty())
    AddSeparatingFaces(grid, mesh);
  if (mesh.tetDefects.size() == n)
  {
    auto defects = namedArray<vtkUnsignedCharArray>(omesh::keys::DEFECTS, n); // bits as vtkMeshValidityCheck's
    std::copy(mesh.tetDefects.begin(), mesh.tetDefects.end(), defects->GetPointer(0));
    grid->GetCellData()->AddArray(defects);
  }
  grid->GetCellData()->AddArray(material);
  grid->GetCellData()->SetScalars(material);
  grid->GetCellData()->AddArray(shapes->minDihedral);
  grid->GetCellData()->AddArray(shapes->maxDihedral);
  grid->GetCellData()->AddArray(shapes->radiusEdge);
}

void TetMeshOutput::AddSeparatingFaces(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh)
{
  // The face not holding corner c, in the written (positively oriented) corner order, is the
  // Abaqus face S1..S4 (1-2-3, 1-4-2, 2-4-3, 3-4-1) numbered kFaceWithout[c] + 1.
  constexpr int kFaceWithout[4] = { 2, 3, 1, 0 };
  const auto& P = mesh.points;
  vtkNew<vtkIdTypeArray> faces;
  faces->SetName(omesh::keys::SEPARATING_FACES);
  faces->SetNumberOfComponents(2);
  faces->SetNumberOfTuples(static_cast<vtkIdType>(mesh.separatingFaces.size()));
  vtkIdType* out = faces->GetPointer(0);
  for (const auto& f : mesh.separatingFaces)
  {
    const auto& k = mesh.tets[f.tet];
    const bool swapped = omesh::signedVolume(P[k[0]], P[k[1]], P[k[2]], P[k[3]]) < 0; // as AddTetrahedra
    const int corner = swapped && f.opposite < 2 ? 1 - f.opposite : f.opposite;
    *out++ = 4 * static_cast<vtkIdType>(f.tet) + kFaceWithout[corner];
    *out++ = f.other;
  }
  grid->GetFieldData()->AddArray(faces);
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

void TetMeshOutput::AddStatistic(vtkFieldData* fieldData, const std::string& name, double value)
{
  auto* names = vtkStringArray::SafeDownCast(fieldData->GetAbstractArray(omesh::keys::STATISTIC_NAMES));
  auto* values = vtkDoubleArray::SafeDownCast(fieldData->GetArray(omesh::keys::STATISTIC_VALUES));
  if (!names || !values)
    return;
  names->InsertNextValue(name);
  values->InsertNextValue(value);
}

void TetMeshOutput::AddStrings(vtkFieldData* fieldData, const char* name, const std::vector<std::string>& strings)
{
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  for (const auto& s : strings)
    array->InsertNextValue(s);
  fieldData->AddArray(array);
}
