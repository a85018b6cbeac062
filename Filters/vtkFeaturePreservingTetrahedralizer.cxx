// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkFeaturePreservingTetrahedralizer.h"

#include "FeatureSelection.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelSmoothing.h"
#include "MeshingPipeline.h"
#include "OracleBuilder.h"
#include "OracleMesher.h"
#include "TetMeshOutput.h"
#include "WorkerThreads.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <sstream>

vtkStandardNewMacro(vtkFeaturePreservingTetrahedralizer);

namespace
{
/// Throws when a property lies outside [low, high] (or is NaN), naming it.
void checkRange(const char* property, double value, double low, double high, const char* meaning = "")
{
  if (value >= low && value <= high)
    return;
  std::ostringstream o;
  o << "vtkFeaturePreservingTetrahedralizer: " << property << " " << value << " is out of range (" << low << " to "
    << high << meaning << ")";
  throw omesh::InputError(o.str());
}
}

vtkFeaturePreservingTetrahedralizer::vtkFeaturePreservingTetrahedralizer()
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(3);
  // Every default from the core's, the one source of them.
  const omesh::MesherOptions defaults;
  this->FeatureStrategy = defaults.strategy == omesh::FeatureStrategy::Conforming ? CONFORMING
    : defaults.strategy == omesh::FeatureStrategy::None                          ? NONE
                                                                                 : PROTECTING_BALLS;
  this->Features = static_cast<int>(omesh::kDefaultFeatureSource); // the enums share their order
  this->CreaseAngle = omesh::kDefaultCreaseAngle;
  const omesh::MeshCriteria::Values c = defaults.criteria.globalValues();
  this->FacetAngle = c.facetAngle;
  this->FacetSize = c.facetSize;
  this->FacetDistance = c.facetDistance;
  this->CellSize = c.cellSize;
  this->CellRadiusEdgeRatio = c.cellRadiusEdgeRatio;
  this->EdgeSize = c.edgeSize;
  this->ResampleFeatureLines = defaults.resampleFeatureLines;
  this->SliverAngle = defaults.sliverAngle;
  this->InterfaceSliverAngle = defaults.interfaceSliverAngle;
  this->PickingSliverAngle = defaults.pickingSliverAngle;
  this->Perturb = defaults.perturb;
  this->Exude = defaults.exude;
  this->ImproveAngles = defaults.improveAngles;
  this->ImprovementMinAngle = defaults.improvementMinAngle;
  this->ImprovementMaxAngle = defaults.improvementMaxAngle;
  this->PerturbationFailuresPerBound = defaults.perturbationFailuresPerBound;
  this->ExudationSliverBound = defaults.exudationSliverBound;
  this->PerturbationStepsPerVertex = defaults.perturbationStepsPerVertex;
  this->ExudationStepsPerCell = defaults.exudationStepsPerCell;
  this->OptimisationTimeLimit = defaults.optimisationTimeLimit;
  this->ElementOrder = defaults.elementOrder;
  this->Seed = static_cast<int>(defaults.seed);
  this->MaximumNumberOfVertices = static_cast<vtkIdType>(defaults.maximumNumberOfVertices);
  this->Threads = defaults.threads;
  this->TimeLimit = defaults.timeLimit;
}

vtkFeaturePreservingTetrahedralizer::~vtkFeaturePreservingTetrahedralizer() = default;

int vtkFeaturePreservingTetrahedralizer::FillInputPortInformation(int, vtkInformation* info)
{
  // Any data object on every port, all optional to the pipeline: RequestData checks the types and
  // the oracle's presence itself, so that a wrong input gets an error naming the port.
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkFeaturePreservingTetrahedralizer::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkUnstructuredGrid" : "vtkPolyData");
  return 1;
}

void vtkFeaturePreservingTetrahedralizer::SetMaterialCriteria(int materialId, double facetAngle,
  double facetSize, double facetDistance, double cellSize, double cellRadiusEdgeRatio, double edgeSize)
{
  this->MaterialCriteria[materialId] = { facetAngle, facetSize, facetDistance, cellSize, cellRadiusEdgeRatio, edgeSize };
  this->Modified();
}

void vtkFeaturePreservingTetrahedralizer::RemoveMaterialCriteria(int materialId)
{
  if (this->MaterialCriteria.erase(materialId))
    this->Modified();
}

void vtkFeaturePreservingTetrahedralizer::ClearMaterialCriteria()
{
  if (!this->MaterialCriteria.empty())
  {
    this->MaterialCriteria.clear();
    this->Modified();
  }
}

void vtkFeaturePreservingTetrahedralizer::AddMaterialCriteria(double materialId, double facetAngle,
  double facetSize, double facetDistance, double cellSize, double cellRadiusEdgeRatio, double edgeSize)
{
  const int row = this->MaterialCriteriaRows++;
  const bool integral = std::isfinite(materialId) && materialId >= 0 && materialId <= VTK_INT_MAX &&
    materialId == std::floor(materialId);
  if (this->MaterialCriteriaError.empty())
  {
    std::ostringstream message;
    if (!integral)
      message << "material criteria row " << row + 1 << ": the material id must be an integer >= 0, got "
              << materialId;
    else if (this->MaterialCriteria.count(static_cast<int>(materialId)))
      message << "material criteria row " << row + 1 << ": material " << static_cast<int>(materialId)
              << " is listed twice";
    this->MaterialCriteriaError = message.str();
  }
  if (integral)
    this->SetMaterialCriteria(static_cast<int>(materialId), facetAngle, facetSize, facetDistance, cellSize,
      cellRadiusEdgeRatio, edgeSize);
  else
    this->Modified();
}

void vtkFeaturePreservingTetrahedralizer::RemoveAllMaterialCriteria()
{
  if (this->MaterialCriteriaRows > 0 || !this->MaterialCriteriaError.empty())
    this->Modified();
  this->MaterialCriteriaRows = 0;
  this->MaterialCriteriaError.clear();
  this->ClearMaterialCriteria();
}

/// One run of RequestData: the core's inputs and options, then its result.
struct vtkFeaturePreservingTetrahedralizer::PipelineCall
{
  std::shared_ptr<omesh::HierarchicalOracle> oracle;
  omesh::PipelineInput input;
  omesh::PipelineOptions options;
  omesh::PipelineResult result;
  TetShapeCellArrays shapes; ///< the cell arrays the mesher's measuring pass writes
  double oracleSeconds = 0.0; ///< the oracle's making from the inputs (a label map's smoothing)
};

int vtkFeaturePreservingTetrahedralizer::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* grid = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!this->MaterialCriteriaError.empty())
  {
    vtkErrorMacro(<< this->MaterialCriteriaError);
    return 0;
  }
  PipelineCall run;
  try
  {
    this->CheckProperties(); // before any heavy work
    // every parallel loop of the call (a label map's smoothing, the output's passes) on Threads
    omesh::runOnThreads(this->Threads, [&] {
      this->GatherInputs(inputVector, run);
      run.result = omesh::runMeshingPipeline(*run.oracle, std::move(run.input), run.options);
    });
  }
  catch (const omesh::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const omesh::LabelSmoothingAborted&)
  {
    vtkErrorMacro(<< "meshing aborted (AbortExecute) while smoothing a label map: no mesh");
    return 0;
  }
  catch (const omesh::FeatureSearchAborted&)
  {
    vtkErrorMacro(<< "meshing aborted (AbortExecute) while finding feature lines: no mesh");
    return 0;
  }
  catch (const omesh::TimeLimitReached& e)
  {
    // an error (no partial mesh: one cut by the clock depends on the machine's load), with the
    // figures so far in the otherwise empty output
    vtkErrorMacro(<< "meshing failed: " << e.what());
    TetMeshOutput::AddStatistics(grid->GetFieldData(), e.statistics);
    return 0;
  }
  catch (const omesh::MeshingAborted&)
  {
    // an error, not an empty mesh as success: every caller (Update's status, Python, the CLI) sees it
    vtkErrorMacro(<< "meshing aborted (AbortExecute): no mesh");
    return 0;
  }
  catch (const std::exception& e)
  {
    // a CGAL precondition or assertion (CGAL::Failure_exception), or memory: an error, not a crash
    vtkErrorMacro(<< "meshing failed: " << e.what());
    return 0;
  }
  this->AssembleOutputs(run, outputVector);
  return 1;
}

void vtkFeaturePreservingTetrahedralizer::CheckProperties() const
{
  checkRange("FeatureStrategy", this->FeatureStrategy, CONFORMING, PROTECTING_BALLS,
    ": 0 Conforming, 1 None, 2 ProtectingBalls");
  checkRange("ElementOrder", this->ElementOrder, 1, 2, ": 1 linear, 2 quadratic tetrahedra");
  checkRange("Features", this->Features, FEATURES_NONE, FEATURES_BOTH,
    ": 0 None, 1 Given, 2 Automatic, 3 Both");
  omesh::checkCreaseAngle(this->CreaseAngle, "vtkFeaturePreservingTetrahedralizer: CreaseAngle");
  checkRange("SliverAngle", this->SliverAngle, 0.0, 30.0, " degrees; 0 = off");
  checkRange("InterfaceSliverAngle", this->InterfaceSliverAngle, 0.0, 30.0, " degrees; 0 = off");
  checkRange("PickingSliverAngle", this->PickingSliverAngle, -1.0, 30.0, " degrees; 0 = off, -1 = automatic");
  if (this->MaximumNumberOfVertices < 0)
    throw omesh::InputError("vtkFeaturePreservingTetrahedralizer: MaximumNumberOfVertices " +
      std::to_string(this->MaximumNumberOfVertices) + " is out of range (>= 0; 0 = unlimited)");
  checkRange("Threads", this->Threads, 0, 1024, "; 1 = sequential, 0 = every core");
  checkRange("PerturbationFailuresPerBound", this->PerturbationFailuresPerBound, 0.0, 1e6, "; 0 = never give up");
  checkRange("ExudationSliverBound", this->ExudationSliverBound, 0.0, 90.0, " degrees; 0 = every cell");
  checkRange("ImprovementMinAngle", this->ImprovementMinAngle, 1.0, 60.0, " degrees");
  checkRange("ImprovementMaxAngle", this->ImprovementMaxAngle, 120.0, 179.0, " degrees");
  checkRange("PerturbationStepsPerVertex", this->PerturbationStepsPerVertex, 0.0, 1e6, "; 0 = no budget");
  checkRange("ExudationStepsPerCell", this->ExudationStepsPerCell, 0.0, 1e6, "; 0 = no budget");
  checkRange("OptimisationTimeLimit", this->OptimisationTimeLimit, -1.0, 1e9, " seconds; 0 = none, -1 = CGAL's");
  checkRange("TimeLimit", this->TimeLimit, -1.0, 1e9, " seconds; 0 = automatic, -1 = none");
  omesh::MeshCriteria::fromVtk(this->GlobalCriteria()).check("vtkFeaturePreservingTetrahedralizer");
  for (const auto& [m, c] : this->MaterialCriteria)
    omesh::MeshCriteria::fromVtk(c).check(
      "vtkFeaturePreservingTetrahedralizer: material criteria for material " + std::to_string(m));
}

std::array<double, 6> vtkFeaturePreservingTetrahedralizer::GlobalCriteria() const
{
  return { this->FacetAngle, this->FacetSize, this->FacetDistance, this->CellSize, this->CellRadiusEdgeRatio,
    this->EdgeSize };
}

void vtkFeaturePreservingTetrahedralizer::SetUpOptions(PipelineCall& run)
{
  run.options.features = static_cast<omesh::FeatureSource>(this->Features);
  run.options.creaseAngle = this->CreaseAngle;
  omesh::MesherOptions& options = run.options.mesher;
  options.strategy = this->FeatureStrategy == CONFORMING ? omesh::FeatureStrategy::Conforming
    : this->FeatureStrategy == NONE                    ? omesh::FeatureStrategy::None
                                                        : omesh::FeatureStrategy::ProtectingBalls;
  options.resampleFeatureLines = this->ResampleFeatureLines;
  options.sliverAngle = this->SliverAngle;
  options.interfaceSliverAngle = this->InterfaceSliverAngle;
  options.pickingSliverAngle = this->PickingSliverAngle;
  options.perturb = this->Perturb;
  options.exude = this->Exude;
  options.improveAngles = this->ImproveAngles;
  options.shapeArrays = [&run](std::size_t tetrahedra) { return run.shapes.allocate(tetrahedra); };
  options.improvementMinAngle = this->ImprovementMinAngle;
  options.improvementMaxAngle = this->ImprovementMaxAngle;
  options.perturbationFailuresPerBound = this->PerturbationFailuresPerBound;
  options.exudationSliverBound = this->ExudationSliverBound;
  options.perturbationStepsPerVertex = this->PerturbationStepsPerVertex;
  options.exudationStepsPerCell = this->ExudationStepsPerCell;
  options.optimisationTimeLimit = this->OptimisationTimeLimit;
  options.elementOrder = this->ElementOrder;
  options.seed = static_cast<unsigned>(this->Seed);
  options.maximumNumberOfVertices = static_cast<std::size_t>(this->MaximumNumberOfVertices);
  options.threads = this->Threads;
  options.timeLimit = this->TimeLimit;
  options.progress = [this](double fraction, const char*) {
    this->UpdateProgress(fraction);
    return !this->GetAbortExecute();
  };
}

void vtkFeaturePreservingTetrahedralizer::GatherInputs(vtkInformationVector** inputVector, PipelineCall& run)
{
  vtkDataObject* oracleData = vtkDataObject::GetData(inputVector[0]);
  vtkDataObject* linesData = vtkDataObject::GetData(inputVector[1]);
  vtkDataObject* seedsData = vtkDataObject::GetData(inputVector[2]);
  vtkPolyData* lines = vtkPolyData::SafeDownCast(linesData);
  vtkPointSet* seeds = vtkPointSet::SafeDownCast(seedsData);
  if (!oracleData)
    throw omesh::InputError("vtkFeaturePreservingTetrahedralizer: no input on port 0: connect a "
                            "vtkHierarchicalOracle (or one domain)");
  if (linesData && !lines)
    throw omesh::InputError(std::string("feature lines (input port 1): need vtkPolyData lines, got ") +
      linesData->GetClassName());
  if (seedsData && !seeds)
    throw omesh::InputError(std::string("seed points (input port 2): need points (vtkPolyData), got ") +
      seedsData->GetClassName());
  this->SetUpOptions(run);
  run.input.lines = OracleBuilder::ToFeatureSegments(lines, &run.input.owners);
  const auto oracleStarted = std::chrono::steady_clock::now();
  run.oracle = OracleBuilder::BuildOracle(oracleData, [this](double f) {
    this->UpdateProgress(0.02 * f); // a label map's smoothing: before the feature search's tenth
    return !this->GetAbortExecute();
  });
  run.oracleSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - oracleStarted).count();
  // The merge rule of MeshCriteria.h: global < the domains' own < this filter's table.
  const omesh::CriteriaLevel domainLevel = OracleBuilder::DomainCriteria(oracleData, *run.oracle);
  omesh::CriteriaLevel tableLevel;
  for (const auto& [m, c] : this->MaterialCriteria)
    tableLevel.add(m, omesh::MeshCriteria::fromVtk(c), "the per-material table");
  run.options.mesher.criteria =
    omesh::mergeCriteria(omesh::MeshCriteria::fromVtk(this->GlobalCriteria()), { &domainLevel, &tableLevel });
  // names and criteria given to materials no input has (read from the domains' field data)
  std::vector<int> tableMaterials;
  for (const auto& entry : this->MaterialCriteria)
    tableMaterials.push_back(entry.first);
  run.input.inputWarnings = OracleBuilder::UnknownMaterialWarnings(oracleData, *run.oracle, tableMaterials);
  if (seeds)
    OracleBuilder::CheckCoordinates(seeds->GetPoints(), "seed points (input port 2)", "");
  for (vtkIdType i = 0; seeds && i < seeds->GetNumberOfPoints(); ++i)
  {
    double x[3];
    seeds->GetPoint(i, x);
    run.input.seedPoints.push_back({ x[0], x[1], x[2] });
  }
}

void vtkFeaturePreservingTetrahedralizer::AssembleOutputs(PipelineCall& run, vtkInformationVector* outputVector)
{
  const auto started = std::chrono::steady_clock::now();
  const omesh::PipelineResult& result = run.result;
  for (const auto& w : result.mesh.warnings)
    vtkWarningMacro(<< w);
  vtkUnstructuredGrid* grid = vtkUnstructuredGrid::GetData(outputVector, 0);
  TetMeshOutput::FillGrid(
    grid, result.mesh, run.options.mesher.elementOrder == 2 ? &result.quadratic : nullptr, result.inputWarnings, &run.shapes);
  TetMeshOutput::FillInterfaces(vtkPolyData::GetData(outputVector, 1), result.mesh, grid);
  // the mesher's pieces name the selection's segments, also where it resampled them
  TetMeshOutput::FillSegments(vtkPolyData::GetData(outputVector, 2), result.mesh, result.selection);
  TetMeshOutput::AddStatistic(grid->GetFieldData(), "time.oracle", run.oracleSeconds);
  TetMeshOutput::AddStatistic(grid->GetFieldData(), "time.vtk_output",
    std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

void vtkFeaturePreservingTetrahedralizer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FeatureStrategy: " << this->FeatureStrategy << "\n";
  os << indent << "Features: " << this->Features << "\n";
  os << indent << "CreaseAngle: " << this->CreaseAngle << "\n";
  os << indent << "FacetAngle: " << this->FacetAngle << "\n";
  os << indent << "FacetSize: " << this->FacetSize << "\n";
  os << indent << "FacetDistance: " << this->FacetDistance << "\n";
  os << indent << "CellSize: " << this->CellSize << "\n";
  os << indent << "CellRadiusEdgeRatio: " << this->CellRadiusEdgeRatio << "\n";
  os << indent << "EdgeSize: " << this->EdgeSize << "\n";
  os << indent << "ResampleFeatureLines: " << this->ResampleFeatureLines << "\n";
  os << indent << "SliverAngle: " << this->SliverAngle << "\n";
  os << indent << "InterfaceSliverAngle: " << this->InterfaceSliverAngle << "\n";
  os << indent << "PickingSliverAngle: " << this->PickingSliverAngle << "\n";
  os << indent << "Perturb: " << this->Perturb << "\n";
  os << indent << "Exude: " << this->Exude << "\n";
  os << indent << "ImproveAngles: " << this->ImproveAngles << "\n";
  os << indent << "ImprovementMinAngle: " << this->ImprovementMinAngle << "\n";
  os << indent << "ImprovementMaxAngle: " << this->ImprovementMaxAngle << "\n";
  os << indent << "PerturbationFailuresPerBound: " << this->PerturbationFailuresPerBound << "\n";
  os << indent << "ExudationSliverBound: " << this->ExudationSliverBound << "\n";
  os << indent << "PerturbationStepsPerVertex: " << this->PerturbationStepsPerVertex << "\n";
  os << indent << "ExudationStepsPerCell: " << this->ExudationStepsPerCell << "\n";
  os << indent << "OptimisationTimeLimit: " << this->OptimisationTimeLimit << "\n";
  os << indent << "ElementOrder: " << this->ElementOrder << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "MaximumNumberOfVertices: " << this->MaximumNumberOfVertices << "\n";
  os << indent << "Threads: " << this->Threads << "\n";
  os << indent << "TimeLimit: " << this->TimeLimit << "\n";
  for (const auto& [m, c] : this->MaterialCriteria)
    os << indent << "Material " << m << " criteria: " << c[0] << " " << c[1] << " " << c[2] << " " << c[3]
       << " " << c[4] << " " << c[5] << "\n";
}
