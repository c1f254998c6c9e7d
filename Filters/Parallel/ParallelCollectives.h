/**
 * @file ParallelCollectives.h
 * Collective decisions and reductions of the distribution layer: whether a run is parallel,
 * agreement of all processes on a condition, the union of the pieces' bounds and extents, sums
 * and other reductions of values over pieces of a grid, and the pairwise order in which
 * processes exchange messages. Every function marked collective must be called by every
 * process of the controller, in the same order.
 */
#ifndef ParallelCollectives_h
#define ParallelCollectives_h

#include "VolIllumParallelModule.h"
#include "vtkType.h"

#include <cstdint>
#include <functional>
#include <vector>

class vtkAlgorithm;
class vtkDataSet;
class vtkMultiProcessController;

namespace volillum
{

/// The controller of a parallel run: `controller` when it has more than one process, else
/// nullptr (run serially).
VOLILLUMPARALLEL_EXPORT vtkMultiProcessController* ParallelRun(
  vtkMultiProcessController* controller);

/// Collective: the bounds of the points of all processes' pieces (piece may be nullptr).
VOLILLUMPARALLEL_EXPORT void UnionOfBounds(
  vtkMultiProcessController* controller, vtkDataSet* piece, double bounds[6]);

/**
 * Collective: every process's `extent` (6 values each, in process order); a process
 * without a piece passes nullptr and gets an empty extent (its second value below its
 * first).
 */
VOLILLUMPARALLEL_EXPORT std::vector<int> GatherExtents(
  vtkMultiProcessController* controller, const int* extent);

/**
 * Collective: the sums (modulo 2^32) over all processes of `values`, 3 a point of a grid of
 * `dimensions` points (x fastest), over each process's extent of that grid (`extents`, as
 * GatherExtents gives them): this process gets those of its own extent in `own` (3 a point,
 * x fastest). The sums travel in blocks of at most 2^22 values (16 MiB), a reduction to the
 * process that owns them (vtkMultiProcessController::Reduce).
 */
VOLILLUMPARALLEL_EXPORT void SumOverPieces(vtkMultiProcessController* controller,
  const int dimensions[3], const std::vector<int>& extents, const std::uint32_t* values,
  std::vector<std::uint32_t>& own);

/// Values of `rows` rows along x of an extent of a grid, from row `firstRow` (rows counted
/// along y, then z, within the extent), a fixed number of values a point, x fastest.
template <typename T>
using PieceRows = std::function<void(const int* extent, size_t firstRow, size_t rows, T* values)>;

/**
 * Collective: per point of each process's extent of a grid (`extents`, as GatherExtents
 * gives them), the reduction (`operation`: vtkCommunicator::SUM_OP, PRODUCT_OP, ...) over
 * all processes of `components` values: `fill` gives this process's values for a block of
 * rows of an extent (whole rows, at most 2^20 values, every process the same blocks in the
 * same order), and the process that owns the extent gets the reduced values of each of its
 * blocks through `receive` (vtkMultiProcessController::Reduce to it). `progress`, when
 * given, is told the fraction of all the extents' rows filled after each block.
 */
VOLILLUMPARALLEL_EXPORT void ReduceOverPieces(vtkMultiProcessController* controller,
  const std::vector<int>& extents, int components, int operation, const PieceRows<double>& fill,
  const PieceRows<const double>& receive, const std::function<void(double)>& progress = nullptr);

/**
 * Runs exchange(k, send) twice with each of the `peers` (process ids in increasing order),
 * once sending (send true) and once receiving: first sending to a higher process, first
 * receiving from a lower one. Every process meets its peers in the same global order of
 * pairs, so blocking sends cannot wait on each other in a cycle.
 */
template <typename Exchange>
void WithEachPeer(int local, const std::vector<int>& peers, Exchange&& exchange)
{
  for (size_t k = 0; k < peers.size(); ++k)
  {
    const bool sendFirst = local < peers[k];
    exchange(k, sendFirst);
    exchange(k, !sendFirst);
  }
}

/// Collective: whether `ok` holds on every process (`ok` itself without a controller: a
/// serial run).
VOLILLUMPARALLEL_EXPORT bool AllOk(vtkMultiProcessController* controller, bool ok);

/**
 * Collective: whether every process must update `filter`, whose output covers only this
 * process's piece (so its pipeline, asked for the whole data, would run it on some
 * processes and not on the others): when any process's output is older than `read` (what
 * the filter reads besides its own settings, which count too). Then the filter is marked
 * modified on every process, so that each runs it. Without a controller (a serial run):
 * true, and the pipeline decides.
 */
VOLILLUMPARALLEL_EXPORT bool MustUpdateTogether(
  vtkMultiProcessController* controller, vtkAlgorithm* filter, vtkMTimeType read);

}

#endif
