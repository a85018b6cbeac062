// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkOracleFeatureLines
 * @brief The feature lines that arise where the oracle's inputs meet, found with oracle queries.
 *
 * Input: the output of vtkHierarchicalOracle (or one domain). Output: vtkPolyData polylines, one
 * cell per curve: cut rims (a cut domain crossing a surface or label-map interface), entry curves
 * (one input's surface entering another's material), triple lines of label maps and of mixed
 * inputs, and the creases of single inputs where they are seen (a box's edges, a finite
 * cylinder's rims, a surface's sharp edges above CreaseAngle; see omesh::findFeatureLines).
 * Vertices on the true curves (to 1e-10 of the oracle's diagonal), curves ending at one shared
 * vertex, corners kept. Cell data: Materials (4 components: the materials meeting along the curve,
 * ascending, -1 = outside, -2 = none), Triple (1 when three or more materials meet, 0 for a
 * crease between two) and Crease (1 for a crease of one input); point data
 * SmallAngle (degrees: the smallest angle between curves or chords at the vertex, 180 if none);
 * field data Warnings (curves meeting below 60 degrees, which threaten the mesher's termination).
 *
 * The curves are resampled as the tetrahedralizer's Features option does when MaximumSegmentLength
 * is 0 (the default): to the edge size of the criteria given here (else the facet size, else 1/40
 * of the oracle's diagonal).
 *
 * @sa vtkFeaturePreservingTetrahedralizer vtkHierarchicalOracle vtkFeatureEdges
 */
#ifndef vtkOracleFeatureLines_h
#define vtkOracleFeatureLines_h

#include "OracleMeshFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

class ORACLEMESHFILTERS_EXPORT vtkOracleFeatureLines : public vtkPolyDataAlgorithm
{
public:
  static vtkOracleFeatureLines* New();
  vtkTypeMacro(vtkOracleFeatureLines, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Chord length of the resampled curves; 0 (default) = EdgeSize, else FacetSize, else 1/40 of
  /// the oracle's diagonal (what the tetrahedralizer's automatic features use).
  vtkSetMacro(MaximumSegmentLength, double);
  vtkGetMacro(MaximumSegmentLength, double);
  ///@}

  ///@{
  /// The tetrahedralizer's criteria the curves are resampled for (0 = no bound), as there.
  vtkSetMacro(EdgeSize, double);
  vtkGetMacro(EdgeSize, double);
  vtkSetMacro(FacetSize, double);
  vtkGetMacro(FacetSize, double);
  vtkSetMacro(FacetDistance, double);
  vtkGetMacro(FacetDistance, double);
  ///@}

  ///@{
  /// Step of the search grid; 0 (default) = half the chord length. Curves shorter than about this
  /// or closer to each other can be missed.
  vtkSetMacro(Spacing, double);
  vtkGetMacro(Spacing, double);
  ///@}

  ///@{
  /// Creases of single inputs are kept where their faces' normals differ by more than this
  /// (degrees; default 60, the core's omesh::kDefaultCreaseAngle): a surface's sharp edges, a box's
  /// edges and a cylinder's rims (90) below 90. 180 = no creases. Out of range (0 or less, above
  /// 180, NaN): the next update fails with an error naming the property.
  vtkSetMacro(CreaseAngle, double);
  vtkGetMacro(CreaseAngle, double);
  ///@}

protected:
  vtkOracleFeatureLines();
  ~vtkOracleFeatureLines() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MaximumSegmentLength = 0.0;
  double Spacing = 0.0;
  double CreaseAngle;
  double EdgeSize;
  double FacetSize;
  double FacetDistance;

private:
  vtkOracleFeatureLines(const vtkOracleFeatureLines&) = delete;
  void operator=(const vtkOracleFeatureLines&) = delete;
};

#endif
