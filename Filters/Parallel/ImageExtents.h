/**
 * @file ImageExtents.h
 * Extents of a distributed image: the block each process reads, the illumination grid's
 * part that covers a piece, tests on extents, and the collective move of a grid's values from
 * one distribution over the processes to another (ExchangeExtents), on which the image
 * filters' distributed paths build.
 */
#ifndef ImageExtents_h
#define ImageExtents_h

#include "VolIllumParallelModule.h"

#include <cstdint>
#include <vector>

class vtkImageData;
class vtkMultiProcessController;

namespace volillum
{

/// Whether an extent holds no point (a second value below the first on some axis).
VOLILLUMPARALLEL_EXPORT bool ExtentIsEmpty(const int extent[6]);

/**
 * The extent of the illumination grid (`target` points per axis over the whole data extent
 * `whole`) that covers the data piece `piece`: the points from the last one at or before the
 * piece's first point to the first one at or after its last point. Pieces that share a
 * boundary plane (vtkExtentTranslator's convention) give extents that share at least one
 * plane, so the output pieces cover the whole illumination grid.
 */
VOLILLUMPARALLEL_EXPORT void TargetPieceExtent(
  const int whole[6], const int target[3], const int piece[6], int out[6]);

/// The block of the data's extent `whole` that this process of `controller` reads in a
/// parallel run (block p of N, vtkExtentTranslator in block mode); false when there are more
/// processes than blocks.
VOLILLUMPARALLEL_EXPORT bool ProcessBlock(
  vtkMultiProcessController* controller, const int whole[6], int block[6]);

/// Whether extent `outer` holds every point of extent `inner`.
VOLILLUMPARALLEL_EXPORT bool ExtentHolds(const int outer[6], const int inner[6]);

/// Points of an extent (0 for an empty one).
VOLILLUMPARALLEL_EXPORT long long ExtentPoints(const int extent[6]);

/// Whether the union of the extents (6 values each, as GatherExtents gives them) holds every
/// point of `wanted`.
VOLILLUMPARALLEL_EXPORT bool ExtentsCover(const std::vector<int>& extents, const int wanted[6]);

/**
 * Collective: values of a grid moved from one distribution over the processes to another.
 * Each process holds `values` (`components` a point, x fastest) over the extent `held` and
 * owns the points of `owned` within it (the processes' `owned` extents do not overlap);
 * it gets into `into` (over the extent `wanted`) the values of every point of `wanted` that
 * some process owns, copied, or added (modulo 2^32 for unsigned values) with `add`. Points of
 * `wanted` that no process owns are left as they are. Empty extents (second value below the
 * first) take part without data. Only the pairs of processes with points to move exchange
 * (Send/Receive in a global order of pairs). Returns the bytes this process sent.
 */
template <typename T>
long long ExchangeExtents(vtkMultiProcessController* controller, const int held[6],
  const int owned[6], const T* values, const int wanted[6], T* into, int components, bool add);
extern template VOLILLUMPARALLEL_EXPORT long long ExchangeExtents<std::uint16_t>(
  vtkMultiProcessController*, const int*, const int*, const std::uint16_t*, const int*,
  std::uint16_t*, int, bool);
extern template VOLILLUMPARALLEL_EXPORT long long ExchangeExtents<std::uint32_t>(
  vtkMultiProcessController*, const int*, const int*, const std::uint32_t*, const int*,
  std::uint32_t*, int, bool);

/**
 * Collective: the origin, spacing and orientation of the pieces (`piece` may be nullptr or
 * empty) set on `shape`: those of the lowest process with points (a producer such as
 * Resample To Image gives them with its data only, not in the pipeline information). Returns
 * false where a piece with points has others (within 1e-9 of a spacing); `shape` keeps its
 * own where no process has points.
 */
VOLILLUMPARALLEL_EXPORT bool AgreeOnGeometry(
  vtkMultiProcessController* controller, vtkImageData* piece, vtkImageData* shape);

// Calls row(offsetA, offsetB, count) for each row along x of `part`, the offsets being the
// row's first value in arrays over the extents a and b (`components` a point); the rows come
// in order (y, then z).
template <typename Row>
void ForEachRowOf(const int* a, const int* b, const int* part, int components, Row&& row)
{
  // The row's first point in an array over extent e.
  auto point = [part](const int* e, int j, int k)
  {
    const long long nx = e[1] - e[0] + 1, ny = e[3] - e[2] + 1;
    return (part[0] - e[0]) + nx * ((j - e[2]) + ny * (k - e[4]));
  };
  const long long count = components * static_cast<long long>(part[1] - part[0] + 1);
  for (int k = part[4]; k <= part[5]; ++k)
  {
    for (int j = part[2]; j <= part[3]; ++j)
    {
      row(components * point(a, j, k), components * point(b, j, k), count);
    }
  }
}

// ForEachRowOf for one extent: row(offset, count).
template <typename Row>
void ForEachRow(const int* extent, const int* part, int components, Row&& row)
{
  ForEachRowOf(extent, extent, part, components,
    [&](long long offset, long long, long long count) { row(offset, count); });
}

}

#endif
