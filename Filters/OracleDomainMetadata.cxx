// SPDX-License-Identifier: GPL-3.0-or-later
#include "OracleDomainMetadata.h"

#include <algorithm>

#include "InputError.h"

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkStringArray.h>

namespace
{
const char* const kKind = OracleDomainMetadata::KindArray;
const char* const kName = "OracleMesh_Name";
const char* const kCut = "OracleMesh_Cut";
const char* const kMaterialId = "OracleMesh_MaterialId";
const char* const kMaterialName = "OracleMesh_MaterialName";
const char* const kParameters = "OracleMesh_Parameters";
const char* const kTransform = "OracleMesh_Transform";
const char* const kLabelArray = "OracleMesh_LabelArray";
const char* const kLabelAssociation = "OracleMesh_LabelAssociation";
const char* const kBackground = "OracleMesh_BackgroundLabel";
const char* const kInterpolation = "OracleMesh_LabelInterpolation";
const char* const kCriteria = "OracleMesh_Criteria";
const char* const kLabelValues = "OracleMesh_LabelValues";
const char* const kLabelNames = "OracleMesh_LabelNames";
const char* const kSeamWeld = "OracleMesh_SeamWeld";
const char* const kVersion = OracleDomainMetadata::VersionArray;

void putString(vtkFieldData* fd, const char* key, const std::string& v)
{
  vtkNew<vtkStringArray> a;
  a->SetName(key);
  a->InsertNextValue(v);
  fd->AddArray(a);
}
void putInts(vtkFieldData* fd, const char* key, const std::vector<int>& v)
{
  vtkNew<vtkIntArray> a;
  a->SetName(key);
  for (int x : v)
    a->InsertNextValue(x);
  fd->AddArray(a);
}
void putDoubles(vtkFieldData* fd, const char* key, const std::vector<double>& v)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(key);
  for (double x : v)
    a->InsertNextValue(x);
  fd->AddArray(a);
}
std::string getString(vtkFieldData* fd, const char* key)
{
  auto* a = vtkStringArray::SafeDownCast(fd->GetAbstractArray(key));
  return (a && a->GetNumberOfValues() > 0) ? a->GetValue(0) : std::string();
}
std::vector<double> getDoubles(vtkFieldData* fd, const char* key)
{
  std::vector<double> v;
  if (vtkDataArray* a = fd->GetArray(key))
  {
    for (vtkIdType i = 0; i < a->GetNumberOfTuples() * a->GetNumberOfComponents(); ++i)
      v.push_back(a->GetComponent(i / a->GetNumberOfComponents(), i % a->GetNumberOfComponents()));
  }
  return v;
}
std::vector<int> getInts(vtkFieldData* fd, const char* key)
{
  std::vector<int> v;
  for (double d : getDoubles(fd, key))
    v.push_back(static_cast<int>(d));
  return v;
}
}

void OracleDomainMetadata::WriteTo(vtkFieldData* fd) const
{
  putInts(fd, kVersion, { kFormatVersion });
  putString(fd, kKind, Kind);
  putString(fd, kName, Name);
  putInts(fd, kCut, { Cut ? 1 : 0 });
  putInts(fd, kMaterialId, { MaterialId });
  putString(fd, kMaterialName, MaterialName);
  putDoubles(fd, kParameters, Parameters);
  if (!Transform.empty())
    putDoubles(fd, kTransform, Transform);
  else
    fd->RemoveArray(kTransform);
  if (std::any_of(Criteria.begin(), Criteria.end(), [](double v) { return v >= 0; }))
    putDoubles(fd, kCriteria, { Criteria.begin(), Criteria.end() });
  else
    fd->RemoveArray(kCriteria);
  if (!SeamWeld.empty())
    putString(fd, kSeamWeld, SeamWeld);
  else
    fd->RemoveArray(kSeamWeld);
  if (Kind == "LabelMap")
  {
    putString(fd, kLabelArray, LabelArray);
    putString(fd, kLabelAssociation, CellLabels ? "Cell" : "Point");
    putInts(fd, kBackground, { BackgroundLabel });
    putString(fd, kInterpolation, LabelInterpolation);
    putInts(fd, kLabelValues, LabelValues);
    vtkNew<vtkStringArray> names;
    names->SetName(kLabelNames);
    for (const auto& n : LabelNames)
      names->InsertNextValue(n);
    fd->AddArray(names);
  }
}

bool OracleDomainMetadata::ReadFrom(vtkFieldData* fd, OracleDomainMetadata& out)
{
  if (!fd || !fd->GetAbstractArray(kKind))
    return false;
  out = OracleDomainMetadata();
  const std::vector<int> version = getInts(fd, kVersion);
  if (version.size() != 1 || version[0] > kFormatVersion)
    throw omesh::InputError("domain metadata has format version " +
      (version.empty() ? std::string("(none)") : std::to_string(version[0])) +
      "; this OracleMesh reads version " + std::to_string(kFormatVersion));
  out.Kind = getString(fd, kKind);
  out.Name = getString(fd, kName);
  const auto cut = getInts(fd, kCut);
  out.Cut = !cut.empty() && cut[0] != 0;
  const auto mat = getInts(fd, kMaterialId);
  if (!mat.empty())
    out.MaterialId = mat[0];
  out.MaterialName = getString(fd, kMaterialName);
  out.Parameters = getDoubles(fd, kParameters);
  out.Transform = getDoubles(fd, kTransform);
  if (!out.Transform.empty() && out.Transform.size() != 12)
    throw omesh::InputError("domain '" + out.Name + "': " + kTransform + " must hold 12 numbers");
  const auto criteria = getDoubles(fd, kCriteria);
  if (!criteria.empty() && criteria.size() != 6)
    throw omesh::InputError("domain '" + out.Name + "': " + kCriteria + " must hold 6 numbers");
  std::copy(criteria.begin(), criteria.end(), out.Criteria.begin());
  out.SeamWeld = getString(fd, kSeamWeld);
  if (out.Kind == "LabelMap")
  {
    out.LabelArray = getString(fd, kLabelArray);
    out.CellLabels = getString(fd, kLabelAssociation) == "Cell";
    const auto bg = getInts(fd, kBackground);
    if (!bg.empty())
      out.BackgroundLabel = bg[0];
    const std::string interpolation = getString(fd, kInterpolation);
    if (!interpolation.empty() && interpolation != "Nearest" && interpolation != "Trilinear" &&
      interpolation != "Smooth")
      throw omesh::InputError("domain '" + out.Name + "': " + kInterpolation + " is '" + interpolation +
        "'; expected Nearest, Trilinear or Smooth");
    out.LabelInterpolation = interpolation.empty() ? "Nearest" : interpolation;
    out.LabelValues = getInts(fd, kLabelValues);
    if (auto* names = vtkStringArray::SafeDownCast(fd->GetAbstractArray(kLabelNames)))
    {
      for (vtkIdType i = 0; i < names->GetNumberOfValues(); ++i)
        out.LabelNames.push_back(names->GetValue(i));
    }
    if (out.LabelNames.size() != out.LabelValues.size())
      throw omesh::InputError("domain '" + out.Name + "': label values and label names differ in count");
  }
  return true;
}
