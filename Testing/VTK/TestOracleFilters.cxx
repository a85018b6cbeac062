// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK adapters: C++ pipelines, volumes through the sampler, metadata round trips, bad input.
#include "vtkFeaturePreservingTetrahedralizer.h"
#include "vtkHierarchicalOracle.h"
#include "vtkImplicitDomain.h"
#include "vtkLabelMapDomain.h"
#include "vtkMeshValidityCheck.h"
#include "vtkOracleSampler.h"
#include "vtkSphereDomain.h"
#include "vtkSurfaceDomain.h"

#include <vtkAlgorithmOutput.h>
#include <vtkBox.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkCubeSource.h>
#include <vtkCylinder.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkMath.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadric.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkTransform.h>
#include <vtkTriangleFilter.h>
#include <vtkTrivialProducer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLMultiBlockDataWriter.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

namespace
{
/// Collects the error messages an algorithm (and its executive) reports during an update.
class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (data)
      Messages += static_cast<const char*>(data);
  }
  std::string Messages;
};

/// Updates `alg`; returns the error text ("" when it succeeded without errors).
std::string UpdateAndCatch(vtkAlgorithm* alg, std::initializer_list<vtkAlgorithm*> upstream = {})
{
  vtkNew<ErrorCatcher> catcher;
  std::vector<vtkObject*> observed{ alg, alg->GetExecutive() };
  for (vtkAlgorithm* a : upstream)
  {
    observed.push_back(a);
    observed.push_back(a->GetExecutive());
  }
  for (vtkObject* o : observed)
    o->AddObserver(vtkCommand::ErrorEvent, catcher);
  const int ok = alg->GetExecutive()->Update();
  for (vtkObject* o : observed)
    o->RemoveObservers(vtkCommand::ErrorEvent);
  if (!ok && catcher->Messages.empty())
    return "update failed without a message";
  return catcher->Messages;
}

std::map<int, double> SampledVolumes(vtkAlgorithmOutput* oracle, int n, const double* bounds = nullptr)
{
  vtkNew<vtkOracleSampler> sampler;
  sampler->SetInputConnection(oracle);
  sampler->SetDimensions(n, n, n);
  if (bounds)
    sampler->SetBounds(const_cast<double*>(bounds));
  EXPECT_EQ(UpdateAndCatch(sampler), "");
  std::map<int, double> v;
  vtkFieldData* fd = sampler->GetOutput()->GetFieldData();
  auto* ids = vtkIntArray::SafeDownCast(fd->GetArray("MaterialIds"));
  auto* vols = vtkDoubleArray::SafeDownCast(fd->GetArray("MaterialVolume"));
  for (vtkIdType i = 0; ids && i < ids->GetNumberOfTuples(); ++i)
    v[ids->GetValue(i)] = vols->GetValue(i);
  return v;
}

/// 3D label image: 1 in a block of 10 x 8 x 6 voxels, background 0.
vtkSmartPointer<vtkImageData> BlockImage(bool cellData, int type = VTK_UNSIGNED_CHAR)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(20, 16, 12);
  image->SetSpacing(0.5, 0.5, 0.5);
  image->SetOrigin(-5, -4, -3);
  const int nx = cellData ? 19 : 20, ny = cellData ? 15 : 16, nz = cellData ? 11 : 12;
  vtkSmartPointer<vtkDataArray> labels = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(type));
  labels->SetName("labels");
  labels->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        labels->SetTuple1(i + nx * (j + ny * k), (i >= 5 && i < 15 && j >= 4 && j < 12 && k >= 3 && k < 9) ? 1 : 0);
  if (cellData)
    image->GetCellData()->SetScalars(labels);
  else
    image->GetPointData()->SetScalars(labels);
  return image;
}
}

TEST(OracleFilters, SphereBoxAndLabelMapVolumesThroughTheSampler)
{
  vtkNew<vtkSphereDomain> sphere;
  sphere->SetCenter(1, 2, 3);
  sphere->SetRadius(2);
  sphere->SetMaterialId(5);
  vtkNew<vtkBox> boxFunction;
  boxFunction->SetBounds(-4, 4, -4, 4, -4, 4);
  vtkNew<vtkImplicitDomain> box;
  box->SetImplicitFunction(boxFunction);
  box->CutOff();
  box->SetMaterialId(6);
  vtkNew<vtkHierarchicalOracle> oracle;
  oracle->AddInputConnection(sphere->GetOutputPort());
  oracle->AddInputConnection(box->GetOutputPort());
  const auto v = SampledVolumes(oracle->GetOutputPort(), 160);
  const double ball = 4.0 / 3.0 * M_PI * 8.0;
  EXPECT_NEAR(v.at(5), ball, 0.02 * ball);
  // sphere sticks out of the box (z up to 5): the box keeps 512 minus the ball's part inside it
  const double capOutside = M_PI * 1 * 1 * (3 * 2 - 1) / 3.0; // cap of height 1 above z = 4
  EXPECT_NEAR(v.at(6), 512.0 - (ball - capOutside), 0.02 * 512.0);

  for (bool cells : { false, true })
  {
    vtkNew<vtkLabelMapDomain> labels;
    labels->SetInputData(BlockImage(cells));
    vtkNew<vtkHierarchicalOracle> lo;
    lo->AddInputConnection(labels->GetOutputPort());
    const auto lv = SampledVolumes(lo->GetOutputPort(), 120);
    EXPECT_NEAR(lv.at(1), 10 * 8 * 6 * 0.125, 0.03 * 60.0) << (cells ? "cell" : "point") << " labels";
  }
}

TEST(OracleFilters, CutPlaneRemovesLowerPrioritiesOnly)
{
  vtkNew<vtkSphereDomain> top;
  top->SetRadius(1);
  top->SetMaterialId(1);
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(0, 0, 0);
  plane->SetNormal(0, 0, -1); // contains z >= 0
  vtkNew<vtkImplicitDomain> cut;
  cut->SetImplicitFunction(plane);
  cut->SetCut(true);
  vtkNew<vtkSphereDomain> bottom;
  bottom->SetRadius(2);
  bottom->SetMaterialId(2);
  vtkNew<vtkHierarchicalOracle> oracle;
  oracle->AddInputConnection(top->GetOutputPort());
  oracle->AddInputConnection(cut->GetOutputPort());
  oracle->AddInputConnection(bottom->GetOutputPort());
  const auto v = SampledVolumes(oracle->GetOutputPort(), 160);
  const double small = 4.0 / 3.0 * M_PI, big = 4.0 / 3.0 * M_PI * 8;
  EXPECT_NEAR(v.at(1), small, 0.02 * small);
  EXPECT_NEAR(v.at(2), big / 2 - small / 2, 0.02 * big);
}

TEST(OracleFilters, TransformedImplicitFunctionsAreHonoured)
{
  // A box rotated by 45 degrees about z through ParaView-style transforms: volume unchanged,
  // bounds grow by sqrt(2).
  vtkNew<vtkBox> f;
  f->SetBounds(-1, 1, -1, 1, -1, 1);
  vtkNew<vtkTransform> t;
  t->RotateZ(45);
  f->SetTransform(t);
  vtkNew<vtkImplicitDomain> box;
  box->SetImplicitFunction(f);
  box->SetCut(false);
  box->SetMaterialId(2);
  const auto v = SampledVolumes(box->GetOutputPort(), 140);
  EXPECT_NEAR(v.at(2), 8.0, 0.03 * 8.0);
  vtkNew<vtkCylinder> c;
  c->SetCenter(0, 0, 0);
  c->SetAxis(1, 0, 0);
  c->SetRadius(1);
  vtkNew<vtkImplicitDomain> screw;
  screw->SetImplicitFunction(c);
  screw->SetHeight(4);
  screw->SetCut(false);
  screw->SetMaterialId(4);
  screw->Update();
  const double* b = screw->GetOutput()->GetBounds();
  EXPECT_NEAR(b[0], -2, 0.2);
  EXPECT_NEAR(b[1], 2, 0.2);
  const auto cv = SampledVolumes(screw->GetOutputPort(), 140);
  EXPECT_NEAR(cv.at(4), M_PI * 4, 0.03 * M_PI * 4);
}

namespace
{
/// The domain description a vtkImplicitDomain writes: (parameters, transform) from its field data.
std::pair<std::vector<double>, std::vector<double>> CylinderDescription(vtkImplicitFunction* f, double height)
{
  vtkNew<vtkImplicitDomain> d;
  d->SetImplicitFunction(f);
  d->SetHeight(height);
  d->SetMaterialId(4);
  EXPECT_EQ(UpdateAndCatch(d), "");
  std::pair<std::vector<double>, std::vector<double>> out;
  vtkFieldData* fd = d->GetOutput()->GetFieldData();
  for (auto [name, v] : { std::make_pair("OracleMesh_Parameters", &out.first),
         std::make_pair("OracleMesh_Transform", &out.second) })
    if (vtkDataArray* a = fd->GetArray(name))
      for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
        v->push_back(a->GetComponent(i / a->GetNumberOfComponents(), i % a->GetNumberOfComponents()));
  return out;
}
}

TEST(OracleFilters, CylinderWithARotationIsOnePlainCentreAndAxis)
{
  // ParaView's way: local axis y and a rotation about the centre taking the axis to y (world to
  // local); the scene's way: the axis itself. One description, bit for bit, without a transform.
  const double centre[3] = { -15, -14, 66 }, axis[3] = { 0.1, 0.05, 1 };
  vtkNew<vtkCylinder> plain;
  plain->SetCenter(centre);
  plain->SetAxis(axis[0], axis[1], axis[2]);
  plain->SetRadius(2.5);
  const auto expected = CylinderDescription(plain, 34);
  ASSERT_EQ(expected.first.size(), 8u);
  EXPECT_TRUE(expected.second.empty());
  const double len = std::sqrt(0.1 * 0.1 + 0.05 * 0.05 + 1.0);
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_EQ(expected.first[i], centre[i]);
    EXPECT_NEAR(expected.first[3 + i], axis[i] / len, 1e-9);
  }

  // y -> axis: rotate about y x axis by the angle between them, about the centre.
  const double y[3] = { 0, 1, 0 };
  double u[3] = { axis[0] / len, axis[1] / len, axis[2] / len }, r[3];
  vtkMath::Cross(y, u, r);
  const double angle = vtkMath::DegreesFromRadians(std::acos(vtkMath::Dot(y, u)));
  vtkNew<vtkTransform> localToWorld;
  localToWorld->Translate(centre);
  localToWorld->RotateWXYZ(angle, r);
  localToWorld->Translate(-centre[0], -centre[1], -centre[2]);
  vtkNew<vtkTransform> worldToLocal;
  worldToLocal->SetMatrix(localToWorld->GetMatrix());
  worldToLocal->Inverse();
  vtkNew<vtkCylinder> rotated;
  rotated->SetCenter(centre);
  rotated->SetAxis(0, 1, 0);
  rotated->SetRadius(2.5);
  rotated->SetTransform(worldToLocal);
  EXPECT_EQ(CylinderDescription(rotated, 34), expected);

  // A rotation about another point moves the centre: its preimage, still without a transform.
  vtkNew<vtkTransform> shifted;
  shifted->Translate(5, 0, 0); // world to local: x + 5
  vtkNew<vtkCylinder> moved;
  moved->SetCenter(centre);
  moved->SetAxis(axis[0], axis[1], axis[2]);
  moved->SetRadius(2.5);
  moved->SetTransform(shifted);
  const auto m = CylinderDescription(moved, 34);
  EXPECT_TRUE(m.second.empty());
  EXPECT_NEAR(m.first[0], centre[0] - 5, 1e-12);
  for (int i = 1; i < 6; ++i)
    EXPECT_EQ(m.first[i], expected.first[i]);

  // A scaled cylinder (elliptic) is not a plain cylinder: its transform stays.
  vtkNew<vtkTransform> scaled;
  scaled->Scale(2, 1, 1);
  vtkNew<vtkCylinder> elliptic;
  elliptic->SetRadius(1);
  elliptic->SetTransform(scaled);
  EXPECT_EQ(CylinderDescription(elliptic, 4).second.size(), 12u);
}

TEST(OracleFilters, SurfaceDomainMatchesTheEnclosedVolume)
{
  vtkNew<vtkSphereSource> source;
  source->SetRadius(3);
  source->SetThetaResolution(48);
  source->SetPhiResolution(48);
  vtkNew<vtkSurfaceDomain> surface;
  surface->SetInputConnection(source->GetOutputPort());
  surface->SetMaterialId(3);
  ASSERT_EQ(UpdateAndCatch(surface), "");
  // the sampled volume of the polyhedron, not of the ideal sphere: compare to the polyhedron's
  vtkPolyData* pd = surface->GetOutput();
  double volume = 0;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    double p[3][3];
    vtkIdType n;
    const vtkIdType* ids;
    pd->GetCellPoints(c, n, ids);
    for (int k = 0; k < 3; ++k)
      pd->GetPoint(ids[k], p[k]);
    volume += (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) / 6.0;
  }
  const auto v = SampledVolumes(surface->GetOutputPort(), 140);
  EXPECT_NEAR(v.at(3), std::abs(volume), 0.02 * std::abs(volume));
}

TEST(OracleFilters, AJitteredSoupIsWeldedKeepingItsDataAndSayingSo)
{
  // a cube's 12 triangles, each with its own corners moved by up to 1e-4 (100 times the merge
  // tolerance): the automatic test's seam weld leaves 8 points, point and cell data kept
  vtkNew<vtkCubeSource> cube;
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(cube->GetOutputPort());
  tri->Update();
  vtkPolyData* triangles = tri->GetOutput();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkFloatArray> corner, face;
  corner->SetName("Corner");
  face->SetName("Face");
  unsigned seed = 1;
  auto jitter = [&seed] {
    seed = seed * 1103515245u + 12345u;
    return 1e-4 * ((seed >> 8) % 2001 / 1000.0 - 1.0);
  };
  for (vtkIdType c = 0; c < triangles->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    triangles->GetCellPoints(c, n, ids);
    vtkIdType copy[3];
    for (int k = 0; k < 3; ++k)
    {
      double p[3];
      triangles->GetPoint(ids[k], p);
      copy[k] = points->InsertNextPoint(p[0] + jitter(), p[1] + jitter(), p[2] + jitter());
      corner->InsertNextValue(static_cast<float>(4 * (p[0] > 0) + 2 * (p[1] > 0) + (p[2] > 0)));
    }
    cells->InsertNextCell(3, copy);
    face->InsertNextValue(static_cast<float>(c));
  }
  vtkNew<vtkPolyData> soup;
  soup->SetPoints(points);
  soup->SetPolys(cells);
  soup->GetPointData()->AddArray(corner);
  soup->GetCellData()->AddArray(face);
  vtkNew<vtkSurfaceDomain> domain;
  domain->SetInputData(soup);
  ASSERT_EQ(UpdateAndCatch(domain), "");
  vtkPolyData* out = domain->GetOutput();
  EXPECT_EQ(out->GetNumberOfPoints(), 8);
  ASSERT_EQ(out->GetNumberOfPolys(), 12);
  auto* faces = out->GetCellData()->GetArray("Face");
  auto* corners = out->GetPointData()->GetArray("Corner");
  ASSERT_TRUE(faces && corners);
  for (vtkIdType c = 0; c < 12; ++c)
    EXPECT_EQ(faces->GetTuple1(c), c);
  for (vtkIdType v = 0; v < 8; ++v) // each welded point carries a copy's data: its own corner's
  {
    double p[3];
    out->GetPoint(v, p);
    EXPECT_EQ(corners->GetTuple1(v), 4 * (p[0] > 0) + 2 * (p[1] > 0) + (p[2] > 0));
  }
  auto* weld = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("OracleMesh_SeamWeld"));
  ASSERT_TRUE(weld);
  EXPECT_NE(weld->GetValue(0).find("welded 36 unwelded seam edge(s) (of 36 border edges): 28 point(s) merged"), std::string::npos)
    << weld->GetValue(0);
  // an explicit inside test takes the surface as given: the soup stays open (with a warning)
  domain->SetInsideTestToWindingNumber();
  domain->SetAllowSelfIntersections(true);
  ASSERT_EQ(UpdateAndCatch(domain), "");
  EXPECT_EQ(domain->GetOutput()->GetNumberOfPoints(), 36);
  EXPECT_EQ(domain->GetOutput()->GetFieldData()->GetAbstractArray("OracleMesh_SeamWeld"), nullptr);
}

TEST(OracleFilters, CombinedOutputRoundTripsThroughAFile)
{
  vtkNew<vtkSphereDomain> sphere;
  sphere->SetRadius(1.5);
  sphere->SetMaterialId(7);
  vtkNew<vtkLabelMapDomain> labels;
  labels->SetInputData(BlockImage(false));
  labels->SetLabelName(1, "bone");
  vtkNew<vtkHierarchicalOracle> oracle;
  oracle->AddInputConnection(sphere->GetOutputPort());
  oracle->AddInputConnection(labels->GetOutputPort());
  ASSERT_EQ(UpdateAndCatch(oracle), "");
  EXPECT_EQ(oracle->GetOutput()->GetNumberOfBlocks(), 2u);

  const std::string file = std::string(ORACLEMESH_TEST_OUTPUT_DIR) + "/roundtrip.vtm";
  vtkNew<vtkXMLMultiBlockDataWriter> writer;
  writer->SetInputConnection(oracle->GetOutputPort());
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);
  vtkNew<vtkXMLMultiBlockDataReader> reader;
  reader->SetFileName(file.c_str());

  const double bounds[6] = { -5, 5, -4, 4, -3, 3 };
  vtkNew<vtkOracleSampler> a, b;
  a->SetInputConnection(oracle->GetOutputPort());
  b->SetInputConnection(reader->GetOutputPort());
  for (vtkOracleSampler* s : { a.Get(), b.Get() })
  {
    s->SetDimensions(50, 40, 30);
    s->SetBounds(const_cast<double*>(bounds));
    ASSERT_EQ(UpdateAndCatch(s), "");
  }
  auto* ma = vtkIntArray::SafeDownCast(a->GetOutput()->GetPointData()->GetArray("Material"));
  auto* mb = vtkIntArray::SafeDownCast(b->GetOutput()->GetPointData()->GetArray("Material"));
  ASSERT_TRUE(ma && mb);
  int differences = 0, seven = 0, one = 0;
  for (vtkIdType i = 0; i < ma->GetNumberOfTuples(); ++i)
  {
    differences += ma->GetValue(i) != mb->GetValue(i);
    seven += ma->GetValue(i) == 7;
    one += ma->GetValue(i) == 1;
  }
  EXPECT_EQ(differences, 0);
  EXPECT_GT(seven, 0);
  EXPECT_GT(one, 0);
}

TEST(OracleFilters, QuadraticElementsAreTheLinearMeshWithCurvedBoundaryEdges)
{
  vtkNew<vtkSphereDomain> sphere;
  sphere->SetRadius(1.0);
  vtkNew<vtkFeaturePreservingTetrahedralizer> linear, quadratic;
  for (vtkFeaturePreservingTetrahedralizer* m : { linear.Get(), quadratic.Get() })
  {
    m->SetInputConnection(sphere->GetOutputPort());
    m->SetFeatureStrategyToNone();
    m->SetCellSize(0.4);
    m->SetFacetSize(0.4);
    m->SetFacetDistance(0.03);
  }
  EXPECT_EQ(linear->GetElementOrder(), 1); // the default
  quadratic->SetElementOrder(2);
  ASSERT_EQ(UpdateAndCatch(linear, { sphere }), "");
  ASSERT_EQ(UpdateAndCatch(quadratic, { sphere }), "");
  vtkUnstructuredGrid* a = linear->GetOutput();
  vtkUnstructuredGrid* b = quadratic->GetOutput();
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  ASSERT_GT(b->GetNumberOfPoints(), a->GetNumberOfPoints());
  EXPECT_EQ(b->GetPointData()->GetArray("Dimension")->GetNumberOfTuples(), b->GetNumberOfPoints());
  int onSphere = 0;
  for (vtkIdType c = 0; c < b->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(b->GetCellType(c), VTK_QUADRATIC_TETRA);
    vtkIdType na, nb;
    const vtkIdType *pa, *pb;
    a->GetCellPoints(c, na, pa);
    b->GetCellPoints(c, nb, pb);
    ASSERT_EQ(nb, 10);
    for (int k = 0; k < 4; ++k) // same corners, in the same (positive) order
      ASSERT_EQ(pa[k], pb[k]) << "cell " << c;
    double x[3];
    for (int k = 4; k < 10; ++k)
    {
      b->GetPoint(pb[k], x);
      onSphere += std::abs(vtkMath::Norm(x) - 1.0) < 1e-9;
    }
  }
  EXPECT_GT(onSphere, 100);
  for (const char* name : { "Material", "MinDihedralAngle", "RadiusEdgeRatio" })
    EXPECT_EQ(a->GetCellData()->GetArray(name)->GetRange()[0], b->GetCellData()->GetArray(name)->GetRange()[0]) << name;
  // the validity check takes the quadratic tetrahedra (on their corners)
  vtkNew<vtkMeshValidityCheck> check;
  check->SetInputData(b);
  ASSERT_EQ(UpdateAndCatch(check), "");
  EXPECT_EQ(check->GetNumberOfDefects(), 0);
  EXPECT_EQ(check->GetNonTetrahedra(), 0);

  quadratic->SetElementOrder(3);
  EXPECT_NE(UpdateAndCatch(quadratic, { sphere }).find("ElementOrder 3 is out of range"), std::string::npos);
}

TEST(OracleFilters, BadInputGivesClearErrors)
{
  auto expectError = [](vtkAlgorithm* alg, const std::string& fragment, std::initializer_list<vtkAlgorithm*> up = {}) {
    const std::string msg = UpdateAndCatch(alg, up);
    EXPECT_NE(msg.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << msg;
  };
  // a surface with a hole: the sphere without its first triangles
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  vtkNew<vtkPolyData> open;
  open->DeepCopy(sphere->GetOutput());
  open->BuildCells();
  open->DeleteCell(0);
  open->RemoveDeletedCells();
  vtkNew<vtkSurfaceDomain> openDomain;
  openDomain->SetInputData(open);
  openDomain->SetMaterialName("implant");
  openDomain->SetInsideTestToClosed(); // the default, automatic, takes it
  expectError(openDomain, "vtkSurfaceDomain 'implant': surface is not closed: 3 open edge(s)");

  vtkNew<vtkCubeSource> cube; // quads, each face with its own 4 corners: triangulated and welded
  vtkNew<vtkSurfaceDomain> quads;
  quads->SetInputConnection(cube->GetOutputPort());
  EXPECT_EQ(UpdateAndCatch(quads, { cube }), "");
  EXPECT_EQ(quads->GetOutput()->GetNumberOfPolys(), 12);
  EXPECT_EQ(quads->GetOutput()->GetNumberOfPoints(), 8);

  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(cube->GetOutputPort());
  tri->Update();
  vtkNew<vtkPolyData> nan;
  nan->DeepCopy(tri->GetOutput());
  nan->GetPoints()->SetPoint(3, std::nan(""), 0, 0);
  vtkNew<vtkSurfaceDomain> nanDomain;
  nanDomain->SetInputData(nan);
  expectError(nanDomain, "surface point 3 (nan, 0, 0) has a NaN");

  vtkNew<vtkImageData> empty;
  vtkNew<vtkLabelMapDomain> emptyLabels;
  emptyLabels->SetInputData(empty);
  expectError(emptyLabels, "label");

  auto floats = BlockImage(false, VTK_FLOAT);
  floats->GetPointData()->GetScalars()->SetTuple1(17, 0.5);
  vtkNew<vtkLabelMapDomain> floatLabels;
  floatLabels->SetInputData(floats);
  expectError(floatLabels, "label map is not integer: value 0.5 at point 17");
  // float labels holding integers are fine
  vtkNew<vtkLabelMapDomain> integralFloats;
  integralFloats->SetInputData(BlockImage(false, VTK_FLOAT));
  EXPECT_EQ(UpdateAndCatch(integralFloats), "");

  vtkNew<vtkSphereDomain> zero;
  zero->SetRadius(0);
  expectError(zero, "sphere radius must be positive");
  vtkNew<vtkSphereDomain> nanCentre;
  nanCentre->SetCenter(0, std::nan(""), 0);
  expectError(nanCentre, "NaN");

  vtkNew<vtkHierarchicalOracle> none;
  expectError(none, "no domains connected");

  vtkNew<vtkHierarchicalOracle> wrongType;
  wrongType->AddInputConnection(sphere->GetOutputPort()); // plain polydata, not a domain
  expectError(wrongType, "input 0 (vtkPolyData) is not an OracleMesh domain");

  vtkNew<vtkQuadric> quadric;
  vtkNew<vtkImplicitDomain> unsupported;
  unsupported->SetImplicitFunction(quadric);
  expectError(unsupported, "vtkQuadric is not supported");

  vtkNew<vtkImplicitDomain> noFunction;
  expectError(noFunction, "no implicit function set");

  // only a cut plane: nothing to sample
  vtkNew<vtkPlane> plane;
  vtkNew<vtkImplicitDomain> cut;
  cut->SetImplicitFunction(plane);
  cut->SetCut(true);
  vtkNew<vtkHierarchicalOracle> onlyCut;
  onlyCut->AddInputConnection(cut->GetOutputPort());
  vtkNew<vtkOracleSampler> sampler;
  sampler->SetInputConnection(onlyCut->GetOutputPort());
  expectError(sampler, "every domain is a cut");
}

// The per-feature edge size on port 1 (cell array EdgeSize): bad values and one line given two
// values are the core's errors, named by the tetrahedralizer.
TEST(OracleFilters, FeatureLineEdgeSizesAreChecked)
{
  vtkNew<vtkSphereDomain> ball;
  ball->SetRadius(1.0);
  ball->SetMaterialId(1);
  vtkNew<vtkHierarchicalOracle> oracle;
  oracle->AddInputConnection(ball->GetOutputPort());
  // two polylines across the ball along x: the second one a copy of the first one's second half
  auto lines = [](std::initializer_list<double> sizes, int components = 1) {
    auto pd = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    for (double x : { -0.5, 0.0, 0.5 })
      points->InsertNextPoint(x, 0, 0);
    vtkNew<vtkCellArray> cells;
    const vtkIdType first[3] = { 0, 1, 2 }, second[2] = { 1, 2 };
    cells->InsertNextCell(3, first);
    cells->InsertNextCell(2, second);
    pd->SetPoints(points);
    pd->SetLines(cells);
    vtkNew<vtkDoubleArray> edgeSize;
    edgeSize->SetName("EdgeSize");
    edgeSize->SetNumberOfComponents(components);
    for (double s : sizes)
      for (int c = 0; c < components; ++c)
        edgeSize->InsertNextValue(s);
    pd->GetCellData()->AddArray(edgeSize);
    return pd;
  };
  auto run = [&](vtkPolyData* features) {
    vtkNew<vtkFeaturePreservingTetrahedralizer> mesher;
    mesher->SetInputConnection(0, oracle->GetOutputPort());
    mesher->SetInputData(1, features);
    mesher->SetCellSize(0.5);
    mesher->SetFacetSize(0.5);
    mesher->SetFacetDistance(0.05);
    return UpdateAndCatch(mesher, { oracle, ball });
  };
  auto expectIn = [](const std::string& msg, const std::string& fragment) {
    EXPECT_NE(msg.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << msg;
  };
  expectIn(run(lines({ 0.1, -0.5 })), "(0, 0, 0) - (0.5, 0, 0) has EdgeSize -0.5");
  expectIn(run(lines({ 0.1, std::nan("") })), "has EdgeSize nan");
  expectIn(run(lines({ 0.1, 0.2 })), "segment (0, 0, 0) - (0.5, 0, 0) gets EdgeSize 0.1 and 0.2");
  expectIn(run(lines({ 0.1, 0.1 }, 2)), "cell array EdgeSize has 2 components");
  EXPECT_EQ(run(lines({ 0.1, -1 })), ""); // -1: no value of its own; the copy adds nothing
  EXPECT_EQ(run(lines({ 0.1, 0.1 })), "");
}
