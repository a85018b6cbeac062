// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSphereDomain.h"

#include "InputError.h"
#include "OracleBuilder.h"

#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>

vtkStandardNewMacro(vtkSphereDomain);

vtkSphereDomain::vtkSphereDomain()
{
  this->SetNumberOfInputPorts(0);
  this->SetMaterialName("Sphere");
}

int vtkSphereDomain::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  OracleDomainMetadata md;
  this->FillMetadata("Sphere", md);
  md.Parameters = { this->Center[0], this->Center[1], this->Center[2], this->Radius };
  try
  {
    OracleDomainMetadata named = md; // the error names this filter
    named.Name = this->Describe();
    OracleBuilder::BuildImplicit(named); // validates radius, centre, material id
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(this->Center);
  sphere->SetRadius(this->Radius);
  sphere->SetThetaResolution(this->Resolution);
  sphere->SetPhiResolution(this->Resolution);
  sphere->Update();
  output->ShallowCopy(sphere->GetOutput());
  md.WriteTo(output->GetFieldData());
  return 1;
}

void vtkSphereDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Center: " << this->Center[0] << " " << this->Center[1] << " " << this->Center[2] << "\n";
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
}
