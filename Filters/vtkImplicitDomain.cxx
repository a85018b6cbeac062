// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkImplicitDomain.h"

#include "Domain.h"
#include "InputError.h"
#include "OracleBuilder.h"

#include <vtkBox.h>
#include <vtkContourFilter.h>
#include <vtkCylinder.h>
#include <vtkImplicitBoolean.h>
#include <vtkImplicitFunction.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkLinearTransform.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPlane.h>
#include <vtkPolyData.h>
#include <vtkSampleFunction.h>
#include <vtkSphere.h>

#include <algorithm>
#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkImplicitDomain);
vtkCxxSetObjectMacro(vtkImplicitDomain, ImplicitFunction, vtkImplicitFunction);

namespace
{
/// The transform's linear part and offset (world to local: x -> M x + t); throws if not linear.
void linearPart(vtkAbstractTransform* t, double M[3][3], double off[3], const std::string& who)
{
  auto* linear = vtkLinearTransform::SafeDownCast(t);
  if (!linear)
    throw omesh::InputError(
      who + ": the implicit function's transform (" + std::string(t->GetClassName()) + ") is not linear");
  vtkMatrix4x4* m = linear->GetMatrix();
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      M[r][c] = m->GetElement(r, c);
    off[r] = m->GetElement(r, 3);
  }
}

/// A cylinder as one plain centre and unit axis in world coordinates, the same whichever way it
/// was given. ParaView's Cylinder (vtkPVCylinder) keeps the user's centre but the axis as a
/// rotation Transform about that centre (local axis y); the scene loader, Python and C++ give
/// vtkCylinder the axis itself. So: a rotation (orthonormal M) is folded into the axis (M^T a) and
/// the centre (the centre itself when the transform fixes it up to rounding, else its preimage);
/// then the unit axis is rounded to multiples of 2^-30 per component (at most 1e-9 rad of tilt).
/// The two descriptions of one cylinder differ by a few ulps before the rounding and agree bit for
/// bit after it, unless a component lies within those ulps of a rounding boundary (odds about
/// 1e-7 per component; axis-aligned axes are never near one). Returns false, leaving the transform
/// to the caller, when the transform is not a rotation (a scaled or sheared cylinder).
bool describeCylinder(vtkCylinder* cyl, double height, OracleDomainMetadata& md, const std::string& who)
{
  double c[3], a[3];
  cyl->GetCenter(c);
  cyl->GetAxis(a);
  if (vtkAbstractTransform* t = cyl->GetTransform())
  {
    double M[3][3], off[3];
    linearPart(t, M, off, who);
    double worst = 0.0; // |M M^T - I|
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
      {
        const double d = M[i][0] * M[j][0] + M[i][1] * M[j][1] + M[i][2] * M[j][2] - (i == j ? 1.0 : 0.0);
        worst = std::max(worst, std::abs(d));
      }
    if (!(worst <= 1e-12))
    {
      md.Parameters = { c[0], c[1], c[2], a[0], a[1], a[2], cyl->GetRadius(), height };
      return false;
    }
    double wa[3], wc[3], moved = 0.0, scale = 1.0; // world axis M^T a; centre: T(c) == c?
    for (int i = 0; i < 3; ++i)
    {
      wa[i] = M[0][i] * a[0] + M[1][i] * a[1] + M[2][i] * a[2];
      const double image = M[i][0] * c[0] + M[i][1] * c[1] + M[i][2] * c[2] + off[i];
      moved = std::max(moved, std::abs(image - c[i]));
      scale = std::max({ scale, std::abs(c[i]), std::abs(off[i]) });
    }
    if (moved <= 1e-12 * scale)
      std::copy(c, c + 3, wc); // a rotation about the centre (vtkPVCylinder's)
    else
      for (int i = 0; i < 3; ++i) // the preimage M^T (c - t)
        wc[i] = M[0][i] * (c[0] - off[0]) + M[1][i] * (c[1] - off[1]) + M[2][i] * (c[2] - off[2]);
    std::copy(wc, wc + 3, c);
    std::copy(wa, wa + 3, a);
  }
  const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (std::isfinite(len) && len > 0.0) // else the core names the bad axis
    for (double& v : a)
      v = std::ldexp(std::nearbyint(std::ldexp(v / len, 30)), -30);
  md.Parameters = { c[0], c[1], c[2], a[0], a[1], a[2], cyl->GetRadius(), height };
  return true;
}

/// The function's shape as domain metadata (kind, parameters, world-to-local transform).
void describeFunction(vtkImplicitFunction* f, double height, OracleDomainMetadata& md, const std::string& who)
{
  if (!f)
    throw omesh::InputError(who + ": no implicit function set");
  if (auto* plane = vtkPlane::SafeDownCast(f))
  {
    double o[3], n[3];
    plane->GetOrigin(o);
    plane->GetNormal(n);
    // ParaView's vtkPVPlane adds an offset along the normal: recover the true zero set.
    const double n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (n2 > 0)
    {
      const double v = plane->EvaluateFunction(o);
      for (int i = 0; i < 3; ++i)
        o[i] -= v * n[i] / n2;
    }
    md.Kind = "Plane";
    md.Parameters = { o[0], o[1], o[2], n[0], n[1], n[2] };
  }
  else if (auto* box = vtkBox::SafeDownCast(f))
  {
    double b[6];
    box->GetBounds(b);
    md.Kind = "Box";
    md.Parameters.assign(b, b + 6);
  }
  else if (auto* sphere = vtkSphere::SafeDownCast(f))
  {
    md.Kind = "Sphere";
    md.Parameters = { sphere->GetCenter()[0], sphere->GetCenter()[1], sphere->GetCenter()[2], sphere->GetRadius() };
  }
  else if (auto* cyl = vtkCylinder::SafeDownCast(f))
  {
    md.Kind = "Cylinder";
    if (describeCylinder(cyl, height, md, who))
      return; // the transform is folded into the centre and axis
  }
  else
    throw omesh::InputError(who + ": implicit function " + f->GetClassName() +
      " is not supported (use vtkPlane, vtkBox, vtkSphere or vtkCylinder)");
  if (vtkAbstractTransform* t = f->GetTransform())
  {
    double M[3][3], off[3];
    linearPart(t, M, off, who);
    for (int r = 0; r < 3; ++r)
    {
      md.Transform.insert(md.Transform.end(), M[r], M[r] + 3);
      md.Transform.push_back(off[r]);
    }
  }
}
}

vtkImplicitDomain::vtkImplicitDomain()
{
  this->SetNumberOfInputPorts(0);
  this->SetMaterialName("Implicit");
}

vtkImplicitDomain::~vtkImplicitDomain()
{
  this->SetImplicitFunction(nullptr);
}

vtkMTimeType vtkImplicitDomain::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->ImplicitFunction)
    t = std::max(t, this->ImplicitFunction->GetMTime()); // includes its transform
  return t;
}

namespace
{
/// Where the shape is drawn: the user's display bounds, else the shape's bounds (padded), else a
/// cube around the plane's origin or the cylinder's centre.
void displayRegion(const double* displayBounds, bool bounded, const omesh::BoundingBox& shapeBounds,
  const OracleDomainMetadata& md, double region[6])
{
  const double* db = displayBounds;
  if (db[0] < db[1] && db[2] < db[3] && db[4] < db[5])
    std::copy(db, db + 6, region);
  else if (bounded)
  {
    const omesh::Vec3 pad = 0.05 * shapeBounds.size();
    for (int i = 0; i < 3; ++i)
    {
      region[2 * i] = shapeBounds.min[i] - pad[i];
      region[2 * i + 1] = shapeBounds.max[i] + pad[i];
    }
  }
  else
  {
    const double* o = md.Parameters.data(); // plane origin or cylinder centre
    for (int i = 0; i < 3; ++i)
    {
      region[2 * i] = o[i] - 50.0;
      region[2 * i + 1] = o[i] + 50.0;
    }
  }
}

/// The function whose zero set is drawn; a capped cylinder is the infinite one intersected with
/// two planes.
vtkSmartPointer<vtkImplicitFunction> displayShape(vtkImplicitFunction* function, const OracleDomainMetadata& md, double height)
{
  vtkSmartPointer<vtkImplicitFunction> shape = function;
  if (md.Kind != "Cylinder")
    return shape;
  // The cylinder as described (reduced to a plain centre + axis when its transform was a rotation).
  const double* p = md.Parameters.data();
  vtkNew<vtkCylinder> cyl;
  cyl->SetCenter(p[0], p[1], p[2]);
  cyl->SetAxis(p[3], p[4], p[5]);
  cyl->SetRadius(p[6]);
  if (!md.Transform.empty())
    cyl->SetTransform(function->GetTransform());
  shape = cyl;
  if (!(height > 0))
    return shape;
  double axis[3] = { cyl->GetAxis()[0], cyl->GetAxis()[1], cyl->GetAxis()[2] };
  const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  vtkNew<vtkImplicitBoolean> capped;
  capped->SetOperationTypeToIntersection();
  capped->AddFunction(cyl);
  for (int side : { -1, 1 })
  {
    vtkNew<vtkPlane> cap;
    double n[3], o[3];
    for (int i = 0; i < 3; ++i)
    {
      n[i] = side * axis[i] / len;
      o[i] = cyl->GetCenter()[i] + 0.5 * height * n[i];
    }
    cap->SetNormal(n);
    cap->SetOrigin(o);
    cap->SetTransform(cyl->GetTransform());
    capped->AddFunction(cap);
  }
  return capped.GetPointer();
}
}

int vtkImplicitDomain::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  const std::string who = this->Describe();
  OracleDomainMetadata md;
  this->FillMetadata("", md); // the kind follows from the function
  omesh::BoundingBox shapeBounds;
  bool bounded = false;
  try
  {
    if (!(this->Height >= 0) || !std::isfinite(this->Height))
    {
      std::ostringstream o;
      o << who << ": Height " << this->Height << " must be >= 0 and finite (0 = an infinite cylinder)";
      throw omesh::InputError(o.str());
    }
    describeFunction(this->ImplicitFunction, this->Height, md, who);
    OracleDomainMetadata named = md;
    named.Name = who;
    auto domain = OracleBuilder::BuildImplicit(named);
    bounded = domain->bounded();
    if (bounded)
      shapeBounds = domain->bounds();
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  double region[6];
  displayRegion(this->DisplayBounds, bounded, shapeBounds, md, region);
  vtkNew<vtkSampleFunction> sample;
  sample->SetImplicitFunction(displayShape(this->ImplicitFunction, md, this->Height));
  sample->SetModelBounds(region);
  sample->SetSampleDimensions(this->DisplayResolution, this->DisplayResolution, this->DisplayResolution);
  sample->ComputeNormalsOff();
  vtkNew<vtkContourFilter> contour;
  contour->SetInputConnection(sample->GetOutputPort());
  contour->SetValue(0, 0.0);
  contour->ComputeScalarsOff();
  contour->Update();
  output->ShallowCopy(contour->GetOutput());
  md.WriteTo(output->GetFieldData());
  return 1;
}

void vtkImplicitDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ImplicitFunction: " << (this->ImplicitFunction ? this->ImplicitFunction->GetClassName() : "(none)") << "\n";
  os << indent << "Height: " << this->Height << "\n";
  os << indent << "DisplayResolution: " << this->DisplayResolution << "\n";
}
