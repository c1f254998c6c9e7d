#include "vtkTetrahedralizeSurface.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#define TETLIBRARY
#include <tetgen.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkTetrahedralizeSurface);

namespace
{
// Triangles of the input's polygons (fans), or an empty list with a message.
bool Triangles(
  vtkPolyData* input, std::vector<std::array<vtkIdType, 3>>& triangles, std::string& error)
{
  vtkCellArray* polys = input->GetPolys();
  if (!polys || polys->GetNumberOfCells() == 0)
  {
    error = "the input has no polygons; a closed triangulated surface is needed";
    return false;
  }
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      triangles.push_back({ { ids[0], ids[k], ids[k + 1] } });
    }
  }
  return true;
}

// True when every edge is shared by exactly two triangles.
bool Closed(const std::vector<std::array<vtkIdType, 3>>& triangles)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> edges;
  for (const auto& t : triangles)
  {
    for (int e = 0; e < 3; ++e)
    {
      const vtkIdType a = t[e], b = t[(e + 1) % 3];
      ++edges[{ std::min(a, b), std::max(a, b) }];
    }
  }
  return std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}
}

//------------------------------------------------------------------------------
vtkTetrahedralizeSurface::vtkTetrahedralizeSurface() = default;

//------------------------------------------------------------------------------
int vtkTetrahedralizeSurface::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
bool Finite(vtkPolyData* surface)
{
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    const double* p = surface->GetPoint(i);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      return false;
    }
  }
  return true;
}

// Volume enclosed by a closed triangulated surface (divergence theorem; the sign follows
// the orientation).
double EnclosedVolume(vtkPolyData* surface, const std::vector<std::array<vtkIdType, 3>>& triangles)
{
  double volume = 0.0;
  for (const auto& t : triangles)
  {
    double a[3], b[3], c[3], bc[3];
    surface->GetPoint(t[0], a);
    surface->GetPoint(t[1], b);
    surface->GetPoint(t[2], c);
    vtkMath::Cross(b, c, bc);
    volume += vtkMath::Dot(a, bc) / 6.0;
  }
  return volume;
}

// Why TetGen cannot take the closed surface (TetGen aborts the process on non-finite or flat
// input), or nothing; volume is set to the volume it encloses.
std::string CheckSurface(
  vtkPolyData* input, const std::vector<std::array<vtkIdType, 3>>& triangles, double& volume)
{
  double bounds[6];
  input->GetBounds(bounds);
  double diagonal = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    diagonal += (bounds[2 * a + 1] - bounds[2 * a]) * (bounds[2 * a + 1] - bounds[2 * a]);
  }
  diagonal = std::sqrt(diagonal);
  if (!std::isfinite(diagonal) || !Finite(input))
  {
    return "the surface has points that are not finite numbers";
  }
  volume = std::abs(EnclosedVolume(input, triangles));
  if (!(volume > 1e-9 * diagonal * diagonal * diagonal))
  {
    return "the surface encloses no volume (it is flat)";
  }
  return std::string();
}

// The surface as TetGen's piecewise-linear complex: its points and one triangle per facet.
void ToTetGen(
  vtkPolyData* input, const std::vector<std::array<vtkIdType, 3>>& triangles, tetgenio& in)
{
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(input->GetNumberOfPoints());
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    input->GetPoint(i, in.pointlist + 3 * i);
  }
  in.numberoffacets = static_cast<int>(triangles.size());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  in.facetmarkerlist = nullptr;
  for (int f = 0; f < in.numberoffacets; ++f)
  {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k)
    {
      facet.polygonlist[0].vertexlist[k] = static_cast<int>(triangles[f][k]);
    }
  }
}

// The number of triangles of the complex that intersect others (d: detect intersecting facets
// only, Q: quiet), or -1 when TetGen rejects it.
long long IntersectingTriangles(tetgenio& in)
{
  tetgenio check;
  char detect[] = "dQ";
  try
  {
    tetrahedralize(detect, &in, &check);
  }
  catch (int)
  {
    return -1;
  }
  return check.numberoftrifaces;
}

// TetGen's tetrahedra as the grid's points and cells.
void ToGrid(const tetgenio& out, vtkUnstructuredGrid* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(out.numberofpoints);
  for (int i = 0; i < out.numberofpoints; ++i)
  {
    points->SetPoint(i, out.pointlist + 3 * i);
  }
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(out.numberoftetrahedra, 4 * out.numberoftetrahedra);
  for (int t = 0; t < out.numberoftetrahedra; ++t)
  {
    const int* tet = out.tetrahedronlist + t * out.numberofcorners;
    const vtkIdType ids[4] = { tet[0], tet[1], tet[2], tet[3] };
    cells->InsertNextCell(4, ids);
  }
  output->SetPoints(points);
  output->SetCells(VTK_TETRA, cells);
}
}

//------------------------------------------------------------------------------
int vtkTetrahedralizeSurface::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  output->Initialize();
  std::vector<std::array<vtkIdType, 3>> triangles;
  std::string error;
  if (!input || input->GetNumberOfPoints() < 4 || !Triangles(input, triangles, error))
  {
    vtkErrorMacro("Cannot tetrahedralize: "
      << (error.empty() ? "the input needs a closed surface with at least 4 points" : error)
      << ".");
    return 1;
  }
  if (!Closed(triangles))
  {
    vtkErrorMacro("Cannot tetrahedralize: the surface is open (an edge is not shared by "
                  "exactly two polygons). Close it first, for example with Fill Holes.");
    return 1;
  }
  double volume = 0.0;
  const std::string problem = CheckSurface(input, triangles, volume);
  if (!problem.empty())
  {
    vtkErrorMacro("Cannot tetrahedralize: " << problem << ".");
    return 1;
  }
  if (this->MaximumVolume > 0.0 && volume / this->MaximumVolume > MaximumTetrahedra)
  {
    vtkErrorMacro("Cannot tetrahedralize: a Maximum Volume of "
      << this->MaximumVolume << " would make about " << volume / this->MaximumVolume
      << " tetrahedra, more than the limit of " << MaximumTetrahedra << "; raise Maximum Volume.");
    return 1;
  }

  tetgenio in, out;
  ToTetGen(input, triangles, in);
  // TetGen cannot recover from a self-intersecting surface: look for intersections first.
  const long long intersecting = IntersectingTriangles(in);
  if (intersecting < 0)
  {
    vtkErrorMacro("Cannot tetrahedralize: TetGen rejected the surface.");
    return 1;
  }
  if (intersecting > 0)
  {
    vtkErrorMacro("Cannot tetrahedralize: the surface intersects itself ("
      << intersecting << " intersecting triangles).");
    return 1;
  }
  // p: the input is a piecewise-linear complex; q: radius-edge bound; a: volume bound;
  // Q: quiet.
  std::ostringstream switches;
  switches << "pq" << this->RadiusEdgeRatio;
  if (this->MaximumVolume > 0.0)
  {
    switches << "a" << this->MaximumVolume;
  }
  switches << "Q";
  std::string text = switches.str();
  try
  {
    tetrahedralize(&text[0], &in, &out);
  }
  catch (int code)
  {
    vtkErrorMacro("TetGen could not tetrahedralize the surface ("
      << (code == 3                   ? "it intersects itself"
             : code == 1              ? "out of memory"
             : code == 4 || code == 5 ? "features too small or too close for its tolerance"
                                      : "invalid input")
      << ", code " << code << ").");
    output->Initialize();
    return 1;
  }

  ToGrid(out, output);
  return 1;
}

//------------------------------------------------------------------------------
void vtkTetrahedralizeSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumVolume: " << this->MaximumVolume << "\n";
  os << indent << "RadiusEdgeRatio: " << this->RadiusEdgeRatio << "\n";
}
