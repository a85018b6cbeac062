// SPDX-License-Identifier: GPL-3.0-or-later
#include "OracleBuilder.h"

#include <algorithm>

#include "BoxDomain.h"
#include "FeatureSegments.h"
#include "FieldDataKeys.h"
#include "CylinderDomain.h"
#include "HalfSpaceDomain.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelMapDomain.h"
#include "MemoryCheck.h"
#include "SphereDomain.h"
#include "SurfaceDomain.h"
#include "TriangleSurface.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>


using omesh::InputError;

namespace
{
std::string describe(const OracleDomainMetadata& md, const std::string& where)
{
  return md.Name.empty() ? where : where + " '" + md.Name + "'";
}

bool absurd(double v)
{
  return !std::isfinite(v) || std::abs(v) > OracleBuilder::LargestCoordinate;
}

std::string coordinates(const double x[3])
{
  std::ostringstream o;
  o << "(" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  return o.str();
}

void checkPoint(const double x[3], vtkIdType id, const std::string& who, const std::string& what)
{
  if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    throw InputError(who + ": " + (what.empty() ? "" : what + " ") + "point " + std::to_string(id) + " " +
      coordinates(x) + " has a NaN or infinite coordinate");
  if (absurd(x[0]) || absurd(x[1]) || absurd(x[2]))
    throw InputError(who + ": " + (what.empty() ? "" : what + " ") + "point " + std::to_string(id) + " " +
      coordinates(x) + " has a coordinate beyond 1e15 in magnitude (absurd; check the units)");
}

void expectParameters(const OracleDomainMetadata& md, size_t n, const std::string& who)
{
  if (md.Parameters.size() != n)
    throw InputError(who + ": a " + md.Kind + " domain needs " + std::to_string(n) +
      " parameters, it has " + std::to_string(md.Parameters.size()));
}
}

OracleDomainMetadata OracleBuilder::ReadDomain(vtkDataObject* data, const std::string& where)
{
  if (!data)
    throw InputError(where + ": no data");
  OracleDomainMetadata md;
  if (!OracleDomainMetadata::ReadFrom(data->GetFieldData(), md))
    throw InputError(where + " (" + data->GetClassName() +
      ") is not an OracleMesh domain: connect it through vtkSurfaceDomain, vtkLabelMapDomain, "
      "vtkSphereDomain or vtkImplicitDomain first");
  const std::string who = describe(md, where);
  if (md.Kind == "Surface" && !vtkPolyData::SafeDownCast(data))
    throw InputError(who + ": a Surface domain must be vtkPolyData, got " + data->GetClassName());
  if (md.Kind == "LabelMap" && !vtkImageData::SafeDownCast(data))
    throw InputError(who + ": a LabelMap domain must be vtkImageData, got " + data->GetClassName());
  if (md.Kind != "Surface" && md.Kind != "LabelMap" && md.Kind != "Sphere" && md.Kind != "Plane" &&
    md.Kind != "Box" && md.Kind != "Cylinder")
    throw InputError(who + ": unknown domain kind '" + md.Kind + "'");
  return md;
}

std::shared_ptr<omesh::Domain> OracleBuilder::BuildImplicit(const OracleDomainMetadata& md)
{
  const std::string who = md.Name.empty() ? md.Kind : md.Name;
  const auto& p = md.Parameters;
  for (size_t i = 0; i < p.size(); ++i)
    if (!std::isnan(p[i]) && absurd(p[i])) // NaN: the shape names it
    {
      std::ostringstream o;
      o << who << ": " << md.Kind << " parameter " << i << " is " << p[i]
        << " (parameters must be at most 1e15 in magnitude: absurd; check the units)";
      throw InputError(o.str());
    }
  for (double v : md.Transform)
    if (!std::isfinite(v))
      throw InputError(who + ": the shape's transform has a NaN or infinite entry");
  std::shared_ptr<omesh::ImplicitShapeDomain> d;
  if (md.Kind == "Sphere")
  {
    expectParameters(md, 4, who);
    d = std::make_shared<omesh::SphereDomain>(omesh::Vec3{ p[0], p[1], p[2] }, p[3], md.MaterialId, who);
  }
  else if (md.Kind == "Plane")
  {
    expectParameters(md, 6, who);
    d = std::make_shared<omesh::HalfSpaceDomain>(
      omesh::Vec3{ p[0], p[1], p[2] }, omesh::Vec3{ p[3], p[4], p[5] }, md.MaterialId, who);
  }
  else if (md.Kind == "Box")
  {
    expectParameters(md, 6, who);
    d = std::make_shared<omesh::BoxDomain>(
      omesh::Vec3{ p[0], p[2], p[4] }, omesh::Vec3{ p[1], p[3], p[5] }, md.MaterialId, who);
  }
  else if (md.Kind == "Cylinder")
  {
    expectParameters(md, 8, who);
    const double height = p[7] == 0.0 ? std::numeric_limits<double>::infinity() : p[7];
    d = std::make_shared<omesh::CylinderDomain>(omesh::Vec3{ p[0], p[1], p[2] },
      omesh::Vec3{ p[3], p[4], p[5] }, p[6], height, md.MaterialId, who);
  }
  else
    throw InputError(who + ": '" + md.Kind + "' is not an analytic domain kind");
  if (md.Transform.size() == 12)
  {
    std::array<double, 12> m;
    std::copy(md.Transform.begin(), md.Transform.end(), m.begin());
    try
    {
      d->setWorldToLocal(omesh::AffineMap(m));
    }
    catch (const InputError& e)
    {
      throw InputError(who + ": " + e.what());
    }
  }
  d->setCut(md.Cut);
  return d;
}

omesh::TriangleSurface OracleBuilder::ToTriangleSurface(vtkPolyData* pd, const std::string& who)
{
  omesh::TriangleSurface s;
  if (!pd || pd->GetNumberOfPoints() == 0)
    throw InputError(who + ": surface is empty (no points)");
  CheckCoordinates(pd->GetPoints(), who, "surface");
  if (pd->GetNumberOfStrips() > 0)
    throw InputError(who + ": surface has " + std::to_string(pd->GetNumberOfStrips()) +
      " triangle strips; only triangles are accepted (apply vtkTriangleFilter first)");
  s.points.resize(pd->GetNumberOfPoints());
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pd->GetPoint(i, x);
    s.points[i] = { x[0], x[1], x[2] };
  }
  vtkCellArray* polys = pd->GetPolys();
  s.triangles.reserve(polys->GetNumberOfCells());
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  vtkIdType index = 0;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++index)
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    if (n != 3)
      throw InputError(who + ": polygon " + std::to_string(index) + " has " + std::to_string(n) +
        " points; only triangles are accepted (apply vtkTriangleFilter first)");
    s.triangles.push_back({ static_cast<int>(ids[0]), static_cast<int>(ids[1]), static_cast<int>(ids[2]) });
  }
  if (s.triangles.empty())
    throw InputError(who + ": surface has no triangles (it has " + std::to_string(pd->GetNumberOfLines()) +
      " lines and " + std::to_string(pd->GetNumberOfVerts()) + " vertices)");
  return s;
}

omesh::FeatureSegments OracleBuilder::ToFeatureSegments(vtkPolyData* lines, std::vector<int>* owners)
{
  if (owners)
    owners->clear();
  omesh::FeatureSegments f;
  if (!lines)
    return f;
  const std::string who = "feature lines (input port 1)";
  if (lines->GetNumberOfPolys() > 0 || lines->GetNumberOfStrips() > 0 || lines->GetNumberOfVerts() > 0)
    throw InputError(who + ": " + std::to_string(lines->GetNumberOfPolys()) + " polygon(s), " +
      std::to_string(lines->GetNumberOfStrips()) + " strip(s) and " + std::to_string(lines->GetNumberOfVerts()) +
      " vertex cell(s) besides " + std::to_string(lines->GetNumberOfLines()) +
      " line(s); feature lines must be line cells only (lines or polylines, e.g. vtkFeatureEdges' output)");
  std::unordered_map<vtkIdType, int> index;
  auto vertex = [&](vtkIdType id) {
    auto [it, inserted] = index.emplace(id, static_cast<int>(f.points.size()));
    if (inserted)
    {
      double x[3];
      lines->GetPoint(id, x);
      checkPoint(x, id, who, "");
      f.points.push_back({ x[0], x[1], x[2] });
    }
    return it->second;
  };
  // The per-feature edge size: one value per line cell, -1 = unset (the VTK spelling of unset);
  // other values go to the core as they are, whose checks name a negative or NaN one.
  vtkDataArray* sizes = lines->GetCellData()->GetArray("EdgeSize");
  if (sizes && sizes->GetNumberOfComponents() != 1)
    throw InputError(who + ": cell array EdgeSize has " + std::to_string(sizes->GetNumberOfComponents()) +
      " components (one edge size per line is needed)");
  vtkDataArray* ownerArray = owners ? lines->GetCellData()->GetArray(omesh::keys::EDGES_OF_DOMAIN) : nullptr;
  if (ownerArray && ownerArray->GetNumberOfComponents() != 1)
    throw InputError(who + ": cell array " + omesh::keys::EDGES_OF_DOMAIN + " has " +
      std::to_string(ownerArray->GetNumberOfComponents()) + " components (one input index per line is needed)");
  // every point index checked before anything reads a point: a cell may name one past the end
  const vtkIdType pointCount = lines->GetNumberOfPoints();
  auto it = vtk::TakeSmartPointer(lines->GetLines()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k < n; ++k)
      if (ids[k] < 0 || ids[k] >= pointCount)
        throw InputError(who + ": line " + std::to_string(it->GetCurrentCellId()) + " names point " +
          std::to_string(ids[k]) + ", but the lines have " + std::to_string(pointCount) +
          " points (indices 0 to " + std::to_string(pointCount - 1) + "): a broken file or filter output");
  }
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    const double size = sizes ? sizes->GetComponent(it->GetCurrentCellId(), 0) : -1.0;
    for (vtkIdType k = 0; k + 1 < n; ++k)
    {
      f.segments.push_back({ vertex(ids[k]), vertex(ids[k + 1]) });
      if (sizes)
        f.edgeSizes.push_back(size == -1.0 ? std::nullopt : std::optional<double>(size));
      if (owners)
        owners->push_back(ownerArray ? static_cast<int>(ownerArray->GetComponent(it->GetCurrentCellId(), 0)) : -1);
    }
  }
  return f;
}

namespace
{
/// Throws for a label map whose direction matrix, spacing or corners are NaN, infinite or absurd.
void checkLabelMapGeometry(vtkImageData* image, const int ext[6], const std::string& who)
{
  double spacing[3], corner[2][3];
  image->GetSpacing(spacing);
  image->TransformIndexToPhysicalPoint(ext[0], ext[2], ext[4], corner[0]);
  image->TransformIndexToPhysicalPoint(ext[1], ext[3], ext[5], corner[1]);
  const double* dm = image->GetDirectionMatrix()->GetData();
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(dm[i]))
      throw InputError(who + ": the label map's direction matrix has a NaN or infinite entry");
  for (int i = 0; i < 3; ++i)
    if (absurd(spacing[i]) || !(spacing[i] > 0))
      throw InputError(who + ": label map spacing " + coordinates(spacing) +
        " must be positive, finite and at most 1e15");
  for (const double* c : corner)
    if (absurd(c[0]) || absurd(c[1]) || absurd(c[2]))
      throw InputError(who + ": label map corner " + coordinates(c) +
        " (from its origin and spacing) has a NaN, infinite or absurd coordinate (beyond 1e15)");
}

/// The labels as int; throws for a value that is not an integer or does not fit 32 bits.
std::vector<int> integerLabels(vtkDataArray* array, const char* assoc, const std::string& who)
{
  const vtkIdType n = array->GetNumberOfTuples();
  const bool integral = array->GetDataType() != VTK_FLOAT && array->GetDataType() != VTK_DOUBLE;
  std::vector<int> labels(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double v = array->GetTuple1(i);
    if (!integral && (v != std::floor(v) || !std::isfinite(v)))
    {
      std::ostringstream msg;
      msg << who << ": label map is not integer: value " << v << " at " << assoc << " " << i
          << " of array '" << (array->GetName() ? array->GetName() : "") << "' ("
          << array->GetDataTypeAsString() << ")";
      throw InputError(msg.str());
    }
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      throw InputError(who + ": label " + std::to_string(v) + " does not fit a 32-bit integer");
    labels[i] = static_cast<int>(v);
  }
  return labels;
}
}

std::shared_ptr<omesh::LabelMapDomain> OracleBuilder::ToLabelMap(
  vtkImageData* image, const OracleDomainMetadata& md, const std::string& who, const Progress& progress)
{
  if (!image || image->GetNumberOfPoints() == 0)
    throw InputError(who + ": label map is empty (no voxels)");
  vtkDataSetAttributes* attributes = md.CellLabels
    ? static_cast<vtkDataSetAttributes*>(image->GetCellData())
    : static_cast<vtkDataSetAttributes*>(image->GetPointData());
  vtkDataArray* array = md.LabelArray.empty() ? attributes->GetScalars() : attributes->GetArray(md.LabelArray.c_str());
  const char* assoc = md.CellLabels ? "cell" : "point";
  if (!array)
    throw InputError(who + ": label map has no " + std::string(assoc) + " array '" + md.LabelArray +
      "' (or no active " + assoc + " scalars)");
  if (array->GetNumberOfComponents() != 1)
    throw InputError(who + ": label array '" + std::string(array->GetName() ? array->GetName() : "") +
      "' has " + std::to_string(array->GetNumberOfComponents()) + " components; labels need 1");
  int ext[6];
  image->GetExtent(ext);
  std::array<int, 3> dims{ ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  if (md.CellLabels)
  {
    for (int& d : dims)
      d -= 1;
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
      throw InputError(who + ": cell labels need a 3D image; this one has " + std::to_string(dims[0]) +
        " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + " cells");
  }
  const vtkIdType n = array->GetNumberOfTuples();
  if (n == 0)
    throw InputError(who + ": label map is empty (no voxels)");
  checkLabelMapGeometry(image, ext, who);
  // labels as int while converting (4 bytes) and the compact index the domain keeps (2 bytes)
  omesh::checkMemory(who, "a label map of " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
      std::to_string(dims[2]) + " voxels",
    static_cast<double>(n), 6.0);
  const std::vector<int> labels = integerLabels(array, assoc, who);
  double origin[3], spacing[3];
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  const double* dm = image->GetDirectionMatrix()->GetData();
  std::array<double, 9> direction;
  std::copy(dm, dm + 9, direction.begin());
  // The first point is index (ext[0], ext[2], ext[4]), not necessarily the origin.
  double first[3];
  image->TransformIndexToPhysicalPoint(ext[0], ext[2], ext[4], first);
  const omesh::Vec3 o{ first[0], first[1], first[2] }, s{ spacing[0], spacing[1], spacing[2] };
  if (!(s.x > 0 && s.y > 0 && s.z > 0) || !omesh::isFinite(o))
    throw InputError(who + ": label map spacing must be positive and origin finite");
  const omesh::AffineMap worldToVoxel = md.CellLabels
    ? omesh::LabelMapDomain::cellCenteredWorldToVoxel(o, s, direction)
    : omesh::LabelMapDomain::pointCenteredWorldToVoxel(o, s, direction);
  omesh::LabelSmoothingOptions smoothing;
  smoothing.progress = progress;
  auto lm = std::make_shared<omesh::LabelMapDomain>(dims, labels, worldToVoxel, md.BackgroundLabel, who,
    md.LabelInterpolation == "Smooth"      ? omesh::LabelInterpolation::Smooth
      : md.LabelInterpolation == "Trilinear" ? omesh::LabelInterpolation::Trilinear
                                             : omesh::LabelInterpolation::Nearest,
    smoothing);
  lm->setCut(md.Cut);
  if (lm->materials().empty())
    throw InputError(who + ": label map holds only the background label " + std::to_string(md.BackgroundLabel));
  return lm;
}

std::shared_ptr<omesh::Domain> OracleBuilder::BuildDomain(
  vtkDataObject* data, const std::string& where, const Progress& progress)
{
  const OracleDomainMetadata md = ReadDomain(data, where);
  const std::string who = describe(md, where);
  if (md.Kind == "Surface")
  {
    // Parameters: allow self-intersections (0/1), inside test (0 closed, 1 winding number, 2
    // automatic); absent in files written before they existed (then automatic)
    omesh::SurfaceOptions options;
    if (!md.Parameters.empty())
    {
      expectParameters(md, 2, who);
      options.allowSelfIntersections = md.Parameters[0] != 0;
      const double test = md.Parameters[1];
      if (test != 0 && test != 1 && test != 2)
        throw InputError(who + ": surface inside test " + std::to_string(test) +
          " is not 0 (closed), 1 (winding number) or 2 (automatic)");
      options.insideTest = test == 0 ? omesh::InsideTest::Closed
        : test == 1                  ? omesh::InsideTest::WindingNumber
                                     : omesh::InsideTest::Automatic;
    }
    options.weldedBefore = md.SeamWeld;
    auto d = std::make_shared<omesh::SurfaceDomain>(
      ToTriangleSurface(vtkPolyData::SafeDownCast(data), who), md.MaterialId, who, options);
    d->setCut(md.Cut);
    return d;
  }
  if (md.Kind == "LabelMap")
    return ToLabelMap(vtkImageData::SafeDownCast(data), md, who, progress);
  auto d = BuildImplicit(md);
  d->setName(who);
  return d;
}

namespace
{
/// The domains' datasets in BuildOracle's order: block i is domain i.
std::vector<vtkDataObject*> domainBlocks(vtkDataObject* data)
{
  std::vector<vtkDataObject*> blocks;
  if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(data))
    for (unsigned int i = 0; i < mb->GetNumberOfBlocks(); ++i)
      blocks.push_back(mb->GetBlock(i));
  else
    blocks.push_back(data);
  return blocks;
}
}

omesh::CriteriaLevel OracleBuilder::DomainCriteria(
  vtkDataObject* data, const omesh::HierarchicalOracle& oracle)
{
  const std::vector<vtkDataObject*> blocks = domainBlocks(data);
  omesh::CriteriaLevel out;
  for (size_t i = 0; i < blocks.size() && i < oracle.domains().size(); ++i)
  {
    const omesh::Domain& domain = *oracle.domains()[i];
    if (domain.isCut())
      continue;
    const OracleDomainMetadata md = ReadDomain(blocks[i], "domain " + std::to_string(i));
    const omesh::MeshCriteria c = omesh::MeshCriteria::fromVtk(md.Criteria);
    const std::string source = "domain '" + md.Name + "'";
    c.check("criteria of " + source);
    for (int m : domain.materials())
      out.add(m, c, source);
  }
  return out;
}

std::vector<std::string> OracleBuilder::UnknownMaterialWarnings(
  vtkDataObject* data, const omesh::HierarchicalOracle& oracle, const std::vector<int>& criteriaMaterials)
{
  auto listed = [](const std::vector<int>& values) {
    std::string text;
    for (size_t i = 0; i < values.size() && i < 20; ++i)
      text += (i ? ", " : "") + std::to_string(values[i]);
    return values.size() > 20 ? text + ", ..." : text.empty() ? std::string("none") : text;
  };
  std::vector<std::string> warnings;
  const std::vector<vtkDataObject*> blocks = domainBlocks(data);
  for (size_t i = 0; i < blocks.size() && i < oracle.domains().size(); ++i)
  {
    const omesh::Domain& domain = *oracle.domains()[i];
    if (std::string(domain.kind()) != "LabelMap")
      continue;
    const OracleDomainMetadata md = ReadDomain(blocks[i], "domain " + std::to_string(i));
    const std::vector<int> labels = domain.materials();
    for (size_t k = 0; k < md.LabelValues.size(); ++k)
      if (!std::binary_search(labels.begin(), labels.end(), md.LabelValues[k]))
        warnings.push_back("label map " + domain.name() + ": a name is given to label " +
          std::to_string(md.LabelValues[k]) + " ('" + md.LabelNames[k] + "'), which its image does not have" +
          (md.LabelValues[k] == md.BackgroundLabel ? " (it is the background)" : "") + " (its labels: " +
          listed(labels) + ")");
  }
  const std::vector<int> materials = oracle.materials();
  for (int m : criteriaMaterials)
    if (!std::binary_search(materials.begin(), materials.end(), m))
      warnings.push_back("criteria are given for material " + std::to_string(m) +
        ", which no domain has (the domains' materials: " + listed(materials) + ")");
  return warnings;
}

void OracleBuilder::CheckCoordinates(vtkPoints* points, const std::string& who, const std::string& what)
{
  if (!points)
    return;
  double x[3];
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    points->GetPoint(i, x);
    checkPoint(x, i, who, what);
  }
}

std::shared_ptr<omesh::HierarchicalOracle> OracleBuilder::BuildOracle(vtkDataObject* data, const Progress& progress)
{
  auto oracle = std::make_shared<omesh::HierarchicalOracle>();
  if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(data))
  {
    for (unsigned int i = 0; i < mb->GetNumberOfBlocks(); ++i)
    {
      const std::string where = "domain " + std::to_string(i);
      vtkDataObject* block = mb->GetBlock(i);
      if (!block)
        throw InputError(where + ": block is empty");
      oracle->add(BuildDomain(block, where, progress));
    }
  }
  else if (data)
  {
    oracle->add(BuildDomain(data, "input", progress));
  }
  if (oracle->empty())
  {
    // vtkHierarchicalOracle stamps a format version on what it makes: an empty output without it
    // is a failed update upstream (ParaView runs each filter's update on its own)
    auto* mb = vtkMultiBlockDataSet::SafeDownCast(data);
    if (mb && !mb->GetFieldData()->GetAbstractArray(OracleDomainMetadata::VersionArray))
      throw InputError("the oracle is empty: vtkHierarchicalOracle or a filter before it failed (its error, "
                       "reported first, says why; without one, no domain is connected)");
    throw InputError("the oracle has no domains: connect at least one domain to vtkHierarchicalOracle");
  }
  return oracle;
}

