// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLabelMapDomain.h"

#include "InputError.h"
#include "LabelMapDomain.h"
#include "OracleBuilder.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>

vtkStandardNewMacro(vtkLabelMapDomain);

vtkLabelMapDomain::vtkLabelMapDomain()
{
  this->SetDomainName("LabelMap");
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

vtkLabelMapDomain::~vtkLabelMapDomain()
{
  this->SetDomainName(nullptr);
}

void vtkLabelMapDomain::SetLabelName(int label, const char* name)
{
  const std::string value = name ? name : "";
  auto it = this->LabelNames.find(label);
  if (it == this->LabelNames.end() || it->second != value)
  {
    this->LabelNames[label] = value;
    this->Modified();
  }
}

const char* vtkLabelMapDomain::GetLabelName(int label)
{
  auto it = this->LabelNames.find(label);
  return it == this->LabelNames.end() ? nullptr : it->second.c_str();
}

void vtkLabelMapDomain::ClearLabelNames()
{
  if (!this->LabelNames.empty())
  {
    this->LabelNames.clear();
    this->Modified();
  }
}

int vtkLabelMapDomain::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  const std::string name = this->DomainName ? this->DomainName : "";
  const std::string who = "vtkLabelMapDomain '" + name + "'";

  OracleDomainMetadata md;
  md.Kind = "LabelMap";
  md.Name = name;
  md.Cut = this->Cut;
  md.BackgroundLabel = this->BackgroundLabel;
  md.TrilinearLabels = this->Interpolation == TRILINEAR;
  int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkDataArray* array = input ? this->GetInputArrayToProcess(0, inputVector, association) : nullptr;
  if (!array && input && input->GetCellData()->GetScalars())
  {
    array = input->GetCellData()->GetScalars(); // only cell scalars: the cells are the voxels
    association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  md.CellLabels = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  md.LabelArray = (array && array->GetName()) ? array->GetName() : "";
  for (const auto& [label, labelName] : this->LabelNames)
  {
    md.LabelValues.push_back(label);
    md.LabelNames.push_back(labelName);
  }
  try
  {
    if (!input)
      throw omesh::InputError(who + ": no input image");
    if (!array)
      throw omesh::InputError(who + ": the image has no label array (no point or cell scalars, "
                                    "or the selected array does not exist)");
    if (md.LabelArray.empty())
      throw omesh::InputError(who + ": the label array has no name; name it so the oracle can find it again");
    OracleBuilder::ToLabelMap(input, md, who); // full validation: integer, non-empty, labels >= 0
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  output->ShallowCopy(input);
  md.WriteTo(output->GetFieldData());
  return 1;
}

void vtkLabelMapDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BackgroundLabel: " << this->BackgroundLabel << "\n";
  os << indent << "Interpolation: " << (this->Interpolation == TRILINEAR ? "Trilinear" : "Nearest") << "\n";
  os << indent << "Cut: " << this->Cut << "\n";
  os << indent << "DomainName: " << (this->DomainName ? this->DomainName : "(none)") << "\n";
  for (const auto& [label, name] : this->LabelNames)
    os << indent << "Label " << label << ": " << name << "\n";
}
