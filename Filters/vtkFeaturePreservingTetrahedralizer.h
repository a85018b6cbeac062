// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkFeaturePreservingTetrahedralizer
 * @brief Multi-material tetrahedral mesh of a hierarchical oracle, keeping given feature lines.
 *
 * Inputs: port 0, the output of vtkHierarchicalOracle (or one domain); port 1 (optional),
 * vtkPolyData lines: the given constrained segments (Features says whether these, the lines found
 * where the inputs meet, or both are kept) (polylines are split into segments, shared points are
 * shared vertices; an optional cell array "EdgeSize" gives a line its own edge size, -1 = none);
 * port 2 (optional), vtkPolyData points inserted first (a-priori points).
 *
 * Delaunay refinement on CGAL Mesh_3 with the oracle's exact intersections; each tetrahedron takes
 * the material of its circumcentre. FeatureStrategy: Conforming (the default; the paper's rules
 * T1-T3: the segments are refined as the lowest level of Mesh_3's refinement and stay Delaunay
 * edges), None (stock Mesh_3, Pons et al.), ProtectingBalls (CGAL's protecting balls, Dey et al.).
 * Criteria are global and can be overridden per material.
 *
 * Defaults: every property's default comes from the core's omesh::MesherOptions and
 * omesh::MeshCriteria::defaults(), the one source of them; the getters of a fresh filter show
 * them (the Python package, the scene loader and the command line read them there, and a test
 * checks the plugin XML's default_values against them). Criteria merge as documented in
 * MeshCriteria.h: defaults < global < a domain's own < this filter's per-material table; two domains
 * giving one material different values for a criterion are an error naming both. EdgeSize has a
 * per-feature level on top: global < per material < a line's own "EdgeSize" (MeshCriteria.h).
 *
 * Port 0 takes any data object and port 1 any vtkPolyData so that a wrong input gets an error naming
 * the port (an image as feature lines, triangles or vertices as feature lines, no oracle); duplicate
 * and overlapping collinear feature segments are merged (with a warning), not refused. A domain that
 * higher-priority domains hide completely is reported as a warning. An abort (AbortExecute) or a
 * failure ends the update with an error and an empty output, never an empty mesh as success.
 *
 * Outputs: port 0, vtkUnstructuredGrid of tetrahedra (4 nodes, or 10 with ElementOrder 2) with cell data Material, MinDihedralAngle, MaxDihedralAngle
 * (degrees) and RadiusEdgeRatio, point data Dimension (0 corner, 1 segment, 2 interface,
 * 3 volume), field data StatisticNames/StatisticValues, Warnings and SeparatingFaces (the faces on
 * the boundary or between materials as the validity check found them: 4 x cell + the face's
 * Abaqus number - 1, and the material on the other side or -1; what the writers' surface sets
 * are made of); port 1, the interface
 * triangles with cell data Materials (2 components: the materials on the two sides, -1 outside);
 * port 2, the constrained segments cut at the mesh vertices on them, cell data Present (1 when the
 * piece is a mesh edge), Origin (0 given, 1 found where the inputs meet) and Materials (4
 * components: the materials a found piece separates, ascending, -2 none).
 *
 * @warning Long runs: progress through vtkAlgorithm's ProgressEvent; AbortExecute (ParaView's
 * abort button) stops meshing at the next step; TimeLimit ends a run with an error naming the
 * phase. Bad input (an empty oracle, criteria that cannot be met, a mesh that would not fit in
 * memory) fails the update with an error naming it, never a silently wrong mesh.
 *
 * @sa vtkHierarchicalOracle vtkOracleFeatureLines vtkMeshValidityCheck vtkDelaunay3D
 */
#ifndef vtkFeaturePreservingTetrahedralizer_h
#define vtkFeaturePreservingTetrahedralizer_h

#include "OracleMeshFiltersModule.h"

#include <vtkUnstructuredGridAlgorithm.h>

#include <array>
#include <vector>
#include <map>
#include <string>

class ORACLEMESHFILTERS_EXPORT vtkFeaturePreservingTetrahedralizer : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkFeaturePreservingTetrahedralizer* New();
  vtkTypeMacro(vtkFeaturePreservingTetrahedralizer, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum FeatureStrategies
  {
    CONFORMING = 0,
    NONE = 1,
    PROTECTING_BALLS = 2
  };

  ///@{
  /// How constrained segments are kept. Default CONFORMING. Out-of-range values (here and for every
  /// bounded property below) are not clamped: the next update fails with an error naming the property.
  vtkSetMacro(FeatureStrategy, int);
  vtkGetMacro(FeatureStrategy, int);
  void SetFeatureStrategyToConforming() { this->SetFeatureStrategy(CONFORMING); }
  void SetFeatureStrategyToNone() { this->SetFeatureStrategy(NONE); }
  void SetFeatureStrategyToProtectingBalls() { this->SetFeatureStrategy(PROTECTING_BALLS); }
  ///@}

  enum FeatureSources
  {
    FEATURES_NONE = 0,
    FEATURES_GIVEN = 1,
    FEATURES_AUTOMATIC = 2,
    FEATURES_BOTH = 3
  };

  ///@{
  /// Which feature lines are kept: none, the given ones (port 1), the ones found where the inputs
  /// meet (cut rims, entry curves, triple lines, creases above CreaseAngle: omesh::findFeatureLines, as vtkOracleFeatureLines
  /// shows them, resampled to the edge size of the materials they separate), or both. Default
  /// Given (see omesh::kDefaultFeatureSource for why). Automatic segments that run along or cross
  /// given ones are dropped with a warning. With Conforming they are kept like given ones. The
  /// search runs under TimeLimit and reports the first tenth of the progress.
  vtkSetMacro(Features, int);
  vtkGetMacro(Features, int);
  void SetFeaturesToNone() { this->SetFeatures(FEATURES_NONE); }
  void SetFeaturesToGiven() { this->SetFeatures(FEATURES_GIVEN); }
  void SetFeaturesToAutomatic() { this->SetFeatures(FEATURES_AUTOMATIC); }
  void SetFeaturesToBoth() { this->SetFeatures(FEATURES_BOTH); }
  ///@}

  ///@{
  /// With Features Automatic or Both: the creases of single inputs (a surface's sharp edges, a
  /// box's edges, a cylinder's rims) are kept where their faces' normals differ by more than this
  /// (degrees; default 60, the core's omesh::kDefaultCreaseAngle), as vtkOracleFeatureLines'
  /// CreaseAngle. 180 = no creases (only the curves where inputs meet). Range: above 0 to 180.
  vtkSetMacro(CreaseAngle, double); // (0, 180]
  vtkGetMacro(CreaseAngle, double);
  ///@}

  ///@{
  /// Global criteria (0 = no bound, -1 = the default; other negative values are refused). FacetAngle: lower bound of surface triangle angles (degrees,
  /// default 25). FacetSize: upper bound of the surface Delaunay ball radius. FacetDistance: upper
  /// bound of the distance between a surface triangle and the surface. CellSize: upper bound of the
  /// tetrahedron circumradius. CellRadiusEdgeRatio: upper bound of circumradius / shortest edge
  /// (default 3). EdgeSize: upper bound of constrained-segment pieces (a line's own EdgeSize on
  /// port 1 and the materials' EdgeSize come first: MeshCriteria.h).
  vtkSetMacro(FacetAngle, double);
  vtkGetMacro(FacetAngle, double);
  vtkSetMacro(FacetSize, double);
  vtkGetMacro(FacetSize, double);
  vtkSetMacro(FacetDistance, double);
  vtkGetMacro(FacetDistance, double);
  vtkSetMacro(CellSize, double);
  vtkGetMacro(CellSize, double);
  vtkSetMacro(CellRadiusEdgeRatio, double);
  vtkGetMacro(CellRadiusEdgeRatio, double);
  vtkSetMacro(EdgeSize, double);
  vtkGetMacro(EdgeSize, double);
  ///@}

  ///@{
  /// Per-material overrides, in the order facet angle, facet size, facet distance, cell size,
  /// cell radius-edge ratio, edge size; -1 is "not set" (the domain's or the global value counts);
  /// 0 is "no bound"; other negative values are refused.
  void SetMaterialCriteria(int materialId, double facetAngle, double facetSize, double facetDistance,
    double cellSize, double cellRadiusEdgeRatio, double edgeSize);
  void RemoveMaterialCriteria(int materialId);
  void ClearMaterialCriteria();
  ///@}

  ///@{
  /// The same as a table of rows (ParaView's repeatable property): material id, then the six
  /// values as in SetMaterialCriteria. The id comes as a double (a table of doubles) and must be
  /// an integer >= 0 listed once; otherwise the next update fails with an error naming the row.
  void AddMaterialCriteria(double materialId, double facetAngle, double facetSize, double facetDistance,
    double cellSize, double cellRadiusEdgeRatio, double edgeSize);
  void RemoveAllMaterialCriteria();
  ///@}

  ///@{
  /// Sliver removal after refinement (CGAL's perturber and exuder). Default on.
  vtkSetMacro(Perturb, bool);
  vtkGetMacro(Perturb, bool);
  vtkBooleanMacro(Perturb, bool);
  vtkSetMacro(Exude, bool);
  vtkGetMacro(Exude, bool);
  vtkBooleanMacro(Exude, bool);
  ///@}

  ///@{
  /// The quality step after the optimisers (omesh::improveDihedralAngles): flips inside one
  /// material and vertex moves that keep feature lines and interfaces, raising the tetrahedra with
  /// a dihedral angle outside [ImprovementMinAngle, ImprovementMaxAngle] degrees (default on,
  /// [15, 155]; statistics improvement.*, a line in the report).
  vtkSetMacro(ImproveAngles, bool);
  vtkGetMacro(ImproveAngles, bool);
  vtkBooleanMacro(ImproveAngles, bool);
  vtkSetMacro(ImprovementMinAngle, double); // 1 to 60
  vtkGetMacro(ImprovementMinAngle, double);
  vtkSetMacro(ImprovementMaxAngle, double); // 120 to 179
  vtkGetMacro(ImprovementMaxAngle, double);
  ///@}

  ///@{
  /// The optimisation policy (see omesh::MesherOptions): the perturber gives up at a bound on the
  /// smallest dihedral angle it cannot reach after this many vertices it could not move (plus 1% of
  /// its attempts at that bound; default 4; 0 = never, CGAL's behaviour); the exuder pumps the cells
  /// below ExudationSliverBound degrees (default 15; 0 = every cell, CGAL's default).
  vtkSetMacro(PerturbationFailuresPerBound, double); // 0 to 1e6
  vtkGetMacro(PerturbationFailuresPerBound, double);
  vtkSetMacro(ExudationSliverBound, double); // 0 to 90
  vtkGetMacro(ExudationSliverBound, double);
  ///@}

  ///@{
  /// Step budgets of the sliver optimisers (they otherwise may run for hours on large meshes):
  /// perturbation attempts per mesh vertex (default 2) and cells pumped per cell (default 0.1: the exuder treats the worst first, and on an 890k-tet mesh 0.1 reached the same minimal angle as 1 in a fifth of the time);
  /// 0 = no budget. A phase that reaches its budget ends there (statistics
  /// optimisation.perturbation_cut_short / exudation_cut_short, and a line in the report).
  vtkSetMacro(PerturbationStepsPerVertex, double); // 0 to 1e6
  vtkGetMacro(PerturbationStepsPerVertex, double);
  vtkSetMacro(ExudationStepsPerCell, double); // 0 to 1e6
  vtkGetMacro(ExudationStepsPerCell, double);
  ///@}

  ///@{
  /// Seconds for each optimiser: 0 = no limit (default; with a limit the mesh depends on the
  /// machine's speed), -1 = stock CGAL's default (the refinement's running time).
  vtkSetMacro(OptimisationTimeLimit, double); // -1 to 1e9
  vtkGetMacro(OptimisationTimeLimit, double);
  ///@}

  ///@{
  /// Simplify and resample the feature lines before meshing, at the edge size h (core:
  /// simplifyFeatureNetwork): points closer than h merged, lines at less than 30 degrees sharing a
  /// trunk, spurs, short pieces and segments leaving the domain dropped, chords of at most h within
  /// half the smallest facet distance. For lines made of many tiny noisy segments (sharp edges of
  /// scanned surfaces), which otherwise cost a point per wiggle and meet at small angles all along.
  vtkSetMacro(ResampleFeatureLines, bool);
  vtkGetMacro(ResampleFeatureLines, bool);
  vtkBooleanMacro(ResampleFeatureLines, bool);
  ///@}

  ///@{
  /// Tetrahedra of any material whose minimal dihedral angle is below this bound (degrees) are
  /// refined: removes the flat tetrahedra radius-edge refinement leaves; higher values bound the
  /// angles before optimisation at a price in tetrahedra (no termination guarantee: the vertex
  /// budget applies). 0 turns it off. Default 1.
  vtkSetMacro(SliverAngle, double); // 0 to 30
  vtkGetMacro(SliverAngle, double);
  ///@}

  ///@{
  /// Tetrahedra with at least three vertices on interfaces or feature lines and whose minimal dihedral
  /// angle is below this bound (degrees) are refined: the perturber and exuder cannot fix them
  /// (those vertices only slide on their interface). 0 turns it off. Default 10.
  vtkSetMacro(InterfaceSliverAngle, double); // 0 to 30
  vtkGetMacro(InterfaceSliverAngle, double);
  ///@}

  ///@{
  /// Strategies None and Conforming, on one thread: tetrahedra below this bound (degrees; the larger of it
  /// and SliverAngle) are refined, each at a point picked near its circumcentre so that the new
  /// tetrahedra are no slivers (Li and Teng's picking region). Bounds the angles before
  /// optimisation where circumcentres would run into the vertex budget. 0 turns it off (CGAL's
  /// circumcentres); -1, the default: 12 where every material's radius-edge bound is at least
  /// 1.3, 8.7 where every one is at least 1.1 (the paper's), else off (no termination guarantee: the vertex budget applies).
  vtkSetMacro(PickingSliverAngle, double); // -1 to 30
  vtkGetMacro(PickingSliverAngle, double);
  ///@}

  ///@{
  /// 1 (default): linear tetrahedra (VTK_TETRA). 2: quadratic tetrahedra (VTK_QUADRATIC_TETRA,
  /// 10 nodes): the mid-edge nodes of edges on interfaces and the boundary are moved onto the
  /// oracle's true surfaces, then pulled back where a curved tetrahedron's Jacobian gets too small
  /// (statistics quadratic.*); feature-line and interior edges stay straight. Port 1 keeps linear
  /// interface triangles on the corner nodes.
  vtkSetMacro(ElementOrder, int); // 1 or 2
  vtkGetMacro(ElementOrder, int);
  ///@}

  ///@{
  /// Seed of the random choices: same input and seed give an identical mesh. Default 0.
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /// Refinement stops (with a warning) at this many vertices; 0 = unlimited. Default 2,000,000.
  /// The partial mesh is then finished for validity (feature-line pieces as mesh edges, surface
  /// facets' vertices on the surface, no tetrahedron below SliverAngle, at least 1 degree), with
  /// at most max(10 % of this, 500) vertices more; a warning names what is left if that is not
  /// enough (docs/REFERENCE.md, "Time limit").
  vtkSetMacro(MaximumNumberOfVertices, vtkIdType); // >= 0
  vtkGetMacro(MaximumNumberOfVertices, vtkIdType);
  ///@}

  ///@{
  /// Threads of the refinement. 1 (the default): sequential, the same seed gives the same mesh.
  /// N > 1 (0 = every core): CGAL's parallel refinement on N threads; the mesh meets the same
  /// criteria and passes the same checks but differs from run to run (every strategy; the threads
  /// refine at circumcentres, then one thread refines the slivers they left at picked points); the
  /// optimisers run on one thread. A parallel refinement that reaches MaximumNumberOfVertices is
  /// done again on one thread (a warning says so): the mesh is then the sequential run's.
  vtkSetMacro(Threads, int); // >= 0
  vtkGetMacro(Threads, int);
  ///@}

  ///@{
  /// Wall-clock seconds for the whole run (every phase): reaching it fails the update with an
  /// error naming the phase and how far it got (vertices, tetrahedra, seconds); the output then
  /// holds no cells, only those statistics (StatisticNames/StatisticValues). 0 = automatic (the
  /// default: 10 minutes), -1 = none. Criteria that cannot be met within it, or within 10 times
  /// MaximumNumberOfVertices, are refused before meshing with the numbers (checkMeshSize).
  vtkSetMacro(TimeLimit, double); // -1 to 1e9
  vtkGetMacro(TimeLimit, double);
  ///@}

protected:
  vtkFeaturePreservingTetrahedralizer();
  ~vtkFeaturePreservingTetrahedralizer() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Set by the constructor from the core's defaults (omesh::MesherOptions).
  int FeatureStrategy;
  int Features;
  double CreaseAngle;
  bool ResampleFeatureLines;
  double SliverAngle;
  double InterfaceSliverAngle;
  double PickingSliverAngle;
  double FacetAngle;
  double FacetSize;
  double FacetDistance;
  double CellSize;
  double CellRadiusEdgeRatio;
  double EdgeSize;
  bool Perturb;
  bool Exude;
  bool ImproveAngles;
  double ImprovementMinAngle;
  double ImprovementMaxAngle;
  double PerturbationFailuresPerBound;
  double ExudationSliverBound;
  double PerturbationStepsPerVertex;
  double ExudationStepsPerCell;
  double OptimisationTimeLimit;
  int ElementOrder;
  int Seed;
  vtkIdType MaximumNumberOfVertices;
  int Threads;
  double TimeLimit;

private:
  vtkFeaturePreservingTetrahedralizer(const vtkFeaturePreservingTetrahedralizer&) = delete;
  void operator=(const vtkFeaturePreservingTetrahedralizer&) = delete;

  // RequestData: the inputs converted to the core's, the core's pipeline (runMeshingPipeline,
  // MeshingPipeline.h), its result converted back.
  struct PipelineCall; // the core's inputs, options and result (core types: defined in the .cxx)
  void CheckProperties() const;
  /// The global criteria as the properties spell them (-1: the default; other negatives refused).
  std::array<double, 6> GlobalCriteria() const;
  void SetUpOptions(PipelineCall& run);
  void GatherInputs(vtkInformationVector** inputVector, PipelineCall& run);
  void AssembleOutputs(PipelineCall& run, vtkInformationVector* outputVector);

  std::map<int, std::array<double, 6>> MaterialCriteria;
  int MaterialCriteriaRows = 0;
  std::string MaterialCriteriaError; // first bad row given to AddMaterialCriteria
};

#endif
