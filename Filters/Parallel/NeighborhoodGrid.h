/**
 * @file NeighborhoodGrid.h
 * A distributed unstructured grid made ready for the two-level solver: each process's piece
 * without ghost cells, joined with the cells of the other pieces near it, and the exchange of
 * point values between the processes whose pieces meet.
 */
#ifndef NeighborhoodGrid_h
#define NeighborhoodGrid_h

#include "VolIllumParallelModule.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

class vtkDataSet;
class vtkMultiProcessController;
class vtkUnstructuredGrid;

namespace volillum
{

/**
 * Collective: the cells of `piece` that are not ghost cells (DUPLICATECELL), its points
 * (their ids unchanged) and the arrays that travel (see DistributedInput): nullptr when the
 * piece has no cell.
 */
VOLILLUMPARALLEL_EXPORT vtkSmartPointer<vtkUnstructuredGrid> PieceWithoutGhostCells(
  const char* litArray, vtkUnstructuredGrid* piece);

/**
 * For each point of `grid`, the first point at its place (itself when none comes before it):
 * the same coordinates and, when the grid has point global ids, the same id (ids that differ
 * keep copies apart, a seam; an id shared by points at different places joins nothing).
 * Coordinates must be finite. A grid read from a file of several pieces (a .pvtu) holds a
 * copy of each point on a cut per piece: cells on either side of the cut then share no
 * face, and the cut would be lit as a boundary. Pieces joined by NeighborhoodGrid are
 * joined the same way wherever their global ids are sound.
 */
VOLILLUMPARALLEL_EXPORT std::vector<vtkIdType> FirstPointsAtTheirPlaces(vtkDataSet* grid);

/**
 * Collective: whether the processes' pieces (PieceWithoutGhostCells; null for none) can be
 * joined into neighbourhood grids (NeighborhoodGrid::Build): no process came with an `error`
 * of its own (its piece's check, a bad coordinate say, made by the caller), and the same
 * arrays, in the same order, with the same names, types, components and attribute roles, on
 * every piece (a point or cell of one piece is copied into another's grid). When the arrays
 * differ, `error` says why on every process.
 */
VOLILLUMPARALLEL_EXPORT bool PiecesCanJoin(
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
class VOLILLUMPARALLEL_EXPORT NeighborhoodGrid
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
  // Build's last steps: which points of the grid this process computes and owns (`owner`:
  // per point, the lowest process whose cells hold it, the number of processes for none;
  // `inPieceCells`: the same for the piece's cells alone), and the points of its piece each
  // peer reads (Sends; by key, global id or coordinates, `known` giving the point of a key).
  void AssignComputed(const std::vector<int>& owner, const std::vector<int>& inPieceCells);
  void AgreeOnSends(const std::map<std::array<double, 3>, vtkIdType>& known, bool byId);

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

}

#endif
