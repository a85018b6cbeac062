// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkOracleSampler.h"

#include "FieldDataKeys.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelSmoothing.h"
#include "OracleBuilder.h"
#include "MemoryCheck.h"
#include "InputWarnings.h"

#include <vtkDataObject.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkSMPTools.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <cmath>
#include <map>
#include <sstream>

vtkStandardNewMacro(vtkOracleSampler);

vtkOracleSampler::vtkOracleSampler()
{
  this->SetNumberOfInputPorts(1);
}

int vtkOracleSampler::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1); // so "no input" gets this filter's message
  return 1;
}

int vtkOracleSampler::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int ext[6] = { 0, std::max(this->Dimensions[0], 1) - 1, 0, std::max(this->Dimensions[1], 1) - 1, 0,
    std::max(this->Dimensions[2], 1) - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext, 6);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_INT, 1);
  return 1;
}

int vtkOracleSampler::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // The input is a domain collection, not an image: ask for all of it (its whole extent where the
  // pipeline gave it one: without an update extent beside it VTK prints an error).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  else
    inInfo->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
  return 1;
}

namespace
{
/// Throws for Dimensions below 1, a Material array too big for the memory, or bad Bounds.
void checkProperties(const int* dims, const double* b)
{
  if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
    throw omesh::InputError("vtkOracleSampler: Dimensions must be >= 1 on every axis");
  // before any work: the Material array (4 bytes a point)
  omesh::checkMemory("vtkOracleSampler", "Dimensions " + std::to_string(dims[0]) + " x " +
      std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + " points",
    static_cast<double>(dims[0]) * dims[1] * dims[2], 4.0);
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(b[i]) || std::abs(b[i]) > OracleBuilder::LargestCoordinate)
      throw omesh::InputError("vtkOracleSampler: Bounds must be finite and at most 1e15 in magnitude");
  // the default (0, -1) on every axis means "the oracle's bounds"; any other min > max is a slip
  const bool unset = b[0] == 0 && b[1] == -1 && b[2] == 0 && b[3] == -1 && b[4] == 0 && b[5] == -1;
  for (int axis = 0; axis < 3 && !unset; ++axis)
    if (b[2 * axis] > b[2 * axis + 1])
    {
      std::ostringstream o;
      o << "vtkOracleSampler: Bounds are inverted on " << "xyz"[axis] << ": " << b[2 * axis] << " > "
        << b[2 * axis + 1] << " (give xmin xmax ymin ymax zmin zmax, or 0 -1 0 -1 0 -1 for the oracle's bounds)";
      throw omesh::InputError(o.str());
    }
}

/// Field data MaterialIds and MaterialVolume: each material's sample count times the volume of a cell.
void addMaterialVolumes(vtkFieldData* fieldData, const int* values, vtkIdType n, double cell)
{
  std::map<int, vtkIdType> counts;
  for (vtkIdType i = 0; i < n; ++i)
    ++counts[values[i]];
  vtkNew<vtkIntArray> ids;
  ids->SetName(omesh::keys::MATERIAL_IDS);
  vtkNew<vtkDoubleArray> volumes;
  volumes->SetName(omesh::keys::MATERIAL_VOLUME);
  for (const auto& [m, c] : counts)
  {
    if (m == omesh::kOutside)
      continue;
    ids->InsertNextValue(m);
    volumes->InsertNextValue(c * cell);
  }
  fieldData->AddArray(ids);
  fieldData->AddArray(volumes);
}
}

int vtkOracleSampler::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  std::shared_ptr<omesh::HierarchicalOracle> oracle;
  omesh::BoundingBox box;
  try
  {
    checkProperties(this->Dimensions, this->Bounds);
    const double* b = this->Bounds;
    if (!input)
      throw omesh::InputError("vtkOracleSampler: no input on port 0 (connect a vtkHierarchicalOracle)");
    oracle = OracleBuilder::BuildOracle(input, [this](double f) {
      this->UpdateProgress(0.5 * f); // a label map's smoothing, then the samples
      return !this->GetAbortExecute();
    });
    for (const std::string& w : omesh::domainWarnings(*oracle))
      vtkWarningMacro(<< w);
    if (b[0] <= b[1] && b[2] <= b[3] && b[4] <= b[5]) // else the default: the oracle's bounds
    {
      box.add({ b[0], b[2], b[4] });
      box.add({ b[1], b[3], b[5] });
    }
    else
      box = oracle->bounds();
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const omesh::LabelSmoothingAborted&)
  {
    vtkErrorMacro(<< "sampling aborted (AbortExecute) while smoothing a label map: no output");
    return 0;
  }

  const int* d = this->Dimensions;
  double spacing[3];
  for (int i = 0; i < 3; ++i)
    spacing[i] = d[i] > 1 ? (box.max[i] - box.min[i]) / (d[i] - 1) : 1.0;
  output->SetExtent(0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1);
  output->SetOrigin(box.min.x, box.min.y, box.min.z);
  output->SetSpacing(spacing);
  vtkNew<vtkIntArray> material;
  material->SetName(omesh::keys::MATERIAL);
  material->SetNumberOfTuples(static_cast<vtkIdType>(d[0]) * d[1] * d[2]);
  int* values = material->GetPointer(0);

  // Slice by slice: parallel inside a slice, progress and abort between slices.
  const vtkIdType sliceSize = static_cast<vtkIdType>(d[0]) * d[1];
  for (int k = 0; k < d[2]; ++k)
  {
    if (this->GetAbortExecute())
      break;
    vtkSMPTools::For(0, d[1], [&](vtkIdType j0, vtkIdType j1) {
      for (vtkIdType j = j0; j < j1; ++j)
        for (int i = 0; i < d[0]; ++i)
        {
          const omesh::Vec3 p{ box.min.x + i * spacing[0], box.min.y + j * spacing[1], box.min.z + k * spacing[2] };
          values[k * sliceSize + j * d[0] + i] = oracle->material(p);
        }
    });
    this->UpdateProgress(static_cast<double>(k + 1) / d[2]);
  }
  if (this->GetAbortExecute())
  {
    vtkErrorMacro(<< "sampling aborted (AbortExecute): no output");
    output->Initialize();
    return 0;
  }
  output->GetPointData()->SetScalars(material);

  addMaterialVolumes(output->GetFieldData(), values, material->GetNumberOfTuples(), spacing[0] * spacing[1] * spacing[2]);
  return 1;
}

void vtkOracleSampler::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " " << this->Dimensions[2] << "\n";
  os << indent << "Bounds: " << this->Bounds[0] << " " << this->Bounds[1] << " " << this->Bounds[2] << " "
     << this->Bounds[3] << " " << this->Bounds[4] << " " << this->Bounds[5] << "\n";
}
