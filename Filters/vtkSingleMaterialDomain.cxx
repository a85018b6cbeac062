// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSingleMaterialDomain.h"

#include "OracleDomainMetadata.h"

vtkSingleMaterialDomain::vtkSingleMaterialDomain() = default;

vtkSingleMaterialDomain::~vtkSingleMaterialDomain()
{
  this->SetMaterialName(nullptr);
}

std::string vtkSingleMaterialDomain::Describe()
{
  return std::string(this->GetClassName()) + " '" + (this->MaterialName ? this->MaterialName : "") + "'";
}

void vtkSingleMaterialDomain::FillMetadata(const char* kind, OracleDomainMetadata& md)
{
  md.Kind = kind;
  md.Name = this->MaterialName ? this->MaterialName : "";
  md.MaterialName = md.Name;
  md.MaterialId = this->MaterialId;
  md.Cut = this->Cut;
  md.Criteria = { this->FacetAngle, this->FacetSize, this->FacetDistance, this->CellSize,
    this->CellRadiusEdgeRatio, this->EdgeSize };
}

void vtkSingleMaterialDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaterialId: " << this->MaterialId << "\n";
  os << indent << "MaterialName: " << (this->MaterialName ? this->MaterialName : "(none)") << "\n";
  os << indent << "Cut: " << this->Cut << "\n";
}
