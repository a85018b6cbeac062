// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class vtkImplicitDomain
 * @brief A VTK implicit function (plane, box, sphere, cylinder) as an oracle domain (a source).
 *
 * Inside is where the function is <= 0 (VTK's convention: a vtkPlane contains the side its normal
 * points away from). The function's linear Transform is honoured (ParaView's box widget uses it).
 * vtkCylinder is infinite; a positive Height caps it symmetrically about its Center (a screw).
 * A cylinder whose Transform is a rotation (ParaView's Cylinder keeps its axis that way) is reduced
 * to one plain centre and axis in world coordinates, and every cylinder's unit axis is rounded to
 * multiples of 2^-30 per component, so the same cylinder given either way is the same domain bit
 * for bit (see describeCylinder in the .cxx).
 * Unbounded shapes (planes, infinite cylinders) may only be cuts: SetCut(true) (Cut is off by default, as for
 * every domain and in scene files). The output is a tessellation of
 * the shape's boundary inside DisplayBounds, for display only, with the domain description in its
 * field data.
 *
 * @sa vtkSphereDomain vtkSingleMaterialDomain vtkHierarchicalOracle vtkImplicitFunction
 */
#ifndef vtkImplicitDomain_h
#define vtkImplicitDomain_h

#include "OracleMeshFiltersModule.h"

#include "vtkSingleMaterialDomain.h"

class vtkImplicitFunction;

class ORACLEMESHFILTERS_EXPORT vtkImplicitDomain : public vtkSingleMaterialDomain
{
public:
  static vtkImplicitDomain* New();
  vtkTypeMacro(vtkImplicitDomain, vtkSingleMaterialDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkMTimeType GetMTime() override;

  ///@{
  /// The shape: a vtkPlane, vtkBox, vtkSphere or vtkCylinder (subclasses such as ParaView's
  /// vtkPVPlane/vtkPVBox included). Other functions are rejected with an error.
  void SetImplicitFunction(vtkImplicitFunction* f);
  vtkGetObjectMacro(ImplicitFunction, vtkImplicitFunction);
  ///@}

  ///@{
  /// Cylinders only: length along the axis, centred on the cylinder's Center; 0 = infinite.
  /// Negative or not finite: an error at the next update.
  vtkSetMacro(Height, double);
  vtkGetMacro(Height, double);
  ///@}

  ///@{
  /// Region where the shape is drawn (display only). When empty (min > max, the default) bounded
  /// shapes use their own bounds and planes a 100-unit cube around the plane's origin.
  vtkSetVector6Macro(DisplayBounds, double);
  vtkGetVector6Macro(DisplayBounds, double);
  ///@}

  ///@{
  /// Samples per axis used to draw the shape. Default 48.
  vtkSetClampMacro(DisplayResolution, int, 4, 512);
  vtkGetMacro(DisplayResolution, int);
  ///@}

protected:
  vtkImplicitDomain();
  ~vtkImplicitDomain() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkImplicitFunction* ImplicitFunction = nullptr;
  double Height = 0.0;
  double DisplayBounds[6] = { 0, -1, 0, -1, 0, -1 };
  int DisplayResolution = 48;

private:
  vtkImplicitDomain(const vtkImplicitDomain&) = delete;
  void operator=(const vtkImplicitDomain&) = delete;
};

#endif
