// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSurfaceDomain.h"

#include "InputError.h"
#include "OracleBuilder.h"
#include "TriangleSurface.h"

#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

vtkStandardNewMacro(vtkSurfaceDomain);

vtkSurfaceDomain::vtkSurfaceDomain()
{
  this->SetMaterialName("Surface");
}

int vtkSurfaceDomain::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  const std::string who = this->Describe();
  try
  {
    if (this->MaterialId < 0)
      throw omesh::InputError(who + ": MaterialId " + std::to_string(this->MaterialId) + " is negative");
    // Validate here, where the user connected the surface, not later inside the mesher.
    OracleBuilder::ToTriangleSurface(input, who).validateClosed(who);
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  output->ShallowCopy(input);
  OracleDomainMetadata md;
  this->FillMetadata("Surface", md);
  md.WriteTo(output->GetFieldData());
  return 1;
}
