#include "DistributedMesh.h"

#include "NeighborhoodGrid.h"
#include "vtkCommunicator.h"
#include "vtkIdList.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

//------------------------------------------------------------------------------
double MeanTetrahedronEdge(vtkMultiProcessController* controller, vtkUnstructuredGrid* tetrahedra)
{
  double edges[2] = { 0.0, 0.0 }, wholeEdges[2]; // sum of lengths, count (each tetrahedron's)
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; tetrahedra && c < tetrahedra->GetNumberOfCells(); ++c)
  {
    tetrahedra->GetCellPoints(c, cell);
    double x[4][3];
    for (int i = 0; i < 4; ++i)
    {
      tetrahedra->GetPoint(cell->GetId(i), x[i]);
    }
    for (int i = 0; i < 4; ++i)
    {
      for (int j = i + 1; j < 4; ++j)
      {
        edges[0] += std::sqrt(vtkMath::Distance2BetweenPoints(x[i], x[j]));
        edges[1] += 1.0;
      }
    }
  }
  controller->AllReduce(edges, wholeEdges, 2, vtkCommunicator::SUM_OP);
  return wholeEdges[1] == 0.0 ? -1.0 : wholeEdges[0] / wholeEdges[1];
}

//------------------------------------------------------------------------------
bool AgreeOnWholeMesh(vtkMultiProcessController* controller, TetrahedralMesh& mesh,
  const std::vector<unsigned char>& owned, std::string& error)
{
  double local[3] = { 0.0, 0.0, static_cast<double>(mesh.OwnTets) }, sums[3];
  for (int p = 0; p < mesh.NumberOfPoints(); ++p)
  {
    for (int k = mesh.EdgeOffsets[p]; owned[p] && k < mesh.EdgeOffsets[p + 1]; ++k)
    {
      const double* x = mesh.Points.data() + 3 * static_cast<size_t>(p);
      const double* y = mesh.Points.data() + 3 * static_cast<size_t>(mesh.EdgeNeighbors[k]);
      local[0] += std::sqrt(vtkMath::Distance2BetweenPoints(x, y));
      local[1] += 1.0;
    }
  }
  controller->AllReduce(local, sums, 3, vtkCommunicator::SUM_OP);
  double lows[3] = { mesh.Bounds[0], mesh.Bounds[2], mesh.Bounds[4] };
  double highs[3] = { mesh.Bounds[1], mesh.Bounds[3], mesh.Bounds[5] };
  double wholeLows[3], wholeHighs[3];
  controller->AllReduce(lows, wholeLows, 3, vtkCommunicator::MIN_OP);
  controller->AllReduce(highs, wholeHighs, 3, vtkCommunicator::MAX_OP);
  if (sums[2] == 0.0)
  {
    error = "Cannot light the grid: the mesh has no tetrahedron with a non-zero volume.";
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    mesh.Bounds[2 * a] = wholeLows[a];
    mesh.Bounds[2 * a + 1] = wholeHighs[a];
  }
  SetMeanEdgeLength(mesh, sums[0] / std::max(sums[1], 1.0));
  return true;
}

//------------------------------------------------------------------------------
bool ColorDistributedVertices(vtkMultiProcessController* controller,
  const NeighborhoodGrid& neighborhood, const TetrahedralMesh& mesh, VertexColoring& coloring,
  std::string& error)
{
  const std::vector<unsigned char>& computed = neighborhood.GetComputed();
  // Every round colours at least the first point of the global order still waiting (its
  // earlier neighbours have their colours), unless a point's colour never comes from the
  // process that holds it: a round that colours none on any process stops with an error
  // instead of waiting for ever.
  long long waitingBefore = -1;
  bool stuck = false;
  coloring = ColorVertices(mesh, &computed,
    [&](std::vector<int>& color)
    {
      neighborhood.Exchange(color.data(), 1);
      long long waiting = 0, all = 0;
      for (int p = 0; p < mesh.NumberOfPoints(); ++p)
      {
        waiting += computed[p] && color[p] < 0 ? 1 : 0;
      }
      controller->AllReduce(&waiting, &all, 1, vtkCommunicator::SUM_OP);
      stuck = all > 0 && all == waitingBefore;
      waitingBefore = all;
      return all > 0 && !stuck;
    });
  if (stuck)
  {
    error = "The pieces cannot be joined: a point a piece shares with another has no match "
            "there (seen with point global ids from Generate Global Ids).";
    return false;
  }
  // Every process scatters (and passes values) colour by colour: as many colours on all.
  int colors = coloring.NumberOfColors(), wholeColors = 0;
  controller->AllReduce(&colors, &wholeColors, 1, vtkCommunicator::MAX_OP);
  coloring.Offsets.resize(wholeColors + 1, coloring.Offsets.back());
  return true;
}

}
