/**
 * @class vtkTetrahedralizeSurface
 * @brief Quality tetrahedral mesh of the inside of a closed triangulated surface (TetGen).
 *
 * Input: a closed vtkPolyData surface (triangles or other polygons, which are split into
 * triangles). Output: a vtkUnstructuredGrid of tetrahedra filling it, made by TetGen with
 * a radius-edge ratio bound (RadiusEdgeRatio) and optionally a maximum tetrahedron volume
 * (MaximumVolume). Open surfaces (an edge not shared by exactly two triangles),
 * self-intersecting or flat ones, surfaces with non-finite points and a MaximumVolume that
 * would make more than MaximumTetrahedra tetrahedra are reported with vtkErrorMacro and
 * give an empty output.
 */
#ifndef vtkTetrahedralizeSurface_h
#define vtkTetrahedralizeSurface_h

#include "IlluminationFilterSupport.h" // for the shared limits
#include "VolIllumMeshingModule.h"
#include "vtkUnstructuredGridAlgorithm.h"

class VOLILLUMMESHING_EXPORT vtkTetrahedralizeSurface : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkTetrahedralizeSurface* New();
  vtkTypeMacro(vtkTetrahedralizeSurface, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** Largest tetrahedron volume (0, the default: no limit). */
  vtkSetClampMacro(MaximumVolume, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumVolume, double);
  ///@}

  /// Most tetrahedra a MaximumVolume may ask for (enclosed volume / MaximumVolume).
  static constexpr double MaximumTetrahedra = volillum::MaximumTetrahedra;

  ///@{
  /** Bound on circumradius / shortest edge of every tetrahedron (TetGen's -q). Default 2. */
  vtkSetClampMacro(RadiusEdgeRatio, double, 1.1, 100.0);
  vtkGetMacro(RadiusEdgeRatio, double);
  ///@}

protected:
  vtkTetrahedralizeSurface();
  ~vtkTetrahedralizeSurface() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double MaximumVolume = 0.0;
  double RadiusEdgeRatio = 2.0;

private:
  vtkTetrahedralizeSurface(const vtkTetrahedralizeSurface&) = delete;
  void operator=(const vtkTetrahedralizeSurface&) = delete;
};

#endif
