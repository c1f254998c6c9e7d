#include "NeighborhoodGrid.h"

#include "NeighborhoodBins.h"
#include "ParallelCollectives.h"
#include "TravellingPieces.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataSetAttributes.h"
#include "vtkIdList.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace volillum
{

using neighborhood::BinMask;
using neighborhood::CellsNear;
using neighborhood::PointKey;

namespace
{
// Message tags of NeighborhoodGrid.
constexpr int CellsTag = 8270, CountTag = 8271, KeysTag = 8272, ValuesTag = 8273, MaskTag = 8275;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> PieceWithoutGhostCells(
  const char* litArray, vtkUnstructuredGrid* piece)
{
  if (!piece || piece->GetNumberOfCells() == 0)
  {
    return nullptr;
  }
  vtkNew<vtkUnstructuredGrid> travelling;
  CopyLitArrays(litArray, piece, travelling);
  auto own = vtkSmartPointer<vtkUnstructuredGrid>::New();
  own->SetPoints(piece->GetPoints());
  own->GetPointData()->ShallowCopy(travelling->GetPointData());
  own->GetCellData()->CopyAllocate(travelling->GetCellData());
  own->AllocateEstimate(piece->GetNumberOfCells(), 4);
  vtkUnsignedCharArray* ghosts = piece->GetCellGhostArray();
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < piece->GetNumberOfCells(); ++c)
  {
    if (ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL))
    {
      continue; // owned by another piece
    }
    piece->GetCellPoints(c, cell);
    const vtkIdType id = own->InsertNextCell(piece->GetCellType(c), cell);
    own->GetCellData()->CopyData(travelling->GetCellData(), c, id);
  }
  own->Squeeze();
  return own->GetNumberOfCells() > 0 ? own : nullptr;
}

//------------------------------------------------------------------------------
std::vector<vtkIdType> FirstPointsAtTheirPlaces(vtkDataSet* grid)
{
  const vtkIdType n = grid ? grid->GetNumberOfPoints() : 0;
  std::vector<vtkIdType> first(static_cast<size_t>(n));
  vtkDataArray* ids = n > 0 ? grid->GetPointData()->GetGlobalIds() : nullptr;
  vtkIdTypeArray* exact = vtkIdTypeArray::SafeDownCast(ids);
  // The place: the global id (0 without ids) and the coordinates.
  using Place = std::pair<long long, std::array<double, 3>>;
  std::vector<Place> places(first.size());
  for (vtkIdType i = 0; i < n; ++i)
  {
    places[i].first = exact ? exact->GetValue(i)
      : ids                 ? static_cast<long long>(ids->GetComponent(i, 0))
                            : 0;
    grid->GetPoint(i, places[i].second.data());
    first[i] = i;
  }
  // Ordered by place, then by id: a run of one place starts with its first point.
  std::vector<vtkIdType> order(first);
  std::sort(order.begin(), order.end(),
    [&](vtkIdType a, vtkIdType b)
    { return places[a] != places[b] ? places[a] < places[b] : a < b; });
  for (size_t k = 1; k < order.size(); ++k)
  {
    if (places[order[k]] == places[order[k - 1]])
    {
      first[order[k]] = first[order[k - 1]];
    }
  }
  return first;
}

//------------------------------------------------------------------------------
bool PiecesCanJoin(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* piece, std::string& error)
{
  if (!AllOk(controller, error.empty()))
  {
    return false;
  }
  // The arrays' layout, as a fingerprint (of the pieces only: an empty process agrees).
  std::uint64_t layout = 0;
  for (int association : { vtkDataObject::POINT, vtkDataObject::CELL })
  {
    vtkDataSetAttributes* attributes = piece ? piece->GetAttributes(association) : nullptr;
    for (int i = 0; attributes && i < attributes->GetNumberOfArrays(); ++i)
    {
      vtkAbstractArray* array = attributes->GetAbstractArray(i);
      const std::string name = array->GetName() ? array->GetName() : "";
      const int form[4] = { association, array->GetDataType(), array->GetNumberOfComponents(),
        attributes->IsArrayAnAttribute(i) };
      layout = HashBytes(form, sizeof(form), HashBytes(name.data(), name.size(), layout));
    }
  }
  // The pieces' fingerprints (63 bits) agree when the smallest is the largest.
  const long long mine[2] = { piece ? static_cast<long long>(layout >> 1)
                                    : std::numeric_limits<long long>::max(),
    piece ? static_cast<long long>(layout >> 1) : std::numeric_limits<long long>::min() };
  long long lowest = 0, highest = 0;
  controller->AllReduce(mine, &lowest, 1, vtkCommunicator::MIN_OP);
  controller->AllReduce(mine + 1, &highest, 1, vtkCommunicator::MAX_OP);
  if (lowest != std::numeric_limits<long long>::max() && lowest != highest)
  {
    error = "The pieces' arrays to illuminate differ between processes (in name, type, "
            "components or association); every piece must carry the same arrays.";
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool NeighborhoodGrid::Changed(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* piece) const
{
  vtkNew<vtkUnstructuredGrid> empty;
  int changed = !this->Grid || this->Fingerprint == 0 ||
    volillum::Fingerprint(piece ? piece : empty.Get()) != this->Fingerprint;
  int any = 0;
  controller->AllReduce(&changed, &any, 1, vtkCommunicator::LOGICAL_OR_OP);
  return any != 0;
}

namespace
{
// Collective: the processes whose pieces' cells lie within reach of this piece's (`mask`:
// where its cells lie; `has`: whether it has points), in increasing order, with their masks.
// Candidates are the processes whose marked bins' box comes within reach of this piece's (one
// box of 6 bin indices a process travels to all). Only candidates exchange masks, and peers
// are the candidates with cells in bins within reach of this piece's: the same relation seen
// from both, so no process waits for a peer that does not count it as one.
std::vector<int> FindPeers(vtkMultiProcessController* controller, const BinMask& mask, double depth,
  bool has, std::vector<std::vector<unsigned char>>& peerMasks)
{
  const int local = controller->GetLocalProcessId();
  const int processes = controller->GetNumberOfProcesses();
  const std::array<int, 3> reach = mask.Reach(depth);
  const std::array<int, 6> box = mask.MarkedBox();
  std::vector<int> boxes(6 * static_cast<size_t>(processes));
  controller->AllGather(box.data(), boxes.data(), 6);
  const auto marked = [](const int* b) { return b[0] <= b[1]; };
  std::vector<int> candidates;
  for (int q = 0; q < processes && has && marked(box.data()); ++q)
  {
    const int* other = boxes.data() + 6 * static_cast<size_t>(q);
    bool near = q != local && marked(other);
    for (int d = 0; d < 3 && near; ++d)
    {
      near = other[2 * d] <= box[2 * d + 1] + reach[d] && box[2 * d] <= other[2 * d + 1] + reach[d];
    }
    if (near)
    {
      candidates.push_back(q);
    }
  }
  const size_t bytes = mask.Bits.size();
  std::vector<unsigned char> masks(bytes * candidates.size());
  WithEachPeer(local, candidates,
    [&](size_t k, bool send)
    {
      if (send)
      {
        controller->Send(mask.Bits.data(), static_cast<vtkIdType>(bytes), candidates[k], MaskTag);
      }
      else
      {
        controller->Receive(
          masks.data() + bytes * k, static_cast<vtkIdType>(bytes), candidates[k], MaskTag);
      }
    });
  const std::vector<unsigned char> grown = mask.Grown(reach);
  std::vector<int> peers;
  peerMasks.clear();
  for (size_t k = 0; k < candidates.size(); ++k)
  {
    if (BinMask::Share(grown, masks.data() + bytes * k))
    {
      peers.push_back(candidates[k]);
      peerMasks.emplace_back(masks.begin() + bytes * k, masks.begin() + bytes * (k + 1));
    }
  }
  return peers;
}

// Collective: the cells of each peer near this piece (each peer's mask in `peerMasks`).
std::vector<vtkSmartPointer<vtkUnstructuredGrid>> ExchangeCellsNear(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* piece, const BinMask& mask,
  const std::vector<int>& peers, const std::vector<std::vector<unsigned char>>& peerMasks,
  double depth)
{
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> received(peers.size());
  WithEachPeer(controller->GetLocalProcessId(), peers,
    [&](size_t k, bool send)
    {
      if (send)
      {
        controller->Send(CellsNear(piece, mask, peerMasks[k].data(), depth), peers[k], CellsTag);
      }
      else
      {
        received[k] = vtkSmartPointer<vtkUnstructuredGrid>::New();
        controller->Receive(received[k], peers[k], CellsTag);
      }
    });
  return received;
}

// Joins a piece and the cells its peers sent into one grid: a point of a later grid at the
// place (or with the global id) of an earlier one is that point, and a cell that two pieces
// hold (D3's "Duplicate cells" boundary mode gives the cells across a boundary to both
// pieces, unmarked) counts once, as the lowest process's: a cell is known by its type and its
// points' keys in order.
class GridJoiner
{
public:
  GridJoiner(vtkUnstructuredGrid* grid, vtkUnstructuredGrid* piece,
    const std::vector<vtkSmartPointer<vtkUnstructuredGrid>>& received,
    const std::vector<int>& peers, int local, int processes,
    std::vector<std::vector<vtkIdType>>& reads)
    : ById(piece->GetPointData()->GetGlobalIds() != nullptr)
    , Grid(grid)
    , Piece(piece)
    , Local(local)
    , Processes(processes)
    , Reads(reads)
  {
    // The arrays by name: a grid that travelled may hold them in another order (the global
    // ids first), and copying by index would mix them (the lit array taking the ids'
    // values). Grids without points may have lost their arrays on the way: they add nothing.
    this->PointFields.IntersectFieldList(piece->GetPointData());
    this->CellFields.IntersectFieldList(piece->GetCellData());
    for (const auto& from : received)
    {
      if (from->GetNumberOfPoints() > 0)
      {
        this->PointFields.IntersectFieldList(from->GetPointData());
        this->CellFields.IntersectFieldList(from->GetCellData());
      }
    }
    grid->GetPointData()->CopyGlobalIdsOn();
    grid->GetPointData()->CopyAllocate(this->PointFields);
    grid->GetCellData()->CopyAllocate(this->CellFields);
    this->IndexPeerCells(received, peers);
    this->MarkSharedPoints(received);
  }

  // Appends `from`: the piece (peer -1) or the cells of peer `peer` (process `process`).
  void Append(vtkUnstructuredGrid* from, int process, int peer);

  bool ById;
  std::map<std::array<double, 3>, vtkIdType> Known; // the point at each key
  std::vector<int> Owner; // per point: the lowest process whose cells hold it (Processes: none)

private:
  // A cell's key: its type and its points' keys in order.
  std::vector<double> CellKey(vtkUnstructuredGrid* from, vtkIdType c);
  // Per cell that came from a peer: the lowest process that holds it.
  void IndexPeerCells(const std::vector<vtkSmartPointer<vtkUnstructuredGrid>>& received,
    const std::vector<int>& peers);
  // Which points of the piece are among the peers' (only a piece cell whose points all are
  // can be one of theirs).
  void MarkSharedPoints(const std::vector<vtkSmartPointer<vtkUnstructuredGrid>>& received);
  bool MayBeShared(vtkIdType c);
  // The ids in the grid of the points of `from`, each added where no earlier one has its key.
  std::vector<vtkIdType> AppendPoints(vtkUnstructuredGrid* from, int process, int peer);
  // Whether cell c of `from` is left out: a peer's cell already here, or a piece cell that a
  // lower process holds too.
  bool SkipCell(vtkUnstructuredGrid* from, vtkIdType c, int peer);

  struct Holding
  {
    int Lowest;   // process
    bool Present; // in the grid
  };
  using Held = std::map<std::vector<double>, Holding>;

  vtkUnstructuredGrid* Grid;
  vtkUnstructuredGrid* Piece;
  int Local;
  int Processes;
  std::vector<std::vector<vtkIdType>>& Reads;
  vtkDataSetAttributes::FieldList PointFields, CellFields;
  Held HeldCells;
  std::vector<std::vector<Held::iterator>> HeldOf; // per peer and cell
  std::vector<char> Shared;
  int Input = 0; // the index of the grid appended next in the field lists
  vtkNew<vtkIdList> Keyed, Cell;
};

//------------------------------------------------------------------------------
std::vector<double> GridJoiner::CellKey(vtkUnstructuredGrid* from, vtkIdType c)
{
  from->GetCellPoints(c, this->Keyed);
  std::vector<std::array<double, 3>> keys(static_cast<size_t>(this->Keyed->GetNumberOfIds()));
  for (size_t k = 0; k < keys.size(); ++k)
  {
    keys[k] = PointKey(from, this->Keyed->GetId(static_cast<vtkIdType>(k)), this->ById);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<double> key(1, static_cast<double>(from->GetCellType(c)));
  for (const auto& k : keys)
  {
    key.insert(key.end(), k.begin(), k.end());
  }
  return key;
}

//------------------------------------------------------------------------------
void GridJoiner::IndexPeerCells(
  const std::vector<vtkSmartPointer<vtkUnstructuredGrid>>& received, const std::vector<int>& peers)
{
  this->HeldOf.resize(peers.size());
  for (size_t k = 0; k < peers.size(); ++k)
  {
    this->HeldOf[k].reserve(static_cast<size_t>(received[k]->GetNumberOfCells()));
    for (vtkIdType c = 0; c < received[k]->GetNumberOfCells(); ++c)
    {
      const auto entry =
        this->HeldCells.emplace(this->CellKey(received[k], c), Holding{ peers[k], false });
      entry.first->second.Lowest = std::min(entry.first->second.Lowest, peers[k]);
      this->HeldOf[k].push_back(entry.first);
    }
  }
}

//------------------------------------------------------------------------------
void GridJoiner::MarkSharedPoints(const std::vector<vtkSmartPointer<vtkUnstructuredGrid>>& received)
{
  this->Shared.assign(static_cast<size_t>(this->Piece->GetNumberOfPoints()), 0);
  if (this->HeldCells.empty())
  {
    return;
  }
  std::set<std::array<double, 3>> peerPoints;
  for (const auto& from : received)
  {
    for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i)
    {
      peerPoints.insert(PointKey(from, i, this->ById));
    }
  }
  for (vtkIdType i = 0; i < this->Piece->GetNumberOfPoints(); ++i)
  {
    this->Shared[i] = peerPoints.count(PointKey(this->Piece, i, this->ById)) != 0;
  }
}

//------------------------------------------------------------------------------
bool GridJoiner::MayBeShared(vtkIdType c)
{
  this->Piece->GetCellPoints(c, this->Keyed);
  for (vtkIdType k = 0; k < this->Keyed->GetNumberOfIds(); ++k)
  {
    if (!this->Shared[this->Keyed->GetId(k)])
    {
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
std::vector<vtkIdType> GridJoiner::AppendPoints(vtkUnstructuredGrid* from, int process, int peer)
{
  vtkPoints* points = this->Grid->GetPoints();
  std::vector<vtkIdType> ids(static_cast<size_t>(from->GetNumberOfPoints()));
  std::vector<std::pair<std::array<double, 3>, vtkIdType>> added;
  for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i)
  {
    const auto key = PointKey(from, i, this->ById);
    const auto found = process == this->Local ? this->Known.end() : this->Known.find(key);
    if (found != this->Known.end())
    {
      ids[i] = found->second;
      continue;
    }
    ids[i] = points->InsertNextPoint(from->GetPoint(i));
    this->Grid->GetPointData()->CopyData(
      this->PointFields, from->GetPointData(), this->Input, i, ids[i]);
    added.emplace_back(key, ids[i]);
    if (peer >= 0)
    {
      this->Reads[peer].push_back(ids[i]); // a point of that peer's piece
    }
  }
  this->Known.insert(added.begin(), added.end()); // the first point at a place is kept
  this->Owner.resize(static_cast<size_t>(points->GetNumberOfPoints()), this->Processes);
  return ids;
}

//------------------------------------------------------------------------------
bool GridJoiner::SkipCell(vtkUnstructuredGrid* from, vtkIdType c, int peer)
{
  if (peer >= 0)
  {
    Holding& holding = this->HeldOf[peer][c]->second;
    if (holding.Present)
    {
      return true; // already here
    }
    holding.Present = true;
  }
  else if (!this->HeldCells.empty() && this->MayBeShared(c))
  {
    const auto found = this->HeldCells.find(this->CellKey(from, c));
    if (found != this->HeldCells.end() && found->second.Lowest < this->Local)
    {
      return true; // a lower process's cell
    }
    if (found != this->HeldCells.end())
    {
      found->second.Present = true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
void GridJoiner::Append(vtkUnstructuredGrid* from, int process, int peer)
{
  if (from->GetNumberOfPoints() == 0)
  {
    return;
  }
  const std::vector<vtkIdType> ids = this->AppendPoints(from, process, peer);
  for (vtkIdType c = 0; c < from->GetNumberOfCells(); ++c)
  {
    if (this->SkipCell(from, c, peer))
    {
      continue;
    }
    from->GetCellPoints(c, this->Cell);
    for (vtkIdType k = 0; k < this->Cell->GetNumberOfIds(); ++k)
    {
      this->Cell->SetId(k, ids[this->Cell->GetId(k)]);
      this->Owner[this->Cell->GetId(k)] = std::min(this->Owner[this->Cell->GetId(k)], process);
    }
    const vtkIdType id = this->Grid->InsertNextCell(from->GetCellType(c), this->Cell);
    this->Grid->GetCellData()->CopyData(this->CellFields, from->GetCellData(), this->Input, c, id);
  }
  ++this->Input;
}
}

//------------------------------------------------------------------------------
vtkUnstructuredGrid* NeighborhoodGrid::Build(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* piece, double depth)
{
  this->Controller = controller;
  const int local = controller->GetLocalProcessId();
  const int processes = controller->GetNumberOfProcesses();
  const bool has = piece && piece->GetNumberOfPoints() > 0;
  vtkNew<vtkUnstructuredGrid> empty;
  this->Fingerprint = volillum::Fingerprint(piece ? piece : empty.Get());
  // Bins over the bounds of all pieces: where this piece's cells lie (a point in no cell
  // needs none: its light comes from level 0).
  double whole[6];
  UnionOfBounds(controller, has ? piece : nullptr, whole);
  BinMask mask(whole, depth);
  for (vtkIdType c = 0; has && c < piece->GetNumberOfCells(); ++c)
  {
    double bounds[6];
    piece->GetCellBounds(c, bounds);
    mask.Mark(bounds);
  }
  std::vector<std::vector<unsigned char>> peerMasks;
  this->Peers = FindPeers(controller, mask, depth, has, peerMasks);
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> received =
    ExchangeCellsNear(controller, piece, mask, this->Peers, peerMasks, depth);

  // The piece, then the others' cells.
  this->Grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  this->PiecePoints = has ? piece->GetNumberOfPoints() : 0;
  this->PieceCells = has ? piece->GetNumberOfCells() : 0;
  this->Owned.clear();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  this->Grid->SetPoints(points);
  if (!has)
  {
    this->Grid->AllocateEstimate(0, 4);
    return this->Grid;
  }
  this->Reads.assign(this->Peers.size(), {});
  GridJoiner joiner(this->Grid, piece, received, this->Peers, local, processes, this->Reads);
  joiner.Append(piece, local, -1);
  this->PieceCells = this->Grid->GetNumberOfCells();
  // Points of the piece in none of its cells (those of its ghost cells, as D3 leaves them):
  // where another piece's cells hold them, they are that piece's points.
  const std::vector<int> inPieceCells(
    joiner.Owner.begin(), joiner.Owner.begin() + this->PiecePoints);
  for (size_t k = 0; k < this->Peers.size(); ++k)
  {
    joiner.Append(received[k], this->Peers[k], static_cast<int>(k));
  }
  received.clear();
  this->Grid->Squeeze();
  this->AssignComputed(joiner.Owner, inPieceCells);
  this->AgreeOnSends(joiner.Known, joiner.ById);
  return this->Grid;
}

//------------------------------------------------------------------------------
void NeighborhoodGrid::AssignComputed(
  const std::vector<int>& owner, const std::vector<int>& inPieceCells)
{
  // Computed here: the points of the piece's cells, and those in no cell (lit as serially);
  // the piece's other points are read from the lowest process whose cells hold them (it
  // computes them: all the cells around a point of a piece are here, so that process is
  // known). Owned: computed here, and not of a lower process's piece.
  const int local = this->Controller->GetLocalProcessId();
  const int processes = this->Controller->GetNumberOfProcesses();
  const vtkIdType np = this->Grid->GetNumberOfPoints();
  this->Owned.assign(static_cast<size_t>(np), 0);
  this->Computed.assign(static_cast<size_t>(np), 0);
  for (vtkIdType p = 0; p < this->PiecePoints; ++p)
  {
    this->Computed[p] = inPieceCells[p] == local || owner[p] == processes;
    this->Owned[p] = this->Computed[p] && owner[p] >= local;
    if (!this->Computed[p])
    {
      const size_t k =
        std::lower_bound(this->Peers.begin(), this->Peers.end(), owner[p]) - this->Peers.begin();
      this->Reads[k].push_back(p);
    }
  }
}

//------------------------------------------------------------------------------
void NeighborhoodGrid::AgreeOnSends(
  const std::map<std::array<double, 3>, vtkIdType>& known, bool byId)
{
  // Tell each peer which points of its piece are read here (by key), in the order of Reads.
  vtkMultiProcessController* controller = this->Controller;
  this->Sends.assign(this->Peers.size(), {});
  WithEachPeer(controller->GetLocalProcessId(), this->Peers,
    [&](size_t k, bool send)
    {
      const int q = this->Peers[k];
      if (send)
      {
        std::vector<double> keys;
        keys.reserve(3 * this->Reads[k].size());
        for (vtkIdType p : this->Reads[k])
        {
          const auto key = PointKey(this->Grid, p, byId);
          keys.insert(keys.end(), key.begin(), key.end());
        }
        const vtkIdType count = static_cast<vtkIdType>(this->Reads[k].size());
        controller->Send(&count, 1, q, CountTag);
        controller->Send(keys.data(), 3 * count, q, KeysTag);
        return;
      }
      vtkIdType count = 0;
      controller->Receive(&count, 1, q, CountTag);
      std::vector<double> keys(3 * static_cast<size_t>(count));
      controller->Receive(keys.data(), 3 * count, q, KeysTag);
      auto& sends = this->Sends[k];
      sends.resize(static_cast<size_t>(count));
      for (vtkIdType i = 0; i < count; ++i)
      {
        const std::array<double, 3> key = { keys[3 * i], keys[3 * i + 1], keys[3 * i + 2] };
        const auto found = known.find(key);
        sends[i] = found == known.end() ? -1 : found->second;
      }
    });
}

//------------------------------------------------------------------------------
vtkUnstructuredGrid* NeighborhoodGrid::GetGrid() const
{
  return this->Grid;
}

//------------------------------------------------------------------------------
template <typename T>
void NeighborhoodGrid::ExchangeValues(T* values, int components) const
{
  if (!this->Controller)
  {
    return;
  }
  const int local = this->Controller->GetLocalProcessId();
  std::vector<T> buffer;
  WithEachPeer(local, this->Peers,
    [&](size_t k, bool send)
    {
      const int q = this->Peers[k];
      const auto& points = send ? this->Sends[k] : this->Reads[k];
      buffer.assign(points.size() * components, T(0));
      if (send)
      {
        for (size_t i = 0; i < points.size(); ++i)
        {
          if (points[i] >= 0)
          {
            std::copy_n(values + components * points[i], components, &buffer[components * i]);
          }
        }
        this->Controller->Send(buffer.data(), static_cast<vtkIdType>(buffer.size()), q, ValuesTag);
        return;
      }
      this->Controller->Receive(buffer.data(), static_cast<vtkIdType>(buffer.size()), q, ValuesTag);
      for (size_t i = 0; i < points.size(); ++i)
      {
        std::copy_n(&buffer[components * i], components, values + components * points[i]);
      }
    });
}

//------------------------------------------------------------------------------
void NeighborhoodGrid::Exchange(float* values, int components) const
{
  this->ExchangeValues(values, components);
}

//------------------------------------------------------------------------------
void NeighborhoodGrid::Exchange(int* values, int components) const
{
  this->ExchangeValues(values, components);
}

}
