// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the module (uses core types): the core's tetrahedral mesh as the tetrahedralizer's
// three VTK outputs, and the statistics' field-data arrays (also written for a failed run).
#pragma once

#include "FeatureSelection.h"
#include "QuadraticTets.h"
#include "ShapeSummary.h"
#include "TetMesh.h"

#include <vtkSmartPointer.h>

#include <map>
#include <string>
#include <vector>

class vtkDoubleArray;
class vtkFieldData;
class vtkPolyData;
class vtkUnstructuredGrid;

/// The cell arrays of the tetrahedra's shape (MinDihedralAngle, MaxDihedralAngle, RadiusEdgeRatio),
/// allocated when the mesher knows the output's size and written by its one measuring pass
/// (MesherOptions::shapeArrays): no pass of their own.
struct TetShapeCellArrays
{
  vtkSmartPointer<vtkDoubleArray> minDihedral, maxDihedral, radiusEdge;
  std::size_t tetrahedra = 0;

  /// New arrays of `n` values; their buffers, for summariseShapes.
  omesh::TetShapeArrays allocate(std::size_t n);
};

class TetMeshOutput
{
public:
  /// Port 0: tetrahedra positively oriented (10-node ones when `quadratic` is given), cell arrays
  /// Material, MinDihedralAngle, MaxDihedralAngle, RadiusEdgeRatio (and Defects when validated), point array
  /// Dimension, field data: statistics, warnings and `inputWarnings` (the ones --strict refuses).
  /// The shape arrays are `shapes`' when they were written for this mesh, else measured here.
  static void FillGrid(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh, const omesh::QuadraticTetMesh* quadratic,
    const std::vector<std::string>& inputWarnings, const TetShapeCellArrays* shapes = nullptr);
  /// Port 1: interface triangles on the grid's points, cell array Materials (the two sides).
  static void FillInterfaces(vtkPolyData* interfaces, const omesh::TetMesh& mesh, vtkUnstructuredGrid* grid);
  /// Port 2: the constrained segments as they stand in the mesh (cell arrays Present, InputSegment:
  /// the segment of `selection` the piece comes from, also after the mesher resampled them;
  /// Origin, 0 given, 1 found where the inputs meet, and Materials, the 4 materials a found piece
  /// separates: that segment's tags).
  static void FillSegments(vtkPolyData* segments, const omesh::TetMesh& mesh, const omesh::FeatureSelection& selection);
  /// The statistics as two field-data arrays, StatisticNames and StatisticValues.
  static void AddStatistics(vtkFieldData* fieldData, const std::map<std::string, double>& statistics);
  /// One more statistic in the arrays AddStatistics wrote (e.g. the time of this conversion).
  static void AddStatistic(vtkFieldData* fieldData, const std::string& name, double value);

private:
  /// Field array SeparatingFaces (FieldDataKeys.txt): the validity check's faces on the boundary
  /// or between materials, for the surface sets of the writers (Python's surfaces.py).
  static void AddSeparatingFaces(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh);
  static void AddTetrahedra(vtkUnstructuredGrid* grid, const omesh::TetMesh& mesh, const omesh::QuadraticTetMesh* quadratic,
    const TetShapeCellArrays* shapes);
  static void AddStrings(vtkFieldData* fieldData, const char* name, const std::vector<std::string>& strings);
};
