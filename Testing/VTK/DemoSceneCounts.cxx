// SPDX-License-Identifier: GPL-3.0-or-later
// Builds the bundled demo scene as a plain VTK C++ pipeline (the same hierarchy as
// Data/demo/scene.json), samples the oracle and writes the per-material sample counts as JSON.
// The Python and pvpython tests build the scene their own way and must get the same counts.
//   usage: OracleMeshDemoCounts <Data/demo folder> <counts.json> [n]
#include "vtkHierarchicalOracle.h"
#include "vtkImplicitDomain.h"
#include "vtkLabelMapDomain.h"
#include "vtkOracleSampler.h"
#include "vtkSurfaceDomain.h"

#include <vtkCylinder.h>
#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <fstream>
#include <iostream>
#include <map>
#include <string>

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::cerr << "usage: " << argv[0] << " <demo folder> <counts.json> [n]\n";
    return 2;
  }
  const std::string dir = argv[1];
  const int n = argc > 3 ? std::stoi(argv[3]) : 64;

  vtkNew<vtkXMLPolyDataReader> implantReader;
  implantReader->SetFileName((dir + "/implant.vtp").c_str());
  vtkNew<vtkSurfaceDomain> implant;
  implant->SetInputConnection(implantReader->GetOutputPort());
  implant->SetMaterialId(3);
  implant->SetMaterialName("implant");

  vtkNew<vtkCylinder> screwShape;
  screwShape->SetCenter(-15.0, -14.0, 66.0);
  screwShape->SetAxis(0.1, 0.05, 1.0);
  screwShape->SetRadius(2.5);
  vtkNew<vtkImplicitDomain> screw;
  screw->SetImplicitFunction(screwShape);
  screw->SetHeight(34.0);
  screw->SetCut(false);
  screw->SetMaterialId(4);
  screw->SetMaterialName("screw");

  vtkNew<vtkPlane> resectionPlane;
  resectionPlane->SetOrigin(0.0, 0.0, 80.0);
  resectionPlane->SetNormal(0.0, 0.0, -1.0); // contains z >= 80: the bone removed
  vtkNew<vtkImplicitDomain> resection;
  resection->SetImplicitFunction(resectionPlane);
  resection->SetCut(true);
  resection->SetMaterialName("resection");

  vtkNew<vtkXMLImageDataReader> tibiaReader;
  tibiaReader->SetFileName((dir + "/tibia_labels.vti").c_str());
  vtkNew<vtkLabelMapDomain> tibia;
  tibia->SetInputConnection(tibiaReader->GetOutputPort());
  tibia->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "labels");
  tibia->SetLabelName(1, "cortical bone");
  tibia->SetLabelName(2, "cancellous bone");
  tibia->SetDomainName("tibia");

  vtkNew<vtkHierarchicalOracle> oracle; // priority = connection order
  oracle->AddInputConnection(implant->GetOutputPort());
  oracle->AddInputConnection(screw->GetOutputPort());
  oracle->AddInputConnection(resection->GetOutputPort());
  oracle->AddInputConnection(tibia->GetOutputPort());

  vtkNew<vtkOracleSampler> sampler;
  sampler->SetInputConnection(oracle->GetOutputPort());
  sampler->SetDimensions(n, n, n);
  sampler->Update();
  auto* material = vtkIntArray::SafeDownCast(sampler->GetOutput()->GetPointData()->GetArray("Material"));
  if (!material)
  {
    std::cerr << "sampling failed\n";
    return 1;
  }
  std::map<int, long> counts;
  for (vtkIdType i = 0; i < material->GetNumberOfTuples(); ++i)
    ++counts[material->GetValue(i)];
  std::ofstream out(argv[2]);
  out << "{";
  const char* sep = "";
  for (const auto& [m, c] : counts)
  {
    out << sep << "\"" << m << "\": " << c;
    sep = ", ";
    std::cout << "material " << m << ": " << c << " samples\n";
  }
  out << "}\n";
  return out.good() ? 0 : 1;
}
