/**
 * @class vtkAdaptiveTetrahedralMesh
 * @brief Tetrahedral mesh of the region of an image above an iso-value (CGAL Mesh_3).
 *
 * Input: a 3D vtkImageData with point scalars (a scalar field or a label image). The
 * region where the trilinearly interpolated scalar is at least IsoValue is meshed with
 * CGAL's Mesh_3 (Delaunay refinement): tetrahedra no larger than CellSize (circumradius),
 * boundary facets within FacetDistance of the iso-surface, so cells are small where the
 * surface curves and large inside. Output: a vtkUnstructuredGrid of tetrahedra with the
 * input's scalars interpolated at its points. An image without scalars, a 2D image, or an
 * iso-value no point reaches is reported with vtkErrorMacro and gives an empty output.
 */
#ifndef vtkAdaptiveTetrahedralMesh_h
#define vtkAdaptiveTetrahedralMesh_h

#include "IlluminationFilterSupport.h" // for the shared limits
#include "VolIllumMeshingModule.h"
#include "vtkUnstructuredGridAlgorithm.h"

class VOLILLUMMESHING_EXPORT vtkAdaptiveTetrahedralMesh : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkAdaptiveTetrahedralMesh* New();
  vtkTypeMacro(vtkAdaptiveTetrahedralMesh, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Most tetrahedra a Cell Size may ask for (estimated from the region's volume).
  static constexpr double MaximumTetrahedra = volillum::MaximumTetrahedra;

  ///@{
  /** Scalar value bounding the meshed region (inside: at least this). Default 0.5. */
  vtkSetMacro(IsoValue, double);
  vtkGetMacro(IsoValue, double);
  ///@}

  ///@{
  /** Largest tetrahedron circumradius, in world units (0: 4 x the mean spacing). */
  vtkSetClampMacro(CellSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(CellSize, double);
  ///@}

  ///@{
  /** Largest distance of boundary facets from the iso-surface (0: half the mean spacing). */
  vtkSetClampMacro(FacetDistance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FacetDistance, double);
  ///@}

protected:
  vtkAdaptiveTetrahedralMesh();
  ~vtkAdaptiveTetrahedralMesh() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double IsoValue = 0.5;
  double CellSize = 0.0;
  double FacetDistance = 0.0;

private:
  vtkAdaptiveTetrahedralMesh(const vtkAdaptiveTetrahedralMesh&) = delete;
  void operator=(const vtkAdaptiveTetrahedralMesh&) = delete;
};

#endif
