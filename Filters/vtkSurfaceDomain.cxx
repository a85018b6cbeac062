// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSurfaceDomain.h"

#include "InputError.h"
#include "OracleBuilder.h"
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
#include <vtkPolyData.h>
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
  try
  {
    if (!data)
      throw omesh::InputError(who + ": no input on port 0 (connect a closed surface, vtkPolyData)");
    if (!input)
      throw omesh::InputError(who + ": input port 0 needs a surface (vtkPolyData), got " +
        std::string(data->GetClassName()) +
        (data->IsA("vtkImageData") ? "; a label image goes to vtkLabelMapDomain" : ""));
    if (this->MaterialId < 0)
      throw omesh::InputError(who + ": MaterialId " + std::to_string(this->MaterialId) + " is negative");
    if (!(this->MergeTolerance >= 0 && this->MergeTolerance <= 1))
    {
      std::ostringstream o;
      o << who << ": MergeTolerance " << this->MergeTolerance
        << " must be between 0 and 1 (a fraction of the bounding-box diagonal)";
      throw omesh::InputError(o.str());
    }
    if (this->InsideTest != CLOSED && this->InsideTest != WINDING_NUMBER && this->InsideTest != AUTOMATIC)
      throw omesh::InputError(who + ": InsideTest " + std::to_string(this->InsideTest) +
        " is not one of 0 (Closed), 1 (WindingNumber) and 2 (Automatic)");
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
      triangles.validateTriangles(who);
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
  md.WriteTo(output->GetFieldData());
  return 1;
}
