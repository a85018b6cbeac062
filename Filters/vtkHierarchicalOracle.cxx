// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkHierarchicalOracle.h"

#include "InputError.h"
#include "OracleBuilder.h"

#include <vtkAlgorithm.h>
#include <vtkDataObject.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkSmartPointer.h>

vtkStandardNewMacro(vtkHierarchicalOracle);

vtkHierarchicalOracle::vtkHierarchicalOracle()
{
  this->SetNumberOfInputPorts(1);
}

int vtkHierarchicalOracle::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1); // so "no domains" gets our message
  return 1;
}

int vtkHierarchicalOracle::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiBlockDataSet* output = vtkMultiBlockDataSet::GetData(outputVector);
  const int n = inputVector[0]->GetNumberOfInformationObjects();
  try
  {
    if (n == 0)
      throw omesh::InputError("vtkHierarchicalOracle: no domains connected");
    output->SetNumberOfBlocks(n);
    for (int i = 0; i < n; ++i)
    {
      vtkDataObject* in = vtkDataObject::GetData(inputVector[0], i);
      const std::string where = "vtkHierarchicalOracle input " + std::to_string(i);
      vtkAlgorithm* producer = this->GetInputAlgorithm(0, i);
      if (in && !in->GetFieldData()->GetAbstractArray(OracleDomainMetadata::KindArray) && producer &&
        (producer->IsA("vtkSurfaceDomain") || producer->IsA("vtkLabelMapDomain") ||
          producer->IsA("vtkSphereDomain") || producer->IsA("vtkImplicitDomain")))
        throw omesh::InputError(where + ": its " + producer->GetClassName() +
          " produced no domain; that filter's own error says why");
      // an empty output without the domain description: the filter before failed (in ParaView a
      // pass-through filter sits between, so the producer above is not the domain filter)
      auto* set = vtkDataSet::SafeDownCast(in);
      if (in && !in->GetFieldData()->GetAbstractArray(OracleDomainMetadata::KindArray) && set && set->GetNumberOfPoints() == 0 &&
        set->GetNumberOfCells() == 0)
        throw omesh::InputError(where + " is empty: the filter before it failed or produced nothing (its own "
                                        "error, reported first, says why)");
      const OracleDomainMetadata md = OracleBuilder::ReadDomain(in, where);
      vtkSmartPointer<vtkDataObject> block = vtk::TakeSmartPointer(in->NewInstance());
      block->ShallowCopy(in);
      output->SetBlock(i, block);
      output->GetMetaData(static_cast<unsigned int>(i))
        ->Set(vtkCompositeDataSet::NAME(), md.Name.empty() ? ("Domain " + std::to_string(i)).c_str() : md.Name.c_str());
    }
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    return 0;
  }
  vtkNew<vtkIntArray> version;
  version->SetName(OracleDomainMetadata::VersionArray);
  version->InsertNextValue(OracleDomainMetadata::kFormatVersion);
  output->GetFieldData()->AddArray(version);
  return 1;
}

void vtkHierarchicalOracle::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Domains connected: " << this->GetNumberOfInputConnections(0) << "\n";
}
