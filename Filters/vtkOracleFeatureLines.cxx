// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkOracleFeatureLines.h"

#include "FieldDataKeys.h"
#include "FeatureSelection.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "MeshCriteria.h"
#include "LabelSmoothing.h"
#include "OracleBuilder.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>

#include <cmath>

vtkStandardNewMacro(vtkOracleFeatureLines);

vtkOracleFeatureLines::vtkOracleFeatureLines()
{
  // the tetrahedralizer's defaults, from the core
  const omesh::MeshCriteria::Values c = omesh::MeshCriteria::defaults().values();
  this->EdgeSize = c.edgeSize;
  this->FacetSize = c.facetSize;
  this->FacetDistance = c.facetDistance;
  this->CreaseAngle = omesh::kDefaultCreaseAngle;
}

int vtkOracleFeatureLines::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1); // so "no input" gets this filter's message
  return 1;
}

namespace
{
/// The curves as polylines: cell arrays Materials (up to four, -2 pads), Triple and Crease, point array
/// SmallAngle (180 where none), field data Warnings.
void toPolyData(const omesh::FeatureLines& found, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const omesh::Vec3& p : found.segments.points)
    points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> materials;
  materials->SetName(omesh::keys::MATERIALS);
  materials->SetNumberOfComponents(4);
  vtkNew<vtkIntArray> triple;
  triple->SetName("Triple");
  vtkNew<vtkIntArray> crease;
  crease->SetName("Crease");
  for (const omesh::FeatureLine& l : found.lines)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(l.points.size()));
    for (int p : l.points)
      lines->InsertCellPoint(p);
    int m[4] = { -2, -2, -2, -2 };
    for (size_t k = 0; k < l.materials.size() && k < 4; ++k)
      m[k] = l.materials[k];
    materials->InsertNextTypedTuple(m);
    triple->InsertNextValue(l.triple ? 1 : 0);
    crease->InsertNextValue(l.crease ? 1 : 0);
  }
  vtkNew<vtkDoubleArray> smallAngle;
  smallAngle->SetName("SmallAngle");
  smallAngle->SetNumberOfTuples(points->GetNumberOfPoints());
  smallAngle->Fill(180.0);
  for (const auto& a : found.smallAngles)
    smallAngle->SetValue(a.point, a.degrees);
  vtkNew<vtkStringArray> warnings;
  warnings->SetName(omesh::keys::WARNINGS);
  for (const std::string& w : found.warnings)
    warnings->InsertNextValue(w);
  output->SetPoints(points);
  output->SetLines(lines);
  output->GetCellData()->AddArray(materials);
  output->GetCellData()->AddArray(triple);
  output->GetCellData()->AddArray(crease);
  output->GetPointData()->AddArray(smallAngle);
  output->GetFieldData()->AddArray(warnings);
}
}

int vtkOracleFeatureLines::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  omesh::FeatureLines found;
  try
  {
    for (double v : { this->MaximumSegmentLength, this->Spacing, this->EdgeSize, this->FacetSize, this->FacetDistance })
      if (!std::isfinite(v))
        throw omesh::InputError("vtkOracleFeatureLines: MaximumSegmentLength, Spacing, EdgeSize, FacetSize and "
                                "FacetDistance must be numbers (0 = automatic / no bound)");
    omesh::checkCreaseAngle(this->CreaseAngle, "vtkOracleFeatureLines: CreaseAngle");
    if (!input)
      throw omesh::InputError("vtkOracleFeatureLines: no input on port 0 (connect a vtkHierarchicalOracle)");
    auto oracle = OracleBuilder::BuildOracle(input, [this](double) { return !this->GetAbortExecute(); });
    omesh::MaterialCriteria criteria;
    criteria.global.edgeSize = this->EdgeSize;
    criteria.global.facetSize = this->FacetSize;
    criteria.global.facetDistance = this->FacetDistance;
    omesh::FeatureLineOptions options = omesh::featureLineOptions(*oracle, criteria);
    if (this->MaximumSegmentLength > 0)
    {
      options.maxSegmentLength = this->MaximumSegmentLength;
      options.spacing = 0.5 * this->MaximumSegmentLength;
    }
    if (this->Spacing > 0)
      options.spacing = this->Spacing;
    options.creaseAngle = this->CreaseAngle;
    options.progress = [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    found = omesh::findFeatureLines(*oracle, options);
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const omesh::LabelSmoothingAborted&)
  {
    vtkErrorMacro(<< "feature line search aborted (AbortExecute) while smoothing a label map: no output");
    return 0;
  }
  catch (const omesh::FeatureSearchAborted&)
  {
    vtkErrorMacro(<< "feature line search aborted (AbortExecute): no output");
    return 0;
  }
  for (const std::string& w : found.warnings)
    vtkWarningMacro(<< w);

  toPolyData(found, output);
  return 1;
}

void vtkOracleFeatureLines::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumSegmentLength: " << this->MaximumSegmentLength << "\n";
  os << indent << "Spacing: " << this->Spacing << "\n";
  os << indent << "CreaseAngle: " << this->CreaseAngle << "\n";
  os << indent << "EdgeSize: " << this->EdgeSize << "\n";
  os << indent << "FacetSize: " << this->FacetSize << "\n";
  os << indent << "FacetDistance: " << this->FacetDistance << "\n";
}
