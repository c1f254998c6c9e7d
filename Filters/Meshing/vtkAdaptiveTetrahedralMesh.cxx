#include "vtkAdaptiveTetrahedralMesh.h"

#include "IlluminationFilterSupport.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

vtkStandardNewMacro(vtkAdaptiveTetrahedralMesh);

namespace
{
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

// Trilinear interpolation of the image's scalars (component 0) at a world point; NaN
// outside the image.
double Interpolate(vtkImageData* image, vtkDataArray* scalars, const double p[3])
{
  int dims[3];
  double origin[3], spacing[3];
  image->GetDimensions(dims);
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  const int* extent = image->GetExtent();
  int i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    const double u = (p[a] - origin[a]) / spacing[a] - extent[2 * a];
    if (u < 0.0 || u > dims[a] - 1)
    {
      return std::nan("");
    }
    i0[a] = std::min(static_cast<int>(u), dims[a] - 2);
    f[a] = u - i0[a];
  }
  double value = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const int d[3] = { corner & 1, (corner >> 1) & 1, (corner >> 2) & 1 };
    double w = 1.0;
    for (int a = 0; a < 3; ++a)
    {
      w *= d[a] ? f[a] : 1.0 - f[a];
    }
    if (w != 0.0)
    {
      const vtkIdType id = (i0[0] + d[0]) +
        dims[0] * ((i0[1] + d[1]) + static_cast<vtkIdType>(dims[1]) * (i0[2] + d[2]));
      value += w * scalars->GetComponent(id, 0);
    }
  }
  return value;
}

// Why the image cannot be meshed at the iso-value, or nothing.
std::string CheckImage(vtkImageData* image, vtkDataArray* scalars, double iso)
{
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    return "the image must be 3D (at least 2 points along each axis)";
  }
  if (!scalars || scalars->GetNumberOfTuples() != image->GetNumberOfPoints())
  {
    return "the image has no numeric point scalars";
  }
  double range[2];
  scalars->GetRange(range, 0);
  std::ostringstream message;
  if (!(range[1] >= iso))
  {
    message << "no scalar reaches the iso-value " << iso << " (range " << range[0] << " .. "
            << range[1] << ")";
    return message.str();
  }
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  for (int a = 0; a < 3; ++a)
  {
    if (!(spacing[a] > 0.0) || !std::isfinite(spacing[a]) ||
      !(std::abs(origin[a]) <= volillum::MaximumCoordinate))
    {
      message << "the image's spacing must be positive and finite and its origin within +-"
              << volillum::MaximumCoordinate;
      return message.str();
    }
  }
  const double smallest = std::min({ spacing[0], spacing[1], spacing[2] });
  const double largest = std::max({ spacing[0], spacing[1], spacing[2] });
  if (largest > 1e6 * smallest)
  {
    message << "the image's spacings differ by more than a factor of 1e6 (" << spacing[0] << ", "
            << spacing[1] << ", " << spacing[2] << ")";
    return message.str();
  }
  return std::string();
}

// The region of the unit-scale image where the scalars reach the iso-value, meshed by CGAL
// with cells and facets of the given sizes (unit scale); false with a message on failure.
bool MeshRegion(vtkImageData* image, vtkDataArray* scalars, double iso, double cellSize,
  double facetDistance, Complex& complex, std::string& error)
{
  double bounds[6];
  image->GetBounds(bounds);
  // Negative inside: the scalar above the iso-value; positive outside the image.
  std::function<double(const Point&)> inside = [&](const Point& q)
  {
    const double p[3] = { q.x(), q.y(), q.z() };
    const double v = Interpolate(image, scalars, p);
    return std::isnan(v) ? 1.0 : iso - v;
  };
  const Point centre(
    0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5]));
  double radius2 = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double half =
      0.5 * (bounds[2 * a + 1] - bounds[2 * a]) + 1.0; // one (unit) cell of margin
    radius2 += half * half;
  }
  namespace params = CGAL::parameters;
  Domain domain = Domain::create_implicit_mesh_domain(
    inside, Kernel::Sphere_3(centre, radius2), params::relative_error_bound = 1e-6);
  Criteria criteria(params::facet_angle = 25, params::facet_size = cellSize,
    params::facet_distance = facetDistance, params::cell_radius_edge_ratio = 3,
    params::cell_size = cellSize);
  try
  {
    complex =
      CGAL::make_mesh_3<Complex>(domain, criteria, params::no_perturb(), params::no_exude());
  }
  catch (const std::exception& e)
  {
    error = std::string("CGAL failed (") + e.what() + ")";
    return false;
  }
  return true;
}

// The tetrahedra of the complex as a grid with the image's scalars at its points, mapped from
// the unit-scale image back to the input's coordinates (origin, mean spacing); false when
// there are none.
bool ToGrid(const Complex& complex, vtkImageData* image, vtkDataArray* scalars, double iso,
  const double origin[3], double mean, vtkUnstructuredGrid* output)
{
  const Triangulation& tr = complex.triangulation();
  std::map<Triangulation::Vertex_handle, vtkIdType> ids;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> cells;
  for (auto c = complex.cells_in_complex_begin(); c != complex.cells_in_complex_end(); ++c)
  {
    vtkIdType tet[4];
    for (int i = 0; i < 4; ++i)
    {
      const auto v = c->vertex(i);
      auto found = ids.find(v);
      if (found == ids.end())
      {
        const auto& wp = tr.point(c, i);
        found = ids.emplace(v, points->InsertNextPoint(wp.x(), wp.y(), wp.z())).first;
      }
      tet[i] = found->second;
    }
    cells->InsertNextCell(4, tet);
  }
  if (cells->GetNumberOfCells() == 0)
  {
    return false;
  }
  // The input's scalars at the mesh points, which then go back to the input's coordinates.
  vtkSmartPointer<vtkDataArray> carried;
  carried.TakeReference(scalars->NewInstance());
  carried->SetName(scalars->GetName() ? scalars->GetName() : "Scalars");
  carried->SetNumberOfComponents(1);
  carried->SetNumberOfTuples(points->GetNumberOfPoints());
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double p[3];
    points->GetPoint(i, p);
    const double v = Interpolate(image, scalars, p);
    carried->SetTuple1(i, std::isnan(v) ? iso : v);
    points->SetPoint(i, origin[0] + mean * p[0], origin[1] + mean * p[1], origin[2] + mean * p[2]);
  }
  output->SetPoints(points);
  output->SetCells(VTK_TETRA, cells);
  output->GetPointData()->SetScalars(carried);
  return true;
}
}

//------------------------------------------------------------------------------
vtkAdaptiveTetrahedralMesh::vtkAdaptiveTetrahedralMesh()
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
int vtkAdaptiveTetrahedralMesh::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptiveTetrahedralMesh::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* image = vtkImageData::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  output->Initialize();
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector);
  if (!scalars)
  {
    scalars = image->GetPointData()->GetScalars();
  }
  const std::string problem = CheckImage(image, scalars, this->IsoValue);
  if (!problem.empty())
  {
    vtkErrorMacro("Cannot mesh: " << problem << ".");
    return 1;
  }
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  const double mean = (spacing[0] + spacing[1] + spacing[2]) / 3.0;
  const double cellSize = this->CellSize > 0.0 ? this->CellSize : 4.0 * mean;
  const double facetDistance = this->FacetDistance > 0.0 ? this->FacetDistance : 0.5 * mean;
  // Tetrahedra of circumradius cellSize have a volume of about cellSize^3 / 2: bound the
  // count by the region's volume (the points at or above the iso-value) before meshing.
  long long pointsInside = 0;
  for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i)
  {
    pointsInside += scalars->GetComponent(i, 0) >= this->IsoValue ? 1 : 0;
  }
  const double regionVolume =
    static_cast<double>(pointsInside) * spacing[0] * spacing[1] * spacing[2];
  const double estimate = regionVolume / (0.5 * cellSize * cellSize * cellSize);
  if (!(estimate <= MaximumTetrahedra))
  {
    vtkErrorMacro("Cannot mesh: a Cell Size of " << cellSize << " would make about " << estimate
                                                 << " tetrahedra, more than the limit of "
                                                 << MaximumTetrahedra << "; raise Cell Size.");
    return 1;
  }

  // CGAL meshes the image at unit scale (origin 0, mean spacing 1; the orientation is not
  // used): its tolerances are absolute enough to fail on extreme coordinates. The mesh
  // points are mapped back at the end.
  vtkNew<vtkImageData> unit;
  unit->ShallowCopy(image);
  unit->SetOrigin(0.0, 0.0, 0.0);
  unit->SetSpacing(spacing[0] / mean, spacing[1] / mean, spacing[2] / mean);
  unit->SetDirectionMatrix(1, 0, 0, 0, 1, 0, 0, 0, 1);
  this->UpdateProgress(0.1);
  Complex complex;
  std::string error;
  if (!MeshRegion(
        unit, scalars, this->IsoValue, cellSize / mean, facetDistance / mean, complex, error))
  {
    vtkErrorMacro("Cannot mesh: " << error << ".");
    return 1;
  }
  this->UpdateProgress(0.9);
  if (!ToGrid(complex, unit, scalars, this->IsoValue, origin, mean, output))
  {
    vtkErrorMacro("Cannot mesh: CGAL produced no tetrahedra (region too thin for CellSize?).");
    output->Initialize();
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkAdaptiveTetrahedralMesh::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IsoValue: " << this->IsoValue << "\n";
  os << indent << "CellSize: " << this->CellSize << "\n";
  os << indent << "FacetDistance: " << this->FacetDistance << "\n";
}
