// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkFeaturePreservingTetrahedralizer.h"

#include "FeatureClip.h"
#include "FeatureMerge.h"
#include "FeatureSelection.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelSmoothing.h"
#include "MeshQuality.h"
#include "MeshSizeEstimate.h"
#include "OracleBuilder.h"
#include "OracleMesher.h"
#include "QuadraticTets.h"
#include "TetMeshOutput.h"

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
#include <map>
#include <memory>
#include <sstream>

vtkStandardNewMacro(vtkFeaturePreservingTetrahedralizer);

namespace
{
/// Refuses, before any meshing, criteria the run cannot meet (beyond the vertex budget or the time
/// limit: MeshSizeEstimate.h) and a mesh too big for the memory available: errors naming the sizes,
/// not hours of refinement, std::bad_alloc or the OOM killer later. Returns the estimate's vertices.
double checkMeshSize(
  const omesh::HierarchicalOracle& oracle, const omesh::FeatureSegments& features, const omesh::MesherOptions& options)
{
  const omesh::MeshSizeEstimate estimate = omesh::estimateMeshSize(oracle, options.criteria, features);
  const double asked = estimate.total();
  const double budget = options.maximumNumberOfVertices ? static_cast<double>(options.maximumNumberOfVertices) : asked;
  omesh::checkMeshSize(
    estimate, static_cast<double>(options.maximumNumberOfVertices), omesh::effectiveTimeLimit(options));
  std::ostringstream what;
  what << "a mesh of about " << std::min(asked, budget) << " vertices (the criteria ask for about " << asked
       << (budget < asked ? ", MaximumNumberOfVertices caps it)" : ")");
  try
  {
    OracleBuilder::CheckMemory(
      "vtkFeaturePreservingTetrahedralizer", what.str(), std::min(asked, budget), omesh::kBytesPerMeshVertex);
  }
  catch (const omesh::InputError& e)
  {
    throw omesh::InputError(std::string(e.what()) + ": coarsen the criteria or lower MaximumNumberOfVertices");
  }
  return asked;
}

/// The error of a run that ends with no tetrahedron: what removed everything, from what the run
/// found on the way (hidden or cut domains, criteria larger than the domain, the budget), else the
/// likely causes.
std::string emptyMeshMessage(const std::vector<std::string>& notes, const std::vector<std::string>& inputNotes,
  const std::vector<std::string>& meshWarnings)
{
  std::string text = "no tetrahedra: the mesh is empty";
  std::vector<std::string> causes(notes.begin(), notes.end());
  causes.insert(causes.end(), inputNotes.begin(), inputNotes.end());
  causes.insert(causes.end(), meshWarnings.begin(), meshWarnings.end());
  if (causes.empty())
    return text + " (every material is cut away, outside the other domains, or smaller than the mesh size: "
                  "check the cuts' sides and the criteria against the inputs' size)";
  text += "; what the run found:";
  for (size_t i = 0; i < causes.size(); ++i)
    text += (i ? "; " : " ") + causes[i];
  return text;
}

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

/// One run of RequestData: the core's inputs and options, then its mesh.
struct vtkFeaturePreservingTetrahedralizer::MeshingRun
{
  omesh::MesherOptions options;
  std::shared_ptr<omesh::HierarchicalOracle> oracle;
  omesh::FeatureSegments features;
  omesh::FeatureSelection selection; // how `features` were chosen: each segment's origin
  std::vector<omesh::Vec3> seedPoints;
  std::vector<std::string> notes;      // this adapter's warnings, listed before the mesher's
  std::vector<std::string> inputNotes; // of them, those about the inputs (field data InputWarnings)
  omesh::TetMesh mesh;
  omesh::QuadraticTetMesh quadratic; // with ElementOrder 2
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
  MeshingRun run;
  try
  {
    this->CheckProperties(); // before any heavy work
    this->GatherInputs(inputVector, run);
    this->MeshInputs(run);
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

void vtkFeaturePreservingTetrahedralizer::SetUpOptions(MeshingRun& run)
{
  omesh::MesherOptions& options = run.options;
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

void vtkFeaturePreservingTetrahedralizer::GatherInputs(vtkInformationVector** inputVector, MeshingRun& run)
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
  std::vector<int> owners;
  run.features = OracleBuilder::ToFeatureSegments(lines, &owners);
  // The oracle first: the lines are clipped to where they can be features of its domain before
  // they are merged (the merge makes a clipped end one with any given point there).
  run.oracle = OracleBuilder::BuildOracle(oracleData, [this](double f) {
    this->UpdateProgress(0.02 * f); // a label map's smoothing: before the feature search's tenth
    return !this->GetAbortExecute();
  });
  if (!run.features.empty())
    ClipFeatures(run, owners);
  const omesh::FeatureMergeCounts merged = omesh::mergeFeatureSegments(run.features);
  if (merged.changed())
  {
    // only what happened: "merged 2 duplicate segment(s); split 4 pair(s) of crossing segments ..."
    std::vector<std::string> merges;
    if (merged.duplicates)
      merges.push_back(std::to_string(merged.duplicates) + " duplicate segment(s)");
    if (merged.overlapping)
      merges.push_back(std::to_string(merged.overlapping) + " overlapping collinear segment(s) in " +
        std::to_string(merged.overlapGroups) + " group(s)");
    if (merged.mergedPoints)
      merges.push_back(std::to_string(merged.mergedPoints) + " repeated point(s)" +
        (merged.withinRounding ? " (some within rounding of each other)" : ""));
    std::string text = "feature lines: ";
    for (size_t i = 0; i < merges.size(); ++i)
      text += (i == 0 ? "merged " : i + 1 == merges.size() ? " and " : ", ") + merges[i];
    if (merged.crossings)
      text += (merges.empty() ? "" : "; ") + std::string("split ") + std::to_string(merged.crossings) +
        " pair(s) of crossing segments where they cross (lines may meet only at shared points)";
    if (merged.splitSegments)
      text += (merges.empty() && !merged.crossings ? "" : "; ") + std::string("split ") +
        std::to_string(merged.splitSegments) + " segment(s) at points of other lines lying on them within rounding";
    run.notes.push_back(text + "; " + std::to_string(run.features.segments.size()) + " segments remain");
  }

  for (const std::string& w : OracleBuilder::HiddenDomainWarnings(*run.oracle))
    run.notes.push_back(w);
  run.inputNotes = OracleBuilder::InputPlacementWarnings(*run.oracle);
  // The merge rule of MeshCriteria.h: global < the domains' own < this filter's table.
  const omesh::CriteriaLevel domainLevel = OracleBuilder::DomainCriteria(oracleData, *run.oracle);
  omesh::CriteriaLevel tableLevel;
  for (const auto& [m, c] : this->MaterialCriteria)
    tableLevel.add(m, omesh::MeshCriteria::fromVtk(c), "the per-material table");
  run.options.criteria =
    omesh::mergeCriteria(omesh::MeshCriteria::fromVtk(this->GlobalCriteria()), { &domainLevel, &tableLevel });
  // slips that would mesh silently: names and criteria of materials no input has, sizes in other units
  std::vector<int> tableMaterials;
  for (const auto& entry : this->MaterialCriteria)
    tableMaterials.push_back(entry.first);
  for (std::string& w : OracleBuilder::UnknownMaterialWarnings(oracleData, *run.oracle, tableMaterials))
    run.inputNotes.push_back(std::move(w));
  for (std::string& w : omesh::criteriaScaleWarnings(*run.oracle, run.options.criteria))
    run.inputNotes.push_back(std::move(w));
  this->SelectFeatures(run);
  if (seeds)
    OracleBuilder::CheckCoordinates(seeds->GetPoints(), "seed points (input port 2)", "");
  for (vtkIdType i = 0; seeds && i < seeds->GetNumberOfPoints(); ++i)
  {
    double x[3];
    seeds->GetPoint(i, x);
    run.seedPoints.push_back({ x[0], x[1], x[2] });
  }
}

void vtkFeaturePreservingTetrahedralizer::ClipFeatures(MeshingRun& run, const std::vector<int>& owners)
{
  const omesh::FeatureClipCounts clipped = omesh::clipFeatureSegments(run.features, *run.oracle, owners);
  if (!clipped.changed())
    return;
  // one warning: how many segments, of which inputs
  std::ostringstream o;
  o << "feature lines clipped to the meshed domain: " << clipped.removed() << " segment(s) removed and "
    << clipped.split() << " split where they leave it (";
  bool first = true;
  for (const auto& [owner, c] : clipped.owners)
  {
    o << (first ? "" : "; ");
    first = false;
    if (owner == omesh::kUserLine)
      o << "the given lines";
    else
    {
      const auto& domains = run.oracle->domains();
      o << "the sharp edges of ";
      if (owner >= 0 && owner < static_cast<int>(domains.size()) && !domains[owner]->name().empty())
        o << domains[owner]->name();
      else
        o << "input " << owner;
    }
    o << ": " << c.removed << " removed, " << c.split << " split";
  }
  o << "): no material lies there (beyond the domains or cut away)";
  if (std::any_of(clipped.owners.begin(), clipped.owners.end(), [](const auto& e) { return e.first != omesh::kUserLine; }))
    o << " or a higher-priority input covers the part's edge";
  o << ", so no mesh edge can hold them and they are not counted as missing; " << run.features.segments.size()
    << " segments remain";
  run.notes.push_back(o.str());
}

void vtkFeaturePreservingTetrahedralizer::SelectFeatures(MeshingRun& run)
{
  // The lines to keep: given, found where the inputs meet, or both. The search runs under the
  // run's time limit (the mesher gets what is left) and takes the first tenth of the progress.
  const auto source = static_cast<omesh::FeatureSource>(this->Features);
  const bool searching = source == omesh::FeatureSource::Automatic || source == omesh::FeatureSource::Both;
  const omesh::MeshingDeadline deadline(omesh::effectiveTimeLimit(run.options));
  run.selection = omesh::selectFeatures(*run.oracle, run.features, source, run.options.criteria, this->CreaseAngle,
    [this, &deadline](double f) {
      deadline.check("feature line search");
      this->UpdateProgress(0.1 * f);
      return !this->GetAbortExecute();
    });
  run.features = run.selection.segments;
  if (searching)
  {
    if (deadline.limited())
      run.options.timeLimit = std::max(1e-3, deadline.limit() - deadline.elapsed());
    run.options.progress = [this](double fraction, const char*) {
      this->UpdateProgress(0.1 + 0.9 * fraction);
      return !this->GetAbortExecute();
    };
  }
  run.notes.insert(run.notes.end(), run.selection.warnings.begin(), run.selection.warnings.end());
}

void vtkFeaturePreservingTetrahedralizer::MeshInputs(MeshingRun& run)
{
  const double asked = checkMeshSize(*run.oracle, run.features, run.options);
  run.mesh = omesh::meshOracle(*run.oracle, run.features, run.seedPoints, run.options);
  run.mesh.statistics["estimated_vertices"] = asked;
  if (run.mesh.tets.empty())
    throw omesh::InputError(emptyMeshMessage(run.notes, run.inputNotes, run.mesh.warnings));
  if (run.options.elementOrder == 2)
  {
    const auto started = std::chrono::steady_clock::now();
    run.quadratic = omesh::makeQuadraticTets(run.mesh, *run.oracle);
    run.quadratic.statistics["time.quadratic"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    run.mesh.statistics.insert(run.quadratic.statistics.begin(), run.quadratic.statistics.end());
  }
}

void vtkFeaturePreservingTetrahedralizer::AssembleOutputs(MeshingRun& run, vtkInformationVector* outputVector)
{
  std::map<int, std::size_t> tetsPerMaterial;
  for (int m : run.mesh.tetMaterial)
    ++tetsPerMaterial[m];
  for (const std::string& w : OracleBuilder::VanishedMaterialWarnings(*run.oracle, tetsPerMaterial))
    run.inputNotes.push_back(w);
  // what the surfaces' inside tests repaired, measured on the mesh (--strict fails on these)
  const std::vector<std::string> repairs = OracleBuilder::SurfaceWarnings(*run.oracle, &run.mesh);
  run.inputNotes.insert(run.inputNotes.begin(), repairs.begin(), repairs.end());
  run.notes.insert(run.notes.end(), run.inputNotes.begin(), run.inputNotes.end());
  run.mesh.warnings.insert(run.mesh.warnings.begin(), run.notes.begin(), run.notes.end());
  for (const auto& w : run.mesh.warnings)
    vtkWarningMacro(<< w);

  vtkUnstructuredGrid* grid = vtkUnstructuredGrid::GetData(outputVector, 0);
  TetMeshOutput::FillGrid(grid, run.mesh, run.options.elementOrder == 2 ? &run.quadratic : nullptr, run.inputNotes);
  TetMeshOutput::FillInterfaces(vtkPolyData::GetData(outputVector, 1), run.mesh, grid);
  // the mesher's pieces name the selection's segments, also where it resampled them
  TetMeshOutput::FillSegments(vtkPolyData::GetData(outputVector, 2), run.mesh, run.selection);
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
