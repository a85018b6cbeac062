// The C++ example of the README (a test checks the README shows this file verbatim).
#include <vtkFeaturePreservingTetrahedralizer.h>
#include <vtkHierarchicalOracle.h>
#include <vtkImplicitDomain.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkSphereDomain.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

int main()
{
  vtkNew<vtkSphereDomain> bone;
  bone->SetRadius(20);
  bone->SetMaterialId(1);
  vtkNew<vtkPlane> plane; // a cut: removes z >= 10 from the domains below it
  plane->SetOrigin(0, 0, 10);
  plane->SetNormal(0, 0, -1);
  vtkNew<vtkImplicitDomain> cut;
  cut->SetImplicitFunction(plane);
  cut->SetCut(true); // a plane is unbounded: only a cut may be
  vtkNew<vtkHierarchicalOracle> oracle; // first input = highest priority
  oracle->AddInputConnection(cut->GetOutputPort());
  oracle->AddInputConnection(bone->GetOutputPort());
  vtkNew<vtkFeaturePreservingTetrahedralizer> mesher;
  mesher->SetInputConnection(oracle->GetOutputPort());
  mesher->SetCellSize(4);
  mesher->SetFacetDistance(0.5);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputConnection(mesher->GetOutputPort());
  writer->SetFileName("bone.vtu");
  return writer->Write() == 1 && mesher->GetOutput()->GetNumberOfCells() > 0 ? 0 : 1;
}
