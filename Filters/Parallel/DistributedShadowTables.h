/**
 * @file DistributedShadowTables.h
 * @brief Filtered Volumetric Shadows over the processes of a parallel run, without assembling
 * the input: each process builds its summed-area tables over its block grown by a shadow's
 * reach (windows of the whole tables), and the processes whose windows share columns toward a
 * light send each other the sums of the cells beyond them.
 */
#ifndef DistributedShadowTables_h
#define DistributedShadowTables_h

#include "FilteredShadowsKernel.h"
#include "RayMarchKernel.h"
#include "SummedAreaTableKernel.h"
#include "VolIllumParallelModule.h"

#include <vector>

class vtkMultiProcessController;

namespace volillum
{

/**
 * The grown block of a process whose extent of the illumination grid `target` is `own`: the
 * data points (indices in the whole data grid `piece.Whole`) whose cells its tables hold,
 * `tables` (the centres of its block's cells and the data points around its extent, grown by
 * `reach` and a spacing), and those the tables read, `wanted` (grown by `margin` and a spacing
 * more: the radial half cell of a spherical table, 0 without).
 */
VOLILLUMPARALLEL_EXPORT void GrownBlock(const GridGeometry& target, const VolumePiece& piece,
  const int own[6], double reach, double margin, int tables[6], int wanted[6]);

/**
 * Collective: what each process's table windows lack of the whole tables beyond their cells,
 * from the processes whose windows share columns with them (the cells of one that lie beyond
 * the other's grown block go to the other, which adds them up in the order of the processes).
 * The tables read are those of `lookups` (a Cartesian table's axis and the end toward the
 * light) and `sphericalLookups` (a spherical table's columns toward the light), the same on
 * every process (those of the first process with a piece: the others have no lights).
 * `tableExtents`: every process's `tables` extent of GrownBlock (GatherExtents); `tables` and
 * `spherical`: this process's windows. Returns the bytes this process sent.
 */
VOLILLUMPARALLEL_EXPORT long long ShareCellsBeyond(vtkMultiProcessController* controller,
  const VolumePiece& piece, const std::vector<ShadowLookup>& lookups,
  const std::vector<SphericalLookup>& sphericalLookups, int channels,
  const std::vector<int>& tableExtents, std::vector<CartesianSAT>& tables,
  std::vector<SphericalSAT>& spherical);

}

#endif
