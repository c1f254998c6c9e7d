/**
 * @file IlluminationParallel.h
 * @brief The illumination filters on distributed data (pvbatch and pvserver under MPI).
 *
 * Light crosses the whole domain: the light reaching a point depends on material held by
 * other processes. Unstructured grids: each process keeps its piece and the cells of other
 * pieces near it (NeighborhoodGrid), and values cross between processes as the solver
 * steps. Images lit where they are (point scalars): Ray-Marched Illumination marches the
 * parts of the rays in each process's block and multiplies them at the process that holds
 * the point; Filtered Volumetric Shadows lights each process's points from its block grown
 * by a shadow's reach (ExchangeExtents from the neighbours), the tables' windows over it and,
 * per column, the sums of the cells between it and the light from the others (sent
 * pairwise, between processes whose windows share columns); Multi-Light Illumination
 * Volume sweeps directional lights over bands of rows, each process its band's
 * classification (ExchangeExtents from the blocks), each band getting the lattice rows it
 * reads beyond its own from the bands that hold them after every slice, and each point or
 * spot light over wedges of its rays, each process its wedge's classification slice by
 * slice, the units moved to the pieces' processes (ExchangeExtents); cell scalars become point
 * scalars over each block from its cells and the layer around it (BlockPointScalars). Pieces that
 * are not the blocks (another decomposition) give each block its lit array (BlockOfPieces), and
 * each process outputs the illumination over its block. The image filters with the distributed
 * properties off assemble the whole input on every process from the pieces of all processes
 * (collective calls of the filter's vtkMultiProcessController) and output the part of the
 * illumination that belongs to their own piece; the propagation then shares its sweeps out among
 * the processes (SweepShare): each process propagates its sweeps over the whole illumination grid
 * into fixed-point units of its own, and the sums over the processes (SumOverPieces, exact in any
 * order) give each process its piece. Every process keeps the same bookkeeping of lights, so
 * selective updates work as in a serial run. Filters that light points independently compute only
 * the points of the piece. The result equals the serial run's: bit for bit in the tests for the
 * propagation and the ray marcher, up to rounding (1e-8 of the largest value) for distributed
 * tables.
 *
 * Every process must update the filter together (ParaView does: pipelines update on all
 * processes at once). A process with an empty piece takes part and outputs an empty piece.
 */
#ifndef IlluminationParallel_h
#define IlluminationParallel_h

#include "VolIllumFiltersModule.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"
#include "vtkWeakPointer.h"

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkDataArray;
class vtkDataSet;
class vtkImageData;
class vtkMultiProcessController;
class vtkObject;
class vtkUnstructuredGrid;

namespace volillum
{

/// The controller of a parallel run: `controller` when it has more than one process, else
/// nullptr (run serially).
VOLILLUMFILTERS_EXPORT vtkMultiProcessController* ParallelRun(
  vtkMultiProcessController* controller);

/**
 * The extent of the illumination grid (`target` points per axis over the whole data extent
 * `whole`) that covers the data piece `piece`: the points from the last one at or before the
 * piece's first point to the first one at or after its last point. Pieces that share a
 * boundary plane (vtkExtentTranslator's convention) give extents that share at least one
 * plane, so the output pieces cover the whole illumination grid.
 */
VOLILLUMFILTERS_EXPORT void TargetPieceExtent(
  const int whole[6], const int target[3], const int piece[6], int out[6]);

/// The block of the data's extent `whole` that this process of `controller` reads in a
/// parallel run (block p of N, vtkExtentTranslator in block mode); false when there are more
/// processes than blocks.
VOLILLUMFILTERS_EXPORT bool ProcessBlock(
  vtkMultiProcessController* controller, const int whole[6], int block[6]);

/// Collective: the bounds of the points of all processes' pieces (piece may be nullptr).
VOLILLUMFILTERS_EXPORT void UnionOfBounds(
  vtkMultiProcessController* controller, vtkDataSet* piece, double bounds[6]);

/**
 * Collective: every process's `extent` (6 values each, in process order); a process
 * without a piece passes nullptr and gets an empty extent (its second value below its
 * first).
 */
VOLILLUMFILTERS_EXPORT std::vector<int> GatherExtents(
  vtkMultiProcessController* controller, const int* extent);

/**
 * Collective: the sums (modulo 2^32) over all processes of `values`, 3 a point of a grid of
 * `dimensions` points (x fastest), over each process's extent of that grid (`extents`, as
 * GatherExtents gives them): this process gets those of its own extent in `own` (3 a point,
 * x fastest). The sums travel in blocks of at most 2^22 values (16 MiB), a reduction to the
 * process that owns them (vtkMultiProcessController::Reduce).
 */
VOLILLUMFILTERS_EXPORT void SumOverPieces(vtkMultiProcessController* controller,
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
VOLILLUMFILTERS_EXPORT void ReduceOverPieces(vtkMultiProcessController* controller,
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

/// Whether extent `outer` holds every point of extent `inner`.
VOLILLUMFILTERS_EXPORT bool ExtentHolds(const int outer[6], const int inner[6]);

/// Points of an extent (0 for an empty one).
VOLILLUMFILTERS_EXPORT long long ExtentPoints(const int extent[6]);
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
extern template VOLILLUMFILTERS_EXPORT long long ExchangeExtents<std::uint16_t>(
  vtkMultiProcessController*, const int*, const int*, const std::uint16_t*, const int*,
  std::uint16_t*, int, bool);
extern template VOLILLUMFILTERS_EXPORT long long ExchangeExtents<std::uint32_t>(
  vtkMultiProcessController*, const int*, const int*, const std::uint32_t*, const int*,
  std::uint32_t*, int, bool);

/// Collective: whether `ok` holds on every process (`ok` itself without a controller: a
/// serial run).
VOLILLUMFILTERS_EXPORT bool AllOk(vtkMultiProcessController* controller, bool ok);

/**
 * Collective: the origin, spacing and orientation of the pieces (`piece` may be nullptr or
 * empty) set on `shape`: those of the lowest process with points (a producer such as
 * Resample To Image gives them with its data only, not in the pipeline information). Returns
 * false where a piece with points has others (within 1e-9 of a spacing); `shape` keeps its
 * own where no process has points.
 */
VOLILLUMFILTERS_EXPORT bool AgreeOnGeometry(
  vtkMultiProcessController* controller, vtkImageData* piece, vtkImageData* shape);

/**
 * The errors and warnings a filter reports during one parallel update, printed once by the
 * first process. ParaView shows a client only the first server process's messages, so an
 * error of another process's piece (a missing array, a bad coordinate) left the client an
 * empty output without a word. While one of these lives, the filter's messages are collected
 * on every process (ErrorEvent and WarningEvent observers: nothing is printed there); its
 * destructor, collective (every process's update ends together: the filters stop at the
 * same collective decisions), gathers them to the first process, which prints each distinct
 * message once as the filter's, naming the processes that reported it ("Process 1 of 2:
 * ...", "Processes 0-2 of 3: ..."). Without a controller (a serial run) it does nothing.
 */
class VOLILLUMFILTERS_EXPORT ParallelMessages
{
public:
  ParallelMessages(vtkMultiProcessController* controller, vtkAlgorithm* filter);
  ~ParallelMessages();
  ParallelMessages(const ParallelMessages&) = delete;
  ParallelMessages& operator=(const ParallelMessages&) = delete;

  struct Message
  {
    bool Error = true; // else a warning
    std::string Text;  // as printed, with the processes that reported it
  };
  /// What the first process prints, given each process's collected messages (`collected[p]`:
  /// per message 'E' or 'W', its text and a '\0'): each distinct message once, in the order
  /// of its first report.
  static std::vector<Message> Report(const std::vector<std::string>& collected);

private:
  void Collect(vtkObject* caller, unsigned long event, void* text);

  vtkMultiProcessController* Controller = nullptr;
  vtkAlgorithm* Filter = nullptr;
  unsigned long Observers[2] = { 0, 0 };
  std::mutex Mutex;      // a message may come from a worker thread
  std::string Collected; // per message: 'E' or 'W', its text and a '\0'
};

/**
 * Collective: whether every process must update `filter`, whose output covers only this
 * process's piece (so its pipeline, asked for the whole data, would run it on some
 * processes and not on the others): when any process's output is older than `read` (what
 * the filter reads besides its own settings, which count too). Then the filter is marked
 * modified on every process, so that each runs it. Without a controller (a serial run):
 * true, and the pipeline decides.
 */
VOLILLUMFILTERS_EXPORT bool MustUpdateTogether(
  vtkMultiProcessController* controller, vtkAlgorithm* filter, vtkMTimeType read);

/**
 * Collective: the cells of `piece` that are not ghost cells (DUPLICATECELL), its points
 * (their ids unchanged) and the arrays that travel (see DistributedInput): nullptr when the
 * piece has no cell.
 */
VOLILLUMFILTERS_EXPORT vtkSmartPointer<vtkUnstructuredGrid> PieceWithoutGhostCells(
  vtkAlgorithm* algorithm, vtkUnstructuredGrid* piece);

/**
 * For each point of `grid`, the first point at its place (itself when none comes before it):
 * the same coordinates and, when the grid has point global ids, the same id (ids that differ
 * keep copies apart, a seam; an id shared by points at different places joins nothing).
 * Coordinates must be finite. A grid read from a file of several pieces (a .pvtu) holds a
 * copy of each point on a cut per piece: cells on either side of the cut then share no
 * face, and the cut would be lit as a boundary. Pieces joined by NeighborhoodGrid are
 * joined the same way wherever their global ids are sound.
 */
VOLILLUMFILTERS_EXPORT std::vector<vtkIdType> FirstPointsAtTheirPlaces(vtkDataSet* grid);

/**
 * Collective: whether the processes' pieces (PieceWithoutGhostCells; null for none) can be
 * joined into neighbourhood grids (NeighborhoodGrid::Build): every coordinate finite and
 * within +-MaximumCoordinate, and the same arrays, in the same order, with the same names,
 * types, components and attribute roles, on every piece (a point or cell of one piece is
 * copied into another's grid). Otherwise `error` says why, on the processes whose piece has
 * a bad coordinate, or on every process when the pieces' arrays differ.
 */
VOLILLUMFILTERS_EXPORT bool PiecesCanJoin(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* piece, std::string& error);

/**
 * A process's neighbourhood of a distributed unstructured grid: its piece's cells followed
 * by the cells of other processes' pieces whose bounding boxes come within `depth` of the
 * piece's cells (each process sends the others what lies near them: no process holds the
 * whole grid unless the depth spans it). A piece's points in none of its cells (of 2D cells,
 * say) are in the grid too. Points of the piece keep their ids; points of the
 * other pieces follow, one per place (point global ids when the pieces have them, else
 * coordinates: without global ids, coincident points of a seam are one point, as in a serial
 * run, FirstPointsAtTheirPlaces). A cell that a lower process's piece holds too (the same
 * type and points) is that process's only. All the cells around a point of the piece's cells
 * are in the grid. Each process computes the values of the points of its piece's cells (and
 * of its piece's points in no cell anywhere, GetComputed); Exchange gives it those of the
 * other points of its grid, each from a process whose cells hold the point (the piece's
 * points in none of its cells, as D3 leaves the points of ghost cells, among them). A point
 * in several pieces' cells is owned by the lowest of their processes (GetOwned: sums over
 * points count each once; a point in no cell has no edges, and is owned where it is).
 */
class VOLILLUMFILTERS_EXPORT NeighborhoodGrid
{
public:
  /**
   * Collective. `piece`: this process's cells without ghost cells and its points (nullptr
   * or no points for none), with the arrays to carry. Returns the grid: the piece's cells
   * (but those a lower process's piece holds too), then the others'.
   */
  vtkUnstructuredGrid* Build(
    vtkMultiProcessController* controller, vtkUnstructuredGrid* piece, double depth);

  /// Collective: whether any process's piece (structure and arrays) changed since the last
  /// Build, or Reset was called since.
  bool Changed(vtkMultiProcessController* controller, vtkUnstructuredGrid* piece) const;

  /// Forget the grid: Changed answers true until the next Build.
  void Reset() { this->Fingerprint = 0; }

  vtkUnstructuredGrid* GetGrid() const;
  /// Points of the piece (the first ones of the grid).
  vtkIdType GetNumberOfPiecePoints() const { return this->PiecePoints; }
  /// Cells of the piece that the grid holds (the first ones of the grid).
  vtkIdType GetNumberOfPieceCells() const { return this->PieceCells; }
  /// Per point of the grid: 1 where this process computes its values (points of the piece's
  /// cells, and of the piece in no cell); Exchange gives the others theirs.
  const std::vector<unsigned char>& GetComputed() const { return this->Computed; }
  /// Per point of the grid: 1 where this process owns it (computes it, and no lower
  /// process's cells hold it).
  const std::vector<unsigned char>& GetOwned() const { return this->Owned; }

  /// Collective: the values (`components` a point) of the points of other pieces in the
  /// grid, replaced by those the processes of those pieces hold.
  void Exchange(float* values, int components) const;
  void Exchange(int* values, int components) const;

private:
  template <typename T>
  void ExchangeValues(T* values, int components) const;

  vtkMultiProcessController* Controller = nullptr;
  vtkSmartPointer<vtkUnstructuredGrid> Grid;
  std::uint64_t Fingerprint = 0; // of the piece of the last Build
  vtkIdType PiecePoints = 0, PieceCells = 0;
  std::vector<unsigned char> Owned, Computed;
  // Per peer process (one whose piece lies within the depth): the points of its piece this
  // process reads from it, and the points of this piece it sends it, in the order both
  // agreed on.
  std::vector<int> Peers;
  std::vector<std::vector<vtkIdType>> Reads, Sends;
};

/**
 * Point scalars over this process's block of an image whose scalars are cell data, equal to
 * those a serial run makes of the whole image (each point the average of the cells that use
 * it, ToPointScalars): the cells around the block's points are its own and one layer of the
 * neighbouring blocks', which travel from the processes whose blocks own them
 * (ExchangeExtents, only the cell array's values).
 */
class VOLILLUMFILTERS_EXPORT BlockPointScalars
{
public:
  /**
   * Collective. `whole`: the image's whole extent; `block`: this process's block (nullptr
   * for none), which its piece `input` holds; `cells`: the piece's cell array (the same type
   * and components on every process with a block); `component` as in ToPointScalars.
   * Returns an image over the block with the point scalars (named as `cells`), kept while no
   * process's array, extent or component changes; nullptr for a process without a block, and
   * on every process, with the reason in error, when the processes' arrays differ.
   */
  vtkImageData* Update(vtkMultiProcessController* controller, const int whole[6], const int* block,
    vtkImageData* input, vtkDataArray* cells, int component, std::string& error);

private:
  vtkSmartPointer<vtkImageData> Points;
  vtkWeakPointer<vtkDataArray> Source;
  vtkMTimeType SourceTime = 0;
  int Extent[6] = { 0, -1, 0, -1, 0, -1 };
  int Component = -1;
};

/// Whether the union of the extents (6 values each, as GatherExtents gives them) holds every
/// point of `wanted`.
VOLILLUMFILTERS_EXPORT bool ExtentsCover(const std::vector<int>& extents, const int wanted[6]);

/**
 * The lit array of an image over this process's block, gathered from the pieces the
 * processes hold when those pieces are not the blocks (a simulation's own decomposition
 * handed over by Catalyst or a script, pieces cut along another axis): each point (or
 * cell) of the block comes from a process whose piece holds it (ExchangeExtents, only the
 * array's values travel). Memory per process: its piece and its block.
 */
class VOLILLUMFILTERS_EXPORT BlockOfPieces
{
public:
  /**
   * Collective. `shape`: an image with the whole extent, origin, spacing and direction of the
   * data; `block`: this process's block (nullptr for none); `piece`: its piece (nullptr or
   * without points for none) and `array` the piece's array to light, on its cells when
   * `onCells` (nullptr where the piece has none). Returns an image over the block holding the
   * array (as its point or cell scalars, named as `array`), kept while no process's piece
   * extent or array content changes; nullptr for a process without a block, and on every
   * process, with the reason in error, when a piece lacks the array (or its array lacks
   * values), the arrays differ in type, components or association, or the pieces leave part
   * of a block uncovered. Pieces may overlap (shared planes, ghost layers): a point held by
   * several comes from one of them.
   */
  vtkImageData* Update(vtkMultiProcessController* controller, vtkImageData* shape, const int* block,
    vtkImageData* piece, vtkDataArray* array, bool onCells, std::string& error);

private:
  vtkSmartPointer<vtkImageData> Block;
  std::uint64_t Fingerprint = 0; // of the piece's array (content, components, association)
  int Extent[6] = { 0, -1, 0, -1, 0, -1 };
  int BlockExtent[6] = { 0, -1, 0, -1, 0, -1 };
};

/**
 * The whole input of a filter assembled from the pieces of all processes, kept until the
 * content of a piece changes (so a light edit neither moves data nor makes the
 * classification look new, even where the reader read the piece again).
 * Only the arrays the filter may light travel: the array its input array 0 names (point
 * or cell data) and the active scalars.
 */
class VOLILLUMFILTERS_EXPORT DistributedInput
{
public:
  /// Collective: the whole image (the union of the pieces' extents) on every process.
  vtkImageData* Image(
    vtkMultiProcessController* controller, vtkAlgorithm* algorithm, vtkImageData* piece);

private:
  // Collective: whether what any process sends (its piece's structure and lit arrays)
  // changed since the last assembly.
  bool Changed(vtkMultiProcessController* controller, vtkDataSet* travelling);

  vtkSmartPointer<vtkDataSet> Whole;
  std::uint64_t PieceFingerprint = 0;
};

}

#endif
