// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSurfaceDomain.h"

#include "InputError.h"
#include "OracleBuilder.h"
#include "SeamWelding.h"
#include "SelfIntersections.h"
#include "TriangleSurface.h"

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCleanPolyData.h>
#include <vtkTriangleFilter.h>

#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkSurfaceDomain);

namespace
{
bool onlyTriangles(vtkPolyData* pd)
{
  if (pd->GetNumberOfStrips() > 0)
    return false;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    if (n != 3)
      return false;
  }
  return true;
}

/// Throws omesh::InputError naming `who` for a property out of its range.
void checkProperties(const std::string& who, int materialId, double mergeTolerance, int insideTest)
{
  if (materialId < 0)
    throw omesh::InputError(who + ": MaterialId " + std::to_string(materialId) + " is negative");
  if (!(mergeTolerance >= 0 && mergeTolerance <= 1))
  {
    std::ostringstream o;
    o << who << ": MergeTolerance " << mergeTolerance << " must be between 0 and 1 (a fraction of the bounding-box diagonal)";
    throw omesh::InputError(o.str());
  }
  if (insideTest != vtkSurfaceDomain::CLOSED && insideTest != vtkSurfaceDomain::WINDING_NUMBER &&
    insideTest != vtkSurfaceDomain::AUTOMATIC)
    throw omesh::InputError(who + ": InsideTest " + std::to_string(insideTest) +
      " is not one of 0 (Closed), 1 (WindingNumber) and 2 (Automatic)");
}

/// `surface` (triangles only) with the welded seams' points merged: each welded group's point data
/// from its first member, the triangles' cell data kept (weld.surface keeps their order).
vtkSmartPointer<vtkPolyData> weldedCopy(vtkPolyData* surface, const omesh::SeamWelding& weld)
{
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(weld.surface.points.size()));
  for (size_t i = 0; i < weld.surface.points.size(); ++i)
  {
    const omesh::Vec3& p = weld.surface.points[i];
    points->SetPoint(static_cast<vtkIdType>(i), p.x, p.y, p.z);
  }
  out->SetPoints(points);
  vtkPointData* from = surface->GetPointData();
  out->GetPointData()->CopyAllocate(from, points->GetNumberOfPoints());
  std::vector<char> done(weld.surface.points.size(), 0);
  for (size_t v = 0; v < weld.pointIndex.size(); ++v)
    if (!done[weld.pointIndex[v]])
    {
      done[weld.pointIndex[v]] = 1;
      out->GetPointData()->CopyData(from, static_cast<vtkIdType>(v), weld.pointIndex[v]);
    }
  vtkNew<vtkCellArray> polys;
  for (const auto& t : weld.surface.triangles)
  {
    const vtkIdType ids[3] = { t[0], t[1], t[2] };
    polys->InsertNextCell(3, ids);
  }
  out->SetPolys(polys);
  const vtkIdType firstPoly = surface->GetNumberOfVerts() + surface->GetNumberOfLines();
  out->GetCellData()->CopyAllocate(surface->GetCellData(), polys->GetNumberOfCells());
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c)
    out->GetCellData()->CopyData(surface->GetCellData(), firstPoly + c, c);
  return out;
}

/// `surface` with its unwelded seams welded (omesh::weldSeams; `triangles` its triangles), or
/// itself when none is; `description` says what was welded.
vtkSmartPointer<vtkPolyData> weldedSeams(vtkPolyData* surface, const omesh::TriangleSurface& triangles, std::string& description)
{
  const omesh::SeamWelding weld =
    omesh::weldSeams(triangles, omesh::kSeamWeldLimit * omesh::norm(triangles.bounds().size()));
  if (!weld.welded())
    return surface;
  description = weld.describe();
  return weldedCopy(surface, weld);
}
}

vtkSurfaceDomain::vtkSurfaceDomain()
{
  this->SetMaterialName("Surface");
}

int vtkSurfaceDomain::FillInputPortInformation(int, vtkInformation* info)
{
  // Any data object: a wrong type gets this filter's error naming the port, not an empty output.
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

int vtkSurfaceDomain::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* data = vtkDataObject::GetData(inputVector[0]);
  vtkPolyData* input = vtkPolyData::SafeDownCast(data);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  const std::string who = this->Describe();
  vtkSmartPointer<vtkPolyData> surface = input;
  std::string seamWeld; // what the automatic test welded, for the mesher's input warnings
  try
  {
    if (!data)
      throw omesh::InputError(who + ": no input on port 0 (connect a closed surface, vtkPolyData)");
    if (!input)
      throw omesh::InputError(who + ": input port 0 needs a surface (vtkPolyData), got " +
        std::string(data->GetClassName()) +
        (data->IsA("vtkImageData") ? "; a label image goes to vtkLabelMapDomain" : ""));
    checkProperties(who, this->MaterialId, this->MergeTolerance, this->InsideTest);
    if (input->GetNumberOfPoints() == 0)
      throw omesh::InputError(who + ": surface is empty (no points)");
    // Refuse NaN and absurd coordinates before any filter computes bounds or tolerances from them.
    OracleBuilder::CheckCoordinates(input->GetPoints(), who, "surface");
    if (!onlyTriangles(input))
    {
      vtkNew<vtkTriangleFilter> triangulate; // polygons, quads and strips -> triangles
      triangulate->SetInputData(input);
      triangulate->PassVertsOff();
      triangulate->PassLinesOff();
      triangulate->Update();
      surface = triangulate->GetOutput();
    }
    vtkNew<vtkStaticCleanPolyData> merge; // unwelded corners -> shared points
    merge->SetInputData(surface);
    merge->ToleranceIsAbsoluteOff();
    merge->SetTolerance(this->MergeTolerance);
    merge->ConvertPolysToLinesOff(); // triangles collapsed by the merge are dropped, not kept as lines
    merge->ConvertLinesToPointsOff();
    merge->ConvertStripsToPolysOff();
    merge->RemoveUnusedPointsOn();
    merge->Update();
    surface = merge->GetOutput();
    // Validate here, where the user connected the surface, not later inside the mesher.
    const omesh::TriangleSurface triangles = OracleBuilder::ToTriangleSurface(surface, who);
    // Automatic: what the surface lacks is found once, where the oracle builds it (its warning
    // reaches the mesher's input warnings); here only what no inside test can work with.
    if (this->InsideTest == AUTOMATIC)
    {
      // unwelded seams welded here, so that the output's sharp edges (vtkFeatureEdges) are there
      triangles.validateTriangles(who);
      surface = weldedSeams(surface, triangles, seamWeld);
    }
    else if (this->InsideTest == WINDING_NUMBER)
    {
      triangles.validateTriangles(who);
      const std::vector<omesh::BorderLoop> loops = triangles.borderLoops();
      if (!loops.empty())
        vtkWarningMacro(<< who << ": surface is not closed: " << omesh::TriangleSurface::describeHoles(loops)
                        << "; the winding-number inside test closes them");
    }
    else
      triangles.validateClosed(who);
    if (this->InsideTest != AUTOMATIC && !this->AllowSelfIntersections)
      omesh::refuseSelfIntersections(triangles, who);
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  output->CopyStructure(surface);
  output->GetPointData()->PassData(surface->GetPointData());
  output->GetCellData()->PassData(surface->GetCellData());
  output->GetFieldData()->PassData(input->GetFieldData());
  OracleDomainMetadata md;
  this->FillMetadata("Surface", md);
  md.Parameters = { this->AllowSelfIntersections ? 1.0 : 0.0, static_cast<double>(this->InsideTest) };
  md.SeamWeld = seamWeld;
  md.WriteTo(output->GetFieldData());
  return 1;
}
