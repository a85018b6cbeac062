// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLabelMapDomain.h"

#include "InputError.h"
#include "LabelMapDomain.h"
#include "OracleBuilder.h"
#include "MemoryCheck.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <vector>

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

int vtkLabelMapDomain::FillInputPortInformation(int, vtkInformation* info)
{
  // Any data object: a wrong type gets this filter's error naming the port, not an empty output.
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

int vtkLabelMapDomain::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (!inInfo || !inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    return 1; // not an image: RequestData says so
  // Before the reader allocates the image (a failed information pass stops the update before any
  // RequestData; a failed update-extent pass does not): VTK's readers abort the process when an
  // allocation fails. 7 bytes a voxel: one read, and this filter's own 6.
  const int* e = inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  const double voxels =
    static_cast<double>(e[1] - e[0] + 1) * static_cast<double>(e[3] - e[2] + 1) * static_cast<double>(e[5] - e[4] + 1);
  try
  {
    omesh::checkMemory(std::string("vtkLabelMapDomain '") + (this->DomainName ? this->DomainName : "") + "'",
      "its input image of " + std::to_string(e[1] - e[0] + 1) + " x " + std::to_string(e[3] - e[2] + 1) + " x " +
        std::to_string(e[5] - e[4] + 1) + " voxels (refused before it is read)",
      voxels, 7.0);
  }
  catch (const omesh::InputError& error)
  {
    vtkErrorMacro(<< error.what());
    return 0;
  }
  return this->Superclass::RequestInformation(request, inputVector, outputVector);
}

int vtkLabelMapDomain::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (!inInfo || !inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    return 1;
  return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
}

namespace
{
std::string arrayNames(vtkDataSetAttributes* attributes)
{
  std::string names;
  for (int i = 0; i < attributes->GetNumberOfArrays(); ++i)
  {
    const char* n = attributes->GetArrayName(i);
    names += (names.empty() ? "'" : ", '") + std::string(n ? n : "") + "'";
  }
  return names.empty() ? "none" : names;
}

/// The label array when none was named: the one integer single-component array of `attributes`;
/// of several, the active scalars if among them. Null when there is none; throws InputError
/// naming them when several leave the choice open.
vtkDataArray* integerLabelArray(vtkDataSetAttributes* attributes, const std::string& who, const char* what)
{
  std::vector<vtkDataArray*> candidates;
  for (int i = 0; i < attributes->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* a = attributes->GetArray(i);
    if (a && a->GetNumberOfComponents() == 1 && a->GetDataType() != VTK_FLOAT && a->GetDataType() != VTK_DOUBLE)
      candidates.push_back(a);
  }
  if (candidates.size() == 1)
    return candidates[0];
  if (candidates.empty())
    return nullptr;
  for (vtkDataArray* a : candidates)
    if (a == attributes->GetScalars())
      return a;
  std::string names;
  for (vtkDataArray* a : candidates)
    names += (names.empty() ? "'" : ", '") + std::string(a->GetName() ? a->GetName() : "") + "'";
  throw omesh::InputError(who + ": the image has several integer " + what + " arrays (" + names +
    ") and none is the active scalars: name the label array (scene key \"array\", ParaView's Label Array, "
    "SetInputArrayToProcess)");
}
}

namespace
{
/// Why no label array was found: the selected one is missing, or the image has no scalars; with
/// the arrays it has.
std::string noLabelArray(vtkInformation* selected, vtkImageData* input, const std::string& who)
{
  const char* wanted = selected && selected->Has(vtkDataObject::FIELD_NAME())
    ? selected->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  const bool cells = selected && selected->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
    selected->Get(vtkDataObject::FIELD_ASSOCIATION()) == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  const std::string arrays = "point arrays: " + arrayNames(input->GetPointData()) +
    "; cell arrays: " + arrayNames(input->GetCellData());
  if (wanted && *wanted)
    return who + ": the image has no " + (cells ? "cell" : "point") + " array '" + wanted + "' (" + arrays + ")";
  return who + ": the image has no label array: no point or cell scalars (" + arrays + "); select the label array";
}
}

int vtkLabelMapDomain::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* data = vtkDataObject::GetData(inputVector[0]);
  vtkImageData* input = vtkImageData::SafeDownCast(data);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  const std::string name = this->DomainName ? this->DomainName : "";
  const std::string who = "vtkLabelMapDomain '" + name + "'";
  if (!input)
  {
    vtkErrorMacro(<< who << ": "
                  << (data ? "input port 0 needs a label image (vtkImageData), got " + std::string(data->GetClassName()) +
                        (data->IsA("vtkPolyData") ? "; a surface goes to vtkSurfaceDomain" : "")
                           : std::string("no input on port 0 (connect a label image, vtkImageData)")));
    return 0;
  }

  OracleDomainMetadata md;
  md.Kind = "LabelMap";
  md.Name = name;
  md.Cut = this->Cut;
  md.BackgroundLabel = this->BackgroundLabel;
  md.LabelInterpolation = this->Interpolation == SMOOTH ? "Smooth" : this->Interpolation == TRILINEAR ? "Trilinear" : "Nearest";
  md.Criteria = { this->FacetAngle, this->FacetSize, this->FacetDistance, this->CellSize,
    this->CellRadiusEdgeRatio, this->EdgeSize };
  int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkDataArray* array = nullptr;
  vtkInformation* chosen = this->GetInputArrayInformation(0);
  const bool named = chosen && chosen->Has(vtkDataObject::FIELD_NAME()) && chosen->Get(vtkDataObject::FIELD_NAME()) &&
    *chosen->Get(vtkDataObject::FIELD_NAME());
  try
  {
    if (named)
      array = this->GetInputArrayToProcess(0, inputVector, association);
    else if ((array = integerLabelArray(input->GetPointData(), who, "point")))
      association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    else if ((array = input->GetPointData()->GetScalars()))
      association = vtkDataObject::FIELD_ASSOCIATION_POINTS; // integral values in a float array
    else if ((array = integerLabelArray(input->GetCellData(), who, "cell")) ||
      (array = input->GetCellData()->GetScalars()))
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS; // the cells are the voxels
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
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
    if (this->Interpolation != NEAREST && this->Interpolation != TRILINEAR && this->Interpolation != SMOOTH)
      throw omesh::InputError(who + ": Interpolation " + std::to_string(this->Interpolation) +
        " is not 0 (Nearest), 1 (Trilinear) or 2 (Smooth)");
    if (!array)
      throw omesh::InputError(noLabelArray(this->GetInputArrayInformation(0), input, who));
    if (md.LabelArray.empty())
      throw omesh::InputError(who + ": the label array has no name; name it so the oracle can find it again");
    OracleDomainMetadata validation = md; // Nearest: the checks without the smoothing's work
    validation.LabelInterpolation = "Nearest";
    OracleBuilder::ToLabelMap(input, validation, who); // full validation: integer, non-empty, labels >= 0
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
  os << indent << "Interpolation: "
     << (this->Interpolation == SMOOTH ? "Smooth" : this->Interpolation == TRILINEAR ? "Trilinear" : "Nearest") << "\n";
  os << indent << "Cut: " << this->Cut << "\n";
  os << indent << "DomainName: " << (this->DomainName ? this->DomainName : "(none)") << "\n";
  for (const auto& [label, name] : this->LabelNames)
    os << indent << "Label " << label << ": " << name << "\n";
}
