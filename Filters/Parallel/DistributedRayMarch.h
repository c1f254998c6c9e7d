/**
 * @file DistributedRayMarch.h
 * @brief The ray-marched reference over the processes of a parallel run, without assembling
 * the input: each process marches the parts of every point's rays that cross its block, and
 * the products of the parts arrive at the process that holds the point.
 */
#ifndef DistributedRayMarch_h
#define DistributedRayMarch_h

#include "RayMarchKernel.h"
#include "VolIllumParallelModule.h"

#include <functional>
#include <vector>

class vtkMultiProcessController;

namespace volillum
{

/**
 * Collective: the illumination (3 floats a point, x fastest) of the points of this process's
 * extent of the illumination grid `target` into rgb, from the lights `on` (indices into
 * `lights`, the same on every process; `lights` is empty where the process has no block).
 * `volume` and `piece`: this process's block of the classification (no points for none);
 * `extents`: every process's extent (GatherExtents); `empty`: the block's empty blocks (may be
 * nullptr). `progress` is told the fraction of the points done.
 */
VOLILLUMPARALLEL_EXPORT void RayMarchDistributed(vtkMultiProcessController* controller,
  const ClassifiedVolume& volume, const VolumePiece& piece, const std::vector<LightState>& lights,
  const std::vector<size_t>& on, const GridGeometry& target, const std::vector<int>& extents,
  const RayMarchSettings& settings, const EmptyBlocks* empty, float* rgb,
  const std::function<void(double)>& progress);

}

#endif
