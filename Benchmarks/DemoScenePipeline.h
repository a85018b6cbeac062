// SPDX-License-Identifier: GPL-3.0-or-later
// The bundled demo scene (Data/demo/scene.json) as a VTK pipeline, shared by the benchmarks.
#pragma once

#include "vtkHierarchicalOracle.h"
#include "vtkImplicitDomain.h"
#include "vtkLabelMapDomain.h"
#include "vtkSurfaceDomain.h"

#include <vtkCylinder.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <string>

/// implant (3) > screw (4) > resection cut > tibia label map (1, 2), as in scene.json.
struct DemoScenePipeline
{
  vtkNew<vtkXMLPolyDataReader> implantReader;
  vtkNew<vtkSurfaceDomain> implant;
  vtkNew<vtkCylinder> screwShape;
  vtkNew<vtkImplicitDomain> screw;
  vtkNew<vtkPlane> plane;
  vtkNew<vtkImplicitDomain> resection;
  vtkNew<vtkXMLImageDataReader> imageReader;
  vtkNew<vtkLabelMapDomain> tibia;
  vtkNew<vtkHierarchicalOracle> oracle;

  explicit DemoScenePipeline(const std::string& dir)
  {
    implantReader->SetFileName((dir + "/implant.vtp").c_str());
    implant->SetInputConnection(implantReader->GetOutputPort());
    implant->SetMaterialId(3);
    screwShape->SetCenter(-15, -14, 66);
    screwShape->SetAxis(0.1, 0.05, 1);
    screwShape->SetRadius(2.5);
    screw->SetImplicitFunction(screwShape);
    screw->SetHeight(34);
    screw->SetCut(false);
    screw->SetMaterialId(4);
    plane->SetOrigin(0, 0, 80);
    plane->SetNormal(0, 0, -1);
    resection->SetImplicitFunction(plane);
    resection->SetCut(true);
    imageReader->SetFileName((dir + "/tibia_labels.vti").c_str());
    tibia->SetInputConnection(imageReader->GetOutputPort());
    for (vtkAlgorithm* d : std::initializer_list<vtkAlgorithm*>{ implant, screw, resection, tibia })
      oracle->AddInputConnection(d->GetOutputPort());
    oracle->Update();
  }
};
