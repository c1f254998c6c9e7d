#include "IlluminationTetrahedra.h"

#include "IlluminationFilterSupport.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace volillum
{

//------------------------------------------------------------------------------
void CellWithMappedPoints(
  vtkUnstructuredGrid* grid, vtkIdType c, const std::vector<vtkIdType>* map, vtkIdList* cell)
{
  const auto mapped = [&](vtkIdType k)
  {
    const vtkIdType id = cell->GetId(k);
    if (id >= 0 && id < grid->GetNumberOfPoints())
    {
      cell->SetId(k, (*map)[id]);
    }
  };
  if (grid->GetCellType(c) == VTK_POLYHEDRON)
  {
    grid->GetFaceStream(c, cell);
    for (vtkIdType face = 1; map && face < cell->GetNumberOfIds(); face += cell->GetId(face) + 1)
    {
      for (vtkIdType k = face + 1; k <= face + cell->GetId(face) && k < cell->GetNumberOfIds(); ++k)
      {
        mapped(k);
      }
    }
    return;
  }
  grid->GetCellPoints(c, cell);
  for (vtkIdType k = 0; map && k < cell->GetNumberOfIds(); ++k)
  {
    mapped(k);
  }
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> SplitIntoTetrahedra(
  vtkUnstructuredGrid* grid, std::string& error)
{
  bool onlyTetrahedra = true;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells() && onlyTetrahedra; ++c)
  {
    onlyTetrahedra = grid->GetCellType(c) == VTK_TETRA;
  }
  if (onlyTetrahedra)
  {
    return grid;
  }
  // How a cell splits depends on the order of its points' ids (vtkOrderedTriangulator): the
  // cells are split with the points numbered in the order of their coordinates, so that a
  // cell splits alike whatever the numbering of the grid that holds it (the pieces of a
  // parallel run, D3's among them, and a serial run).
  const vtkIdType n = grid->GetNumberOfPoints();
  std::vector<std::array<double, 3>> places(static_cast<size_t>(n));
  for (vtkIdType p = 0; p < n; ++p)
  {
    grid->GetPoint(p, places[p].data());
  }
  std::vector<vtkIdType> order(static_cast<size_t>(n)), rank(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
    [&places](vtkIdType a, vtkIdType b) { return places[a] < places[b]; });
  vtkNew<vtkPoints> sorted;
  sorted->SetDataTypeToDouble();
  sorted->SetNumberOfPoints(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    rank[order[k]] = k;
    sorted->SetPoint(k, places[order[k]].data());
  }
  vtkNew<vtkUnstructuredGrid> renumbered;
  renumbered->SetPoints(sorted);
  renumbered->AllocateEstimate(grid->GetNumberOfCells(), 8);
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    const int type = grid->GetCellType(c);
    CellWithMappedPoints(grid, c, &rank, cell);
    renumbered->InsertNextCell(type, cell);
  }
  renumbered->GetCellData()->ShallowCopy(grid->GetCellData());
  vtkNew<vtkDataSetTriangleFilter> split;
  split->TetrahedraOnlyOn();
  split->SetInputData(renumbered);
  split->Update();
  vtkUnstructuredGrid* pieces = split->GetOutput();
  if (pieces->GetNumberOfPoints() != n)
  {
    error = "Splitting the cells into tetrahedra changed the points; cannot light this grid.";
    return nullptr;
  }
  // The tetrahedra over the grid's own points and numbering.
  auto tetrahedra = vtkSmartPointer<vtkUnstructuredGrid>::New();
  tetrahedra->SetPoints(grid->GetPoints());
  tetrahedra->AllocateEstimate(pieces->GetNumberOfCells(), 4);
  for (vtkIdType c = 0; c < pieces->GetNumberOfCells(); ++c)
  {
    pieces->GetCellPoints(c, cell);
    for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
    {
      cell->SetId(k, order[cell->GetId(k)]);
    }
    tetrahedra->InsertNextCell(pieces->GetCellType(c), cell);
  }
  tetrahedra->GetCellData()->ShallowCopy(pieces->GetCellData());
  tetrahedra->GetPointData()->ShallowCopy(grid->GetPointData()); // global ids included
  return tetrahedra;
}

//------------------------------------------------------------------------------
std::vector<long long> TetrahedronPointIds(vtkUnstructuredGrid* tetrahedra)
{
  std::vector<long long> tets;
  tets.reserve(4 * static_cast<size_t>(tetrahedra->GetNumberOfCells()));
  auto cells = vtk::TakeSmartPointer(tetrahedra->GetCells()->NewIterator());
  vtkIdType c = 0;
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    cells->GetCurrentCell(n, ids);
    if (tetrahedra->GetCellType(c) == VTK_TETRA && n == 4)
    {
      tets.insert(tets.end(), ids, ids + 4);
    }
  }
  return tets;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> PieceTetrahedra(
  vtkSmartPointer<vtkUnstructuredGrid> piece, std::string& error)
{
  if (!piece)
  {
    return nullptr;
  }
  error = volillum::CheckPointIds(piece);
  piece = error.empty() ? SplitIntoTetrahedra(piece, error) : nullptr;
  if (!error.empty() || (piece->GetNumberOfCells() == 0 && piece->GetNumberOfPoints() == 0))
  {
    return nullptr;
  }
  return piece;
}

}
