// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshingPipeline.h"

#include "FeatureClip.h"
#include "FeatureMerge.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "InputWarnings.h"
#include "MemoryCheck.h"
#include "MeshSizeEstimate.h"
#include "MeshingDeadline.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <sstream>

namespace omesh
{
namespace
{
/// One warning saying how many segments clipping removed and split, of which inputs.
std::string clipWarning(const FeatureClipCounts& clipped, const HierarchicalOracle& oracle, std::size_t remaining)
{
  std::ostringstream o;
  o << "feature lines clipped to the meshed domain: " << clipped.removed() << " segment(s) removed and "
    << clipped.split() << " split where they leave it (";
  bool first = true;
  for (const auto& [owner, c] : clipped.owners)
  {
    o << (first ? "" : "; ");
    first = false;
    if (owner == kUserLine)
      o << "the given lines";
    else
    {
      const auto& domains = oracle.domains();
      o << "the sharp edges of ";
      if (owner >= 0 && owner < static_cast<int>(domains.size()) && !domains[owner]->name().empty())
        o << domains[owner]->name();
      else
        o << "input " << owner;
    }
    o << ": " << c.removed << " removed, " << c.split << " split";
  }
  o << "): no material lies there (beyond the domains or cut away)";
  if (std::any_of(clipped.owners.begin(), clipped.owners.end(), [](const auto& e) { return e.first != kUserLine; }))
    o << " or a higher-priority input covers the part's edge";
  o << ", so no mesh edge can hold them and they are not counted as missing; " << remaining << " segments remain";
  return o.str();
}

/// Only what the merge did: "merged 2 duplicate segment(s); split 4 pair(s) of crossing segments ...".
std::string mergeWarning(const FeatureMergeCounts& merged, std::size_t remaining)
{
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
  for (std::size_t i = 0; i < merges.size(); ++i)
    text += (i == 0 ? "merged " : i + 1 == merges.size() ? " and " : ", ") + merges[i];
  if (merged.crossings)
    text += (merges.empty() ? "" : "; ") + std::string("split ") + std::to_string(merged.crossings) +
      " pair(s) of crossing segments where they cross (lines may meet only at shared points)";
  if (merged.splitSegments)
    text += (merges.empty() && !merged.crossings ? "" : "; ") + std::string("split ") +
      std::to_string(merged.splitSegments) + " segment(s) at points of other lines lying on them within rounding";
  return text + "; " + std::to_string(remaining) + " segments remain";
}

/// Refuses, before any meshing, criteria the run cannot meet (beyond the vertex budget or the time
/// limit: MeshSizeEstimate.h) and a mesh too big for the memory available: errors naming the sizes,
/// not hours of refinement, std::bad_alloc or the OOM killer later. Returns the estimate's vertices.
double checkSize(const HierarchicalOracle& oracle, const FeatureSegments& features, const MesherOptions& options)
{
  const MeshSizeEstimate estimate = estimateMeshSize(oracle, options.criteria, features);
  const double asked = estimate.total();
  const double budget = options.maximumNumberOfVertices ? static_cast<double>(options.maximumNumberOfVertices) : asked;
  checkMeshSize(estimate, static_cast<double>(options.maximumNumberOfVertices), effectiveTimeLimit(options));
  std::ostringstream what;
  what << "a mesh of about " << std::min(asked, budget) << " vertices (the criteria ask for about " << asked
       << (budget < asked ? ", MaximumNumberOfVertices caps it)" : ")");
  try
  {
    checkMemory("vtkFeaturePreservingTetrahedralizer", what.str(), std::min(asked, budget), kBytesPerMeshVertex);
  }
  catch (const InputError& e)
  {
    throw InputError(std::string(e.what()) + ": coarsen the criteria or lower MaximumNumberOfVertices");
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
  for (std::size_t i = 0; i < causes.size(); ++i)
    text += (i ? "; " : " ") + causes[i];
  return text;
}
}

PipelineResult runMeshingPipeline(const HierarchicalOracle& oracle, PipelineInput input, PipelineOptions options)
{
  const auto started = std::chrono::steady_clock::now();
  const auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  PipelineResult out;
  std::vector<std::string> notes; // the pipeline's warnings, listed before the mesher's
  std::vector<std::string>& inputNotes = out.inputWarnings;
  FeatureSegments& lines = input.lines;
  MesherOptions& mesher = options.mesher;

  // The lines are clipped to where they can be features of the oracle's domain before they are
  // merged (the merge makes a clipped end one with any given point there).
  if (!lines.empty())
  {
    const FeatureClipCounts clipped = clipFeatureSegments(lines, oracle, input.owners);
    if (clipped.changed())
      notes.push_back(clipWarning(clipped, oracle, lines.segments.size()));
  }
  const FeatureMergeCounts merged = mergeFeatureSegments(lines);
  if (merged.changed())
    notes.push_back(mergeWarning(merged, lines.segments.size()));
  for (std::string& w : hiddenDomainWarnings(oracle))
    notes.push_back(std::move(w));
  // slips that would mesh silently: inputs in other frames or units, the caller's own (names and
  // criteria of materials no input has), sizes in other units
  inputNotes = inputPlacementWarnings(oracle);
  inputNotes.insert(inputNotes.end(), input.inputWarnings.begin(), input.inputWarnings.end());
  for (std::string& w : criteriaScaleWarnings(oracle, mesher.criteria))
    inputNotes.push_back(std::move(w));

  // The lines to keep: given, found where the inputs meet, or both. The search runs under the
  // run's time limit (the mesher gets what is left) and takes the first tenth of the progress.
  const double warningsSeconds = since(started);
  const auto selectionStarted = std::chrono::steady_clock::now();
  const bool searching = options.features == FeatureSource::Automatic || options.features == FeatureSource::Both;
  const MeshingDeadline deadline(effectiveTimeLimit(mesher));
  const auto progress = mesher.progress;
  out.selection = selectFeatures(oracle, lines, options.features, mesher.criteria, options.creaseAngle,
    [&](double f) {
      deadline.check("feature line search");
      return !progress || progress(0.1 * f, "feature line search");
    });
  if (searching)
  {
    if (deadline.limited())
      mesher.timeLimit = std::max(1e-3, deadline.limit() - deadline.elapsed());
    if (progress)
      mesher.progress = [progress](double fraction, const char* phase) { return progress(0.1 + 0.9 * fraction, phase); };
  }
  notes.insert(notes.end(), out.selection.warnings.begin(), out.selection.warnings.end());

  const double selectionSeconds = since(selectionStarted);
  const auto sizeStarted = std::chrono::steady_clock::now();
  const double asked = checkSize(oracle, out.selection.segments, mesher);
  const double sizeSeconds = since(sizeStarted);
  out.mesh = meshOracle(oracle, out.selection.segments, input.seedPoints, mesher);
  out.mesh.statistics["estimated_vertices"] = asked;
  // the pipeline's steps before the mesher: the lines' clip and merge with the input checks, the
  // feature selection (the automatic search when asked), the size and memory estimate
  out.mesh.statistics["time.input_checks"] = warningsSeconds;
  out.mesh.statistics["time.feature_selection"] = selectionSeconds;
  out.mesh.statistics["time.size_estimate"] = sizeSeconds;
  if (out.mesh.tets.empty())
    throw InputError(emptyMeshMessage(notes, inputNotes, out.mesh.warnings));
  if (mesher.elementOrder == 2)
  {
    const auto started = std::chrono::steady_clock::now();
    out.quadratic = makeQuadraticTets(out.mesh, oracle);
    out.quadratic.statistics["time.quadratic"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    out.mesh.statistics.insert(out.quadratic.statistics.begin(), out.quadratic.statistics.end());
  }

  const auto checksStarted = std::chrono::steady_clock::now();
  std::map<int, std::size_t> tetsPerMaterial;
  for (int m : out.mesh.tetMaterial)
    ++tetsPerMaterial[m];
  for (std::string& w : vanishedMaterialWarnings(oracle, tetsPerMaterial))
    inputNotes.push_back(std::move(w));
  // what the surfaces' inside tests repaired, measured on the mesh
  const std::vector<std::string> repairs = surfaceWarnings(oracle, &out.mesh);
  inputNotes.insert(inputNotes.begin(), repairs.begin(), repairs.end());
  out.mesh.statistics["time.input_checks_on_mesh"] =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - checksStarted).count();
  notes.insert(notes.end(), inputNotes.begin(), inputNotes.end());
  out.mesh.warnings.insert(out.mesh.warnings.begin(), notes.begin(), notes.end());
  return out;
}
}
