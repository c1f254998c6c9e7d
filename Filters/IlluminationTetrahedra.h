/**
 * @file IlluminationTetrahedra.h
 * @brief The tetrahedra the unstructured solver lights, made from an input grid's cells: split
 * alike whatever the numbering of the grid that holds a cell (a serial run, the pieces of a
 * parallel one).
 */
#ifndef IlluminationTetrahedra_h
#define IlluminationTetrahedra_h

#include "VolIllumFiltersModule.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <string>
#include <vector>

class vtkIdList;
class vtkUnstructuredGrid;

namespace volillum
{

/// The point ids of cell c of grid (a polyhedron's face stream: per face its number of
/// points, then the points), each id of a point of the grid replaced by its entry in `map`
/// when given (others are left as they are).
VOLILLUMFILTERS_EXPORT void CellWithMappedPoints(
  vtkUnstructuredGrid* grid, vtkIdType c, const std::vector<vtkIdType>* map, vtkIdList* cell);

/// The tetrahedra of grid: grid itself when all its cells are tetrahedra, else
/// vtkDataSetTriangleFilter's split of its 3D cells (the same points, the arrays passed on);
/// nullptr with the reason in error when the split changed the points.
VOLILLUMFILTERS_EXPORT vtkSmartPointer<vtkUnstructuredGrid> SplitIntoTetrahedra(
  vtkUnstructuredGrid* grid, std::string& error);

/// The point ids of the tetrahedra of `tetrahedra`, 4 a tetrahedron (its other cells left out).
VOLILLUMFILTERS_EXPORT std::vector<long long> TetrahedronPointIds(vtkUnstructuredGrid* tetrahedra);

/// A piece's tetrahedra (SplitIntoTetrahedra), nullptr when it has none to light (points in no
/// 3D cell are lit as serially) or, with the reason in error, cannot be split.
VOLILLUMFILTERS_EXPORT vtkSmartPointer<vtkUnstructuredGrid> PieceTetrahedra(
  vtkSmartPointer<vtkUnstructuredGrid> piece, std::string& error);

}

#endif
