#include "NeighborhoodBins.h"

#include "vtkCellData.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

namespace volillum
{
namespace neighborhood
{

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> CellsNear(
  vtkUnstructuredGrid* grid, const BinMask& mask, const unsigned char* bits, double depth)
{
  auto near = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  near->SetPoints(points);
  near->GetPointData()->CopyGlobalIdsOn();
  near->GetPointData()->CopyAllocate(grid->GetPointData());
  near->GetCellData()->CopyAllocate(grid->GetCellData());
  std::vector<vtkIdType> ids(static_cast<size_t>(grid->GetNumberOfPoints()), -1);
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    double bounds[6];
    grid->GetCellBounds(c, bounds);
    if (!mask.Meets(bits, bounds, depth))
    {
      continue;
    }
    grid->GetCellPoints(c, cell);
    for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
    {
      vtkIdType& id = ids[cell->GetId(k)];
      if (id < 0)
      {
        id = points->InsertNextPoint(grid->GetPoint(cell->GetId(k)));
        near->GetPointData()->CopyData(grid->GetPointData(), cell->GetId(k), id);
      }
      cell->SetId(k, id);
    }
    const vtkIdType added = near->InsertNextCell(grid->GetCellType(c), cell);
    near->GetCellData()->CopyData(grid->GetCellData(), c, added);
  }
  near->Squeeze();
  return near;
}

//------------------------------------------------------------------------------
std::array<double, 3> PointKey(vtkDataSet* grid, vtkIdType i, bool byId)
{
  std::array<double, 3> key = { 0.0, 0.0, 0.0 };
  if (byId)
  {
    key[0] = grid->GetPointData()->GetGlobalIds()->GetTuple1(i);
  }
  else
  {
    grid->GetPoint(i, key.data());
  }
  return key;
}

}
}
