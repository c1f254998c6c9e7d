/**
 * @file ImageBlocks.h
 * An image distributed over the processes, made ready for the image filters: assembled whole on
 * every process (DistributedInput), given point scalars where its scalars are on cells
 * (BlockPointScalars), or moved from the pieces a producer made to the blocks the filters
 * light (BlockOfPieces).
 */
#ifndef ImageBlocks_h
#define ImageBlocks_h

#include "VolIllumParallelModule.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"
#include "vtkWeakPointer.h"

#include <cstdint>
#include <functional>
#include <string>

class vtkDataArray;
class vtkDataSet;
class vtkImageData;
class vtkMultiProcessController;

namespace volillum
{

/// Point scalars of an image whose scalars `cells` are on its cells, one component of them
/// (`component` as the filter's ScalarComponent); nullptr with the reason in error.
using CellsToPoints = std::function<vtkSmartPointer<vtkDataArray>(
  vtkImageData* image, vtkDataArray* cells, int component, std::string& error)>;

/**
 * Point scalars over this process's block of an image whose scalars are cell data, equal to
 * those a serial run makes of the whole image (each point the average of the cells that use
 * it, ToPointScalars): the cells around the block's points are its own and one layer of the
 * neighbouring blocks', which travel from the processes whose blocks own them
 * (ExchangeExtents, only the cell array's values).
 */
class VOLILLUMPARALLEL_EXPORT BlockPointScalars
{
public:
  /**
   * Collective. `whole`: the image's whole extent; `block`: this process's block (nullptr
   * for none), which its piece `input` holds; `cells`: the piece's cell array (the same type
   * and components on every process with a block); `component` as in ToPointScalars.
   * Returns an image over the block with the point scalars (named as `cells`), kept while no
   * process's array, extent or component changes; nullptr for a process without a block, and
   * on every process, with the reason in error, when the processes' arrays differ. `convert`
   * makes point scalars of the cells around the block as a serial run converts the image's.
   */
  vtkImageData* Update(vtkMultiProcessController* controller, const int whole[6], const int* block,
    vtkImageData* input, vtkDataArray* cells, int component, const CellsToPoints& convert,
    std::string& error);

private:
  vtkSmartPointer<vtkImageData> Points;
  vtkWeakPointer<vtkDataArray> Source;
  vtkMTimeType SourceTime = 0;
  int Extent[6] = { 0, -1, 0, -1, 0, -1 };
  int Component = -1;
};

/**
 * The lit array of an image over this process's block, gathered from the pieces the
 * processes hold when those pieces are not the blocks (a simulation's own decomposition
 * handed over by Catalyst or a script, pieces cut along another axis): each point (or
 * cell) of the block comes from a process whose piece holds it (ExchangeExtents, only the
 * array's values travel). Memory per process: its piece and its block.
 */
class VOLILLUMPARALLEL_EXPORT BlockOfPieces
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
class VOLILLUMPARALLEL_EXPORT DistributedInput
{
public:
  /// Collective: the whole image (the union of the pieces' extents) on every process.
  /// `litArray`: the name of the array the filter lights (nullptr or "" for the scalars).
  vtkImageData* Image(
    vtkMultiProcessController* controller, const char* litArray, vtkImageData* piece);

private:
  // Collective: whether what any process sends (its piece's structure and lit arrays)
  // changed since the last assembly.
  bool Changed(vtkMultiProcessController* controller, vtkDataSet* travelling);

  vtkSmartPointer<vtkDataSet> Whole;
  std::uint64_t PieceFingerprint = 0;
};

}

#endif
