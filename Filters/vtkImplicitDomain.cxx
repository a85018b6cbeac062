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

#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkImplicitDomain);
vtkCxxSetObjectMacro(vtkImplicitDomain, ImplicitFunction, vtkImplicitFunction);

namespace
{
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
    const double* c = cyl->GetCenter();
    const double* a = cyl->GetAxis();
    md.Kind = "Cylinder";
    md.Parameters = { c[0], c[1], c[2], a[0], a[1], a[2], cyl->GetRadius(), height };
  }
  else
    throw omesh::InputError(who + ": implicit function " + f->GetClassName() +
      " is not supported (use vtkPlane, vtkBox, vtkSphere or vtkCylinder)");
  if (vtkAbstractTransform* t = f->GetTransform())
  {
    auto* linear = vtkLinearTransform::SafeDownCast(t);
    if (!linear)
      throw omesh::InputError(who + ": the implicit function's transform (" +
        std::string(t->GetClassName()) + ") is not linear");
    vtkMatrix4x4* m = linear->GetMatrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        md.Transform.push_back(m->GetElement(r, c));
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

  // Display region: the user's, else the shape's bounds (padded), else a cube around the plane.
  double region[6];
  const double* db = this->DisplayBounds;
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

  // Draw the zero set; a capped cylinder is the infinite one intersected with two planes.
  vtkSmartPointer<vtkImplicitFunction> shape = this->ImplicitFunction;
  if (md.Kind == "Cylinder" && this->Height > 0)
  {
    auto* cyl = vtkCylinder::SafeDownCast(this->ImplicitFunction);
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
        o[i] = cyl->GetCenter()[i] + 0.5 * this->Height * n[i];
      }
      cap->SetNormal(n);
      cap->SetOrigin(o);
      cap->SetTransform(cyl->GetTransform());
      capped->AddFunction(cap);
    }
    shape = capped;
  }
  vtkNew<vtkSampleFunction> sample;
  sample->SetImplicitFunction(shape);
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
