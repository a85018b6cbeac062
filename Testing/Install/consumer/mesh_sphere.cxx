// SPDX-License-Identifier: GPL-3.0-or-later
// Meshes a sphere of radius R with the installed OracleMesh and checks the result: tetrahedra > 0
// and the volume within 5% of 4/3 pi R^3. Prints "tetrahedra N volume V exact E".
#include <vtkFeaturePreservingTetrahedralizer.h>
#include <vtkHierarchicalOracle.h>
#include <vtkSphereDomain.h>

#include <vtkCellType.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkTetra.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <iostream>

int main()
{
  const double R = 10.0;
  vtkNew<vtkSphereDomain> sphere;
  sphere->SetCenter(1, 2, 3);
  sphere->SetRadius(R);
  sphere->SetMaterialId(1);
  vtkNew<vtkHierarchicalOracle> oracle;
  oracle->AddInputConnection(sphere->GetOutputPort());
  vtkNew<vtkFeaturePreservingTetrahedralizer> mesher;
  mesher->SetInputConnection(oracle->GetOutputPort());
  mesher->SetFacetSize(2);
  mesher->SetFacetDistance(0.05);
  mesher->SetCellSize(2);
  mesher->SetSeed(1);
  mesher->Update();
  vtkUnstructuredGrid* mesh = mesher->GetOutput();

  double volume = 0.0;
  vtkIdType tets = 0;
  for (vtkIdType i = 0; i < mesh->GetNumberOfCells(); ++i)
  {
    if (mesh->GetCellType(i) != VTK_TETRA)
      continue;
    vtkIdType n;
    const vtkIdType* ids;
    mesh->GetCellPoints(i, n, ids);
    double p[4][3];
    for (int k = 0; k < 4; ++k)
      mesh->GetPoint(ids[k], p[k]);
    volume += std::abs(vtkTetra::ComputeVolume(p[0], p[1], p[2], p[3]));
    ++tets;
  }
  const double exact = 4.0 / 3.0 * M_PI * R * R * R;
  std::cout << "tetrahedra " << tets << " volume " << volume << " exact " << exact << std::endl;
  if (tets == 0 || std::abs(volume - exact) > 0.05 * exact)
  {
    std::cerr << "mesh_sphere: expected tetrahedra and a volume within 5% of " << exact << std::endl;
    return 1;
  }
  return 0;
}
