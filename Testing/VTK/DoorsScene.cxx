// SPDX-License-Identifier: GPL-3.0-or-later
// The door-test scene (Testing/Data/doors/scene.json) as a C++ pipeline of the VTK filters, meshed
// and written as .vtu: Testing/Python/test_doors.py checks that the command line, oraclemesh.mesh,
// the plugin's proxies in pvpython and this program give the same mesh. Keys the scene leaves out
// are left out here too (the cylinder's Cut, the label array, the facet angle, the strategy, the
// optimisers, the sliver angles, the vertex budget): the defaults must agree.
//   usage: OracleMeshDoorsScene <Data/demo folder> <out.vtu>
#include "vtkFeaturePreservingTetrahedralizer.h"
#include "vtkHierarchicalOracle.h"
#include "vtkImplicitDomain.h"
#include "vtkLabelMapDomain.h"
#include "vtkSurfaceDomain.h"

#include <vtkCylinder.h>
#include <vtkFeatureEdges.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::cerr << "usage: " << argv[0] << " <demo folder> <out.vtu>\n";
    return 2;
  }
  const std::string dir = argv[1];

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
  vtkNew<vtkImplicitDomain> screw; // Cut left at its default
  screw->SetImplicitFunction(screwShape);
  screw->SetHeight(34.0);
  screw->SetMaterialId(4);
  screw->SetMaterialName("screw");
  screw->SetCellSize(3.0);

  vtkNew<vtkPlane> resectionPlane;
  resectionPlane->SetOrigin(0.0, 0.0, 80.0);
  resectionPlane->SetNormal(0.0, 0.0, -1.0);
  vtkNew<vtkImplicitDomain> resection;
  resection->SetImplicitFunction(resectionPlane);
  resection->SetCut(true);
  resection->SetMaterialName("resection");

  vtkNew<vtkXMLImageDataReader> tibiaReader;
  tibiaReader->SetFileName((dir + "/tibia_labels.vti").c_str());
  vtkNew<vtkLabelMapDomain> tibia; // label array left to the filter
  tibia->SetInputConnection(tibiaReader->GetOutputPort());
  tibia->SetLabelName(1, "cortical bone");
  tibia->SetLabelName(2, "cancellous bone");
  tibia->SetDomainName("tibia");

  vtkNew<vtkHierarchicalOracle> oracle; // priority = connection order
  oracle->AddInputConnection(implant->GetOutputPort());
  oracle->AddInputConnection(screw->GetOutputPort());
  oracle->AddInputConnection(resection->GetOutputPort());
  oracle->AddInputConnection(tibia->GetOutputPort());

  vtkNew<vtkFeatureEdges> edges;
  edges->SetInputConnection(implantReader->GetOutputPort());
  edges->BoundaryEdgesOff();
  edges->NonManifoldEdgesOff();
  edges->ManifoldEdgesOff();
  edges->SetFeatureAngle(60.0);

  vtkNew<vtkFeaturePreservingTetrahedralizer> mesher;
  mesher->SetInputConnection(0, oracle->GetOutputPort());
  mesher->SetInputConnection(1, edges->GetOutputPort());
  mesher->ResampleFeatureLinesOn(); // as scene files do for sharp edges found on a surface
  mesher->SetCellRadiusEdgeRatio(2.5);
  mesher->SetCellSize(8.0);
  mesher->SetFacetSize(6.0);
  mesher->SetFacetDistance(2.0);
  mesher->SetEdgeSize(3.0);
  mesher->SetMaterialCriteria(3, -1, -1, 1.0, -1, -1, -1);
  mesher->SetSeed(3);
  mesher->Update();
  vtkUnstructuredGrid* grid = mesher->GetOutput();
  if (grid->GetNumberOfCells() == 0)
  {
    std::cerr << "no mesh\n";
    return 1;
  }
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputData(grid);
  writer->SetFileName(argv[2]);
  writer->SetDataModeToBinary();
  std::cout << grid->GetNumberOfPoints() << " points, " << grid->GetNumberOfCells() << " tetrahedra\n";
  return writer->Write() ? 0 : 1;
}
