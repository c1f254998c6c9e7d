#include "IlluminationParallel.h"

#include "IlluminationFilterSupport.h"
#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkExtentTranslator.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMatrix3x3.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace volillum
{

namespace
{
// A copy of the piece's structure with only the arrays the algorithm may light (the one its
// input array 0 names, in point or cell data, and the active scalars): what travels.
void CopyLitArrays(vtkAlgorithm* algorithm, vtkDataSet* piece, vtkDataSet* out)
{
  vtkInformation* info = algorithm->GetInputArrayInformation(0);
  const char* name = info && info->Has(vtkDataObject::FIELD_NAME())
    ? info->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  for (int association : { vtkDataObject::POINT, vtkDataObject::CELL })
  {
    vtkDataSetAttributes* from = piece->GetAttributes(association);
    vtkDataSetAttributes* to = out->GetAttributes(association);
    if (name && *name)
    {
      if (vtkAbstractArray* named = from->GetAbstractArray(name))
      {
        to->AddArray(named);
      }
    }
    if (vtkDataArray* scalars = from->GetScalars())
    {
      to->SetScalars(scalars);
    }
    if (vtkDataArray* ids = from->GetGlobalIds())
    {
      to->SetGlobalIds(ids);
    }
  }
}

// FNV-1a over 8-byte words (then the last bytes), continuing from hash: a change detector,
// at several GB/s.
std::uint64_t HashBytes(const void* data, size_t size, std::uint64_t hash)
{
  constexpr std::uint64_t prime = 1099511628211ULL;
  const auto* bytes = static_cast<const unsigned char*>(data);
  size_t i = 0;
  for (; i + 8 <= size; i += 8)
  {
    std::uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    hash = (hash ^ word) * prime;
  }
  for (; i < size; ++i)
  {
    hash = (hash ^ bytes[i]) * prime;
  }
  return hash;
}

std::uint64_t HashArray(vtkAbstractArray* array, std::uint64_t hash)
{
  if (!array)
  {
    return HashBytes("-", 1, hash);
  }
  const int type = array->GetDataType();
  const vtkIdType values = array->GetNumberOfValues();
  hash = HashBytes(&type, sizeof(type), hash);
  hash = HashBytes(&values, sizeof(values), hash);
  if (const char* name = array->GetName())
  {
    hash = HashBytes(name, std::strlen(name), hash);
  }
  return HashBytes(array->GetVoidPointer(0), values * array->GetDataTypeSize(), hash);
}

// A fingerprint of what a process sends: its piece's structure and lit arrays. An update that
// re-read an unchanged piece (readers may) keeps the assembled input and its classification.
std::uint64_t Fingerprint(vtkDataSet* travelling)
{
  std::uint64_t hash = 14695981039346656037ULL;
  if (auto* image = vtkImageData::SafeDownCast(travelling))
  {
    hash = HashBytes(image->GetExtent(), 6 * sizeof(int), hash);
    hash = HashBytes(image->GetOrigin(), 3 * sizeof(double), hash);
    hash = HashBytes(image->GetSpacing(), 3 * sizeof(double), hash);
    hash = HashBytes(image->GetDirectionMatrix()->GetData(), 9 * sizeof(double), hash);
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(travelling))
  {
    hash = HashArray(grid->GetPoints() ? grid->GetPoints()->GetData() : nullptr, hash);
    if (vtkCellArray* cells = grid->GetCells())
    {
      hash = HashArray(cells->GetOffsetsArray(), hash);
      hash = HashArray(cells->GetConnectivityArray(), hash);
      hash = HashArray(grid->GetCellTypesArray(), hash);
    }
  }
  for (int association : { vtkDataObject::POINT, vtkDataObject::CELL })
  {
    vtkDataSetAttributes* attributes = travelling->GetAttributes(association);
    for (int a = 0; a < attributes->GetNumberOfArrays(); ++a)
    {
      hash = HashArray(attributes->GetAbstractArray(a), hash);
    }
  }
  return hash;
}

bool IsEmpty(const int extent[6])
{
  return extent[1] < extent[0] || extent[3] < extent[2] || extent[5] < extent[4];
}

// The point extent of an image's cells.
void CellExtent(const int points[6], int cells[6])
{
  for (int a = 0; a < 3; ++a)
  {
    cells[2 * a] = points[2 * a];
    cells[2 * a + 1] = std::max(points[2 * a], points[2 * a + 1] - 1);
  }
}

// The values of a piece's attributes `from` (extent e) in the whole image's `to` (extent
// whole, allocated by CopyAllocate from a piece with the same arrays): a block copy per row
// along x where the piece lies inside and every array of `to` has one of the same name,
// type (not bits) and components in `from`, both in contiguous memory; else tuple by tuple
// (CopyStructuredData, ~40 times slower for the image of 256^3 points measured).
void CopyPiece(vtkDataSetAttributes* from, const int e[6], vtkDataSetAttributes* to,
  const int whole[6], vtkIdType wholeTuples)
{
  bool inside = true; // the piece's extent within the whole one
  for (int a = 0; a < 3; ++a)
  {
    inside = inside && e[2 * a] >= whole[2 * a] && e[2 * a + 1] <= whole[2 * a + 1];
  }
  const long long rowTuples = e[1] - e[0] + 1;
  const long long pieceTuples = rowTuples * (e[3] - e[2] + 1) * (e[5] - e[4] + 1);
  std::vector<std::pair<vtkDataArray*, vtkDataArray*>> pairs;
  for (int i = 0; i < to->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* out = to->GetArray(i);
    const char* name = out ? out->GetName() : nullptr;
    vtkDataArray* in = name ? from->GetArray(name) : nullptr;
    if (!in || in->GetNumberOfTuples() != pieceTuples || in->GetDataType() != out->GetDataType() ||
      in->GetDataTypeSize() <= 0 || !inside ||
      in->GetNumberOfComponents() != out->GetNumberOfComponents() ||
      !in->HasStandardMemoryLayout() || !out->HasStandardMemoryLayout())
    {
      to->CopyStructuredData(from, e, whole);
      return;
    }
    pairs.emplace_back(in, out);
  }
  const long long nx = whole[1] - whole[0] + 1, ny = whole[3] - whole[2] + 1;
  for (const auto& [in, out] : pairs)
  {
    if (out->GetNumberOfTuples() != wholeTuples)
    {
      out->SetNumberOfTuples(wholeTuples);
    }
    const size_t tuple = static_cast<size_t>(in->GetNumberOfComponents()) * in->GetDataTypeSize();
    const auto* source = static_cast<const unsigned char*>(in->GetVoidPointer(0));
    auto* target = static_cast<unsigned char*>(out->GetVoidPointer(0));
    for (long long z = e[4]; z <= e[5]; ++z)
    {
      for (long long y = e[2]; y <= e[3]; ++y)
      {
        const long long at = (e[0] - whole[0]) + nx * ((y - whole[2]) + ny * (z - whole[4]));
        std::memcpy(target + tuple * at, source, tuple * rowTuples);
        source += tuple * rowTuples;
      }
    }
  }
}
}

namespace
{
// Message tags of NeighborhoodGrid.
constexpr int CellsTag = 8270, CountTag = 8271, KeysTag = 8272, ValuesTag = 8273, MaskTag = 8275;

// Where the cells of the pieces lie: bins over the bounds of all pieces, about `depth`
// wide (at most 64 a side), a bit per bin.
class BinMask
{
public:
  BinMask(const double bounds[6], double depth)
  {
    for (int a = 0; a < 3; ++a)
    {
      const double extent = bounds[2 * a + 1] - bounds[2 * a];
      this->Origin[a] = bounds[2 * a];
      this->Bins[a] = extent > 0.0 && depth > 0.0
        ? static_cast<int>(std::min(64.0, std::max(1.0, std::ceil(extent / depth))))
        : 1;
      this->Size[a] = extent > 0.0 ? extent / this->Bins[a] : 1.0;
    }
    this->Bits.assign((this->Count() + 7) / 8, 0);
  }

  size_t Count() const
  {
    return static_cast<size_t>(this->Bins[0]) * this->Bins[1] * this->Bins[2];
  }

  // Calls visit(bin) for each bin the box overlaps until it returns true; returns whether it
  // did.
  template <typename Visit>
  bool AnyBin(const double box[6], Visit&& visit) const
  {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      const auto at = [&](double x)
      {
        const double f = std::floor((x - this->Origin[a]) / this->Size[a]);
        return static_cast<int>(std::min(std::max(f, 0.0), this->Bins[a] - 1.0));
      };
      lo[a] = at(box[2 * a]);
      hi[a] = at(box[2 * a + 1]);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
    {
      for (int j = lo[1]; j <= hi[1]; ++j)
      {
        for (int i = lo[0]; i <= hi[0]; ++i)
        {
          if (visit(this->Index(i, j, k)))
          {
            return true;
          }
        }
      }
    }
    return false;
  }

  // Marks the bins the box overlaps.
  void Mark(const double box[6])
  {
    this->AnyBin(box,
      [this](size_t bin)
      {
        this->Bits[bin / 8] |= static_cast<unsigned char>(1u << (bin % 8));
        return false;
      });
  }

  // Whether the box grown by depth overlaps a bin marked in `bits` (another mask's).
  bool Meets(const unsigned char* bits, const double box[6], double depth) const
  {
    const double grown[6] = { box[0] - depth, box[1] + depth, box[2] - depth, box[3] + depth,
      box[4] - depth, box[5] + depth };
    return this->AnyBin(grown, [bits](size_t bin) { return Marked(bits, bin); });
  }

  // The whole bins within depth along each axis.
  std::array<int, 3> Reach(double depth) const
  {
    std::array<int, 3> reach;
    for (int d = 0; d < 3; ++d)
    {
      reach[d] = static_cast<int>(std::ceil(depth / this->Size[d]));
    }
    return reach;
  }

  // The bin indices (lowest, highest along each axis) of the marked bins; lowest above
  // highest when none is marked.
  std::array<int, 6> MarkedBox() const
  {
    std::array<int, 6> box = { this->Bins[0], -1, this->Bins[1], -1, this->Bins[2], -1 };
    for (int k = 0; k < this->Bins[2]; ++k)
    {
      for (int j = 0; j < this->Bins[1]; ++j)
      {
        for (int i = 0; i < this->Bins[0]; ++i)
        {
          if (this->Marked(this->Bits.data(), this->Index(i, j, k)))
          {
            const int at[3] = { i, j, k };
            for (int d = 0; d < 3; ++d)
            {
              box[2 * d] = std::min(box[2 * d], at[d]);
              box[2 * d + 1] = std::max(box[2 * d + 1], at[d]);
            }
          }
        }
      }
    }
    return box;
  }

  // The marked bins grown by `reach` bins along each axis (a box around each, one axis at a
  // time): a bin of another mask lies within reach of a marked one exactly where the
  // grown bits and the other's share a bit, the same answer seen from either mask.
  std::vector<unsigned char> Grown(const std::array<int, 3>& reach) const
  {
    std::vector<unsigned char> bins(this->Count());
    for (size_t b = 0; b < bins.size(); ++b)
    {
      bins[b] = this->Marked(this->Bits.data(), b);
    }
    std::vector<unsigned char> line;
    for (int d = 0; d < 3; ++d)
    {
      // Lines along d: `stride` apart from bin to bin, starting at every bin of the other
      // two axes.
      const size_t stride = d == 0 ? 1 : d == 1 ? this->Bins[0] : this->Count() / this->Bins[2];
      const int n = this->Bins[d];
      line.resize(n);
      for (size_t outer = 0; outer < this->Count(); outer += stride * n)
      {
        for (size_t first = outer; first < outer + stride; ++first)
        {
          for (int i = 0; i < n; ++i)
          {
            line[i] = bins[first + i * stride];
          }
          for (int i = 0; i < n; ++i)
          {
            unsigned char any = 0;
            for (int m = std::max(0, i - reach[d]); m <= std::min(n - 1, i + reach[d]); ++m)
            {
              any |= line[m];
            }
            bins[first + i * stride] = any;
          }
        }
      }
    }
    std::vector<unsigned char> bits(this->Bits.size(), 0);
    for (size_t b = 0; b < bins.size(); ++b)
    {
      bits[b / 8] |= static_cast<unsigned char>(bins[b] << (b % 8));
    }
    return bits;
  }

  // Whether two bit masks share a marked bin.
  static bool Share(const std::vector<unsigned char>& a, const unsigned char* b)
  {
    for (size_t i = 0; i < a.size(); ++i)
    {
      if (a[i] & b[i])
      {
        return true;
      }
    }
    return false;
  }

  static bool Marked(const unsigned char* bits, size_t bin)
  {
    return ((bits[bin / 8] >> (bin % 8)) & 1) != 0;
  }

  size_t Index(int i, int j, int k) const
  {
    return i + static_cast<size_t>(this->Bins[0]) * (j + static_cast<size_t>(this->Bins[1]) * k);
  }

  double Origin[3];
  double Size[3];
  int Bins[3];
  std::vector<unsigned char> Bits;
};

// The cells of grid whose bounding boxes grown by depth meet the bins marked in `bits`, with
// their points and arrays.
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

// A point's key: its global id (first value) or its coordinates.
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

//------------------------------------------------------------------------------
vtkMultiProcessController* ParallelRun(vtkMultiProcessController* controller)
{
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
}

//------------------------------------------------------------------------------
void TargetPieceExtent(const int whole[6], const int target[3], const int piece[6], int out[6])
{
  for (int a = 0; a < 3; ++a)
  {
    const int cells = whole[2 * a + 1] - whole[2 * a];
    const double ratio = cells > 0 ? static_cast<double>(target[a] - 1) / cells : 0.0;
    // Rounding slack: a piece boundary that falls on an illumination point keeps it.
    constexpr double slack = 1e-9;
    const double first = (piece[2 * a] - whole[2 * a]) * ratio;
    const double last = (piece[2 * a + 1] - whole[2 * a]) * ratio;
    out[2 * a] = std::max(0, static_cast<int>(std::floor(first + slack)));
    out[2 * a + 1] = std::min(target[a] - 1, static_cast<int>(std::ceil(last - slack)));
  }
}

//------------------------------------------------------------------------------
bool DistributedInput::Changed(vtkMultiProcessController* controller, vtkDataSet* travelling)
{
  const std::uint64_t fingerprint = Fingerprint(travelling);
  int changed = !this->Whole || fingerprint != this->PieceFingerprint;
  int any = 0;
  controller->AllReduce(&changed, &any, 1, vtkCommunicator::LOGICAL_OR_OP);
  this->PieceFingerprint = fingerprint;
  return any != 0;
}

//------------------------------------------------------------------------------
vtkImageData* DistributedInput::Image(
  vtkMultiProcessController* controller, vtkAlgorithm* algorithm, vtkImageData* piece)
{
  const int processes = controller->GetNumberOfProcesses();
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  vtkNew<vtkImageData> travelling;
  if (piece && piece->GetNumberOfPoints() > 0)
  {
    piece->GetExtent(extent);
    travelling->CopyStructure(piece);
    CopyLitArrays(algorithm, piece, travelling);
  }
  if (!this->Changed(controller, travelling))
  {
    return vtkImageData::SafeDownCast(this->Whole);
  }
  std::vector<int> extents(6 * static_cast<size_t>(processes));
  controller->AllGather(extent, extents.data(), 6);
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->AllGather(travelling, pieces);

  // The union of the pieces' extents, and the first non-empty piece as the template of
  // the arrays and of the grid's origin, spacing and direction.
  auto whole = vtkSmartPointer<vtkImageData>::New();
  int wholeExtent[6] = { 0, -1, 0, -1, 0, -1 };
  vtkImageData* first = nullptr;
  for (int p = 0; p < processes; ++p)
  {
    const int* e = extents.data() + 6 * p;
    auto* image = vtkImageData::SafeDownCast(pieces[p]);
    if (IsEmpty(e) || !image)
    {
      continue;
    }
    for (int a = 0; a < 3; ++a)
    {
      wholeExtent[2 * a] = first ? std::min(wholeExtent[2 * a], e[2 * a]) : e[2 * a];
      wholeExtent[2 * a + 1] =
        first ? std::max(wholeExtent[2 * a + 1], e[2 * a + 1]) : e[2 * a + 1];
    }
    if (!first)
    {
      first = image;
    }
  }
  if (first)
  {
    vtkImageData* geometry = piece && piece->GetNumberOfPoints() > 0 ? piece : first;
    whole->SetOrigin(geometry->GetOrigin());
    whole->SetSpacing(geometry->GetSpacing());
    whole->SetDirectionMatrix(geometry->GetDirectionMatrix());
    whole->SetExtent(wholeExtent);
    int wholeCells[6];
    CellExtent(wholeExtent, wholeCells);
    whole->GetPointData()->CopyAllocate(first->GetPointData(), whole->GetNumberOfPoints());
    whole->GetCellData()->CopyAllocate(first->GetCellData(), whole->GetNumberOfCells());
    for (int p = 0; p < processes; ++p)
    {
      int* e = extents.data() + 6 * p;
      auto* image = vtkImageData::SafeDownCast(pieces[p]);
      if (IsEmpty(e) || !image)
      {
        continue;
      }
      int cells[6];
      CellExtent(e, cells);
      CopyPiece(
        image->GetPointData(), e, whole->GetPointData(), wholeExtent, whole->GetNumberOfPoints());
      CopyPiece(
        image->GetCellData(), cells, whole->GetCellData(), wholeCells, whole->GetNumberOfCells());
    }
  }
  this->Whole = whole;
  return whole;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> PieceWithoutGhostCells(
  vtkAlgorithm* algorithm, vtkUnstructuredGrid* piece)
{
  if (!piece || piece->GetNumberOfCells() == 0)
  {
    return nullptr;
  }
  vtkNew<vtkUnstructuredGrid> travelling;
  CopyLitArrays(algorithm, piece, travelling);
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
  const vtkIdType bad = FirstBadCoordinate(
    piece && piece->GetPoints() ? piece->GetPoints()->GetData() : nullptr, MaximumCoordinate);
  if (bad >= 0)
  {
    std::ostringstream message;
    message << "Point " << bad << " of this process's piece has a coordinate that is not a "
            << "finite number within +-" << MaximumCoordinate << ".";
    error = message.str();
  }
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
  // Candidates: the processes whose marked bins' box comes within reach of this piece's
  // (one box of 6 bin indices a process travels to all). Only candidates exchange masks,
  // and peers are the candidates with cells in bins within reach of this piece's: the
  // same relation seen from both, so no process waits for a peer that does not count it
  // as one.
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
  this->Peers.clear();
  std::vector<const unsigned char*> peerMasks;
  for (size_t k = 0; k < candidates.size(); ++k)
  {
    if (BinMask::Share(grown, masks.data() + bytes * k))
    {
      this->Peers.push_back(candidates[k]);
      peerMasks.push_back(masks.data() + bytes * k);
    }
  }

  // The cells of each peer near this piece.
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> received(this->Peers.size());
  WithEachPeer(local, this->Peers,
    [&](size_t k, bool send)
    {
      const int q = this->Peers[k];
      if (send)
      {
        controller->Send(CellsNear(piece, mask, peerMasks[k], depth), q, CellsTag);
      }
      else
      {
        received[k] = vtkSmartPointer<vtkUnstructuredGrid>::New();
        controller->Receive(received[k], q, CellsTag);
      }
    });

  // The piece, then the others' cells; a point of a later grid at the place (or with the
  // global id) of an earlier one is that point.
  this->Grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  this->PiecePoints = has ? piece->GetNumberOfPoints() : 0;
  this->PieceCells = has ? piece->GetNumberOfCells() : 0;
  this->Owned.clear();
  vtkUnstructuredGrid* grid = this->Grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  grid->SetPoints(points);
  if (!has)
  {
    grid->AllocateEstimate(0, 4);
    return this->Grid;
  }
  // The arrays by name: a grid that travelled may hold them in another order (the global ids
  // first), and copying by index would mix them (the lit array taking the ids' values).
  // Grids without points may have lost their arrays on the way: they add nothing.
  vtkDataSetAttributes::FieldList pointFields, cellFields;
  pointFields.IntersectFieldList(piece->GetPointData());
  cellFields.IntersectFieldList(piece->GetCellData());
  for (const auto& from : received)
  {
    if (from->GetNumberOfPoints() > 0)
    {
      pointFields.IntersectFieldList(from->GetPointData());
      cellFields.IntersectFieldList(from->GetCellData());
    }
  }
  grid->GetPointData()->CopyGlobalIdsOn();
  grid->GetPointData()->CopyAllocate(pointFields);
  grid->GetCellData()->CopyAllocate(cellFields);
  const bool byId = piece->GetPointData()->GetGlobalIds() != nullptr;
  std::map<std::array<double, 3>, vtkIdType> known;
  std::vector<int> owner;
  this->Reads.assign(this->Peers.size(), {});
  vtkNew<vtkIdList> cell;
  // A cell that two pieces hold (D3's "Duplicate cells" boundary mode gives the cells across a
  // boundary to both pieces, unmarked) counts once, as the lowest process's: a cell is known
  // by its type and its points' keys in order. Per cell that came from a peer: the lowest
  // process that holds it, and whether the grid has it yet.
  vtkNew<vtkIdList> keyed;
  const auto cellKey = [&](vtkUnstructuredGrid* from, vtkIdType c)
  {
    from->GetCellPoints(c, keyed);
    std::vector<std::array<double, 3>> keys(static_cast<size_t>(keyed->GetNumberOfIds()));
    for (size_t k = 0; k < keys.size(); ++k)
    {
      keys[k] = PointKey(from, keyed->GetId(static_cast<vtkIdType>(k)), byId);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<double> key(1, static_cast<double>(from->GetCellType(c)));
    for (const auto& k : keys)
    {
      key.insert(key.end(), k.begin(), k.end());
    }
    return key;
  };
  struct Holding
  {
    int Lowest;   // process
    bool Present; // in the grid
  };
  using Held = std::map<std::vector<double>, Holding>;
  Held held;
  std::vector<std::vector<Held::iterator>> heldOf(this->Peers.size()); // per peer and cell
  for (size_t k = 0; k < this->Peers.size(); ++k)
  {
    heldOf[k].reserve(static_cast<size_t>(received[k]->GetNumberOfCells()));
    for (vtkIdType c = 0; c < received[k]->GetNumberOfCells(); ++c)
    {
      const auto entry = held.emplace(cellKey(received[k], c), Holding{ this->Peers[k], false });
      entry.first->second.Lowest = std::min(entry.first->second.Lowest, this->Peers[k]);
      heldOf[k].push_back(entry.first);
    }
  }
  // Only a piece cell whose points are all among the peers' can be one of theirs.
  std::vector<char> shared(static_cast<size_t>(piece->GetNumberOfPoints()), 0);
  if (!held.empty())
  {
    std::set<std::array<double, 3>> peerPoints;
    for (const auto& from : received)
    {
      for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i)
      {
        peerPoints.insert(PointKey(from, i, byId));
      }
    }
    for (vtkIdType i = 0; i < piece->GetNumberOfPoints(); ++i)
    {
      shared[i] = peerPoints.count(PointKey(piece, i, byId)) != 0;
    }
  }
  const auto mayBeShared = [&](vtkIdType c)
  {
    piece->GetCellPoints(c, keyed);
    for (vtkIdType k = 0; k < keyed->GetNumberOfIds(); ++k)
    {
      if (!shared[keyed->GetId(k)])
      {
        return false;
      }
    }
    return true;
  };
  // `from`: the piece (peer -1) or the cells of peer k; `input`: its index in the field lists.
  int input = 0;
  const auto append = [&](vtkUnstructuredGrid* from, int process, int peer)
  {
    if (from->GetNumberOfPoints() == 0)
    {
      return;
    }
    std::vector<vtkIdType> ids(static_cast<size_t>(from->GetNumberOfPoints()));
    std::vector<std::pair<std::array<double, 3>, vtkIdType>> added;
    for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i)
    {
      const auto key = PointKey(from, i, byId);
      const auto found = process == local ? known.end() : known.find(key);
      if (found != known.end())
      {
        ids[i] = found->second;
        continue;
      }
      ids[i] = points->InsertNextPoint(from->GetPoint(i));
      grid->GetPointData()->CopyData(pointFields, from->GetPointData(), input, i, ids[i]);
      added.emplace_back(key, ids[i]);
      if (peer >= 0)
      {
        this->Reads[peer].push_back(ids[i]); // a point of that peer's piece
      }
    }
    known.insert(added.begin(), added.end()); // the first point at a place is kept
    owner.resize(static_cast<size_t>(points->GetNumberOfPoints()), processes);
    for (vtkIdType c = 0; c < from->GetNumberOfCells(); ++c)
    {
      if (peer >= 0)
      {
        Holding& holding = heldOf[peer][c]->second;
        if (holding.Present)
        {
          continue; // already here
        }
        holding.Present = true;
      }
      else if (!held.empty() && mayBeShared(c))
      {
        const auto found = held.find(cellKey(piece, c));
        if (found != held.end() && found->second.Lowest < local)
        {
          continue; // a lower process's cell
        }
        if (found != held.end())
        {
          found->second.Present = true;
        }
      }
      from->GetCellPoints(c, cell);
      for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
      {
        cell->SetId(k, ids[cell->GetId(k)]);
        owner[cell->GetId(k)] = std::min(owner[cell->GetId(k)], process);
      }
      const vtkIdType id = grid->InsertNextCell(from->GetCellType(c), cell);
      grid->GetCellData()->CopyData(cellFields, from->GetCellData(), input, c, id);
    }
    ++input;
  };
  append(piece, local, -1);
  this->PieceCells = grid->GetNumberOfCells();
  // Points of the piece in none of its cells (those of its ghost cells, as D3 leaves them):
  // where another piece's cells hold them, they are that piece's points.
  const std::vector<int> inPieceCells(owner.begin(), owner.begin() + this->PiecePoints);
  for (size_t k = 0; k < this->Peers.size(); ++k)
  {
    append(received[k], this->Peers[k], static_cast<int>(k));
  }
  received.clear();
  grid->Squeeze();

  // Computed here: the points of the piece's cells, and those in no cell (lit as serially);
  // the piece's other points are read from the lowest process whose cells hold them (it
  // computes them: all the cells around a point of a piece are here, so that process is
  // known). Owned: computed here, and not of a lower process's piece.
  const vtkIdType np = grid->GetNumberOfPoints();
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
  this->Sends.assign(this->Peers.size(), {});
  // Tell each peer which points of its piece are read here (by key), in the order of Reads.
  WithEachPeer(local, this->Peers,
    [&](size_t k, bool send)
    {
      const int q = this->Peers[k];
      if (send)
      {
        std::vector<double> keys;
        keys.reserve(3 * this->Reads[k].size());
        for (vtkIdType p : this->Reads[k])
        {
          const auto key = PointKey(grid, p, byId);
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
  return this->Grid;
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

//------------------------------------------------------------------------------
void UnionOfBounds(vtkMultiProcessController* controller, vtkDataSet* piece, double bounds[6])
{
  const double huge = std::numeric_limits<double>::max();
  double low[3] = { huge, huge, huge }, high[3] = { -huge, -huge, -huge };
  if (piece && piece->GetNumberOfPoints() > 0)
  {
    const double* b = piece->GetBounds();
    for (int a = 0; a < 3; ++a)
    {
      low[a] = b[2 * a];
      high[a] = b[2 * a + 1];
    }
  }
  double wholeLow[3], wholeHigh[3];
  controller->AllReduce(low, wholeLow, 3, vtkCommunicator::MIN_OP);
  controller->AllReduce(high, wholeHigh, 3, vtkCommunicator::MAX_OP);
  for (int a = 0; a < 3; ++a)
  {
    bounds[2 * a] = wholeLow[a];
    bounds[2 * a + 1] = wholeHigh[a];
  }
}

//------------------------------------------------------------------------------
std::vector<int> GatherExtents(vtkMultiProcessController* controller, const int* extent)
{
  const int none[6] = { 0, -1, 0, -1, 0, -1 };
  std::vector<int> extents(6 * static_cast<size_t>(controller->GetNumberOfProcesses()));
  controller->AllGather(extent ? extent : none, extents.data(), 6);
  return extents;
}

//------------------------------------------------------------------------------
namespace
{
// For each process's extent, in blocks of whole rows of at most `block` values: this
// process's values of the block from `fill`, reduced with `op` to the extent's process,
// which gets them through `receive`.
template <typename T>
void ReduceBlocks(vtkMultiProcessController* controller, const std::vector<int>& extents,
  int components, int op, size_t block, const PieceRows<T>& fill, const PieceRows<const T>& receive,
  const std::function<void(double)>& progress = nullptr)
{
  size_t total = 0, done = 0; // rows
  for (size_t p = 0; 6 * p < extents.size(); ++p)
  {
    const int* e = extents.data() + 6 * p;
    total += IsEmpty(e) ? 0 : static_cast<size_t>(e[3] - e[2] + 1) * (e[5] - e[4] + 1);
  }
  const int local = controller->GetLocalProcessId();
  std::vector<T> sent, reduced;
  for (size_t p = 0; 6 * p < extents.size(); ++p)
  {
    const int* e = extents.data() + 6 * p;
    if (IsEmpty(e))
    {
      continue;
    }
    // The piece's rows along x, whole rows per block.
    const size_t row = components * static_cast<size_t>(e[1] - e[0] + 1);
    const size_t rows = static_cast<size_t>(e[3] - e[2] + 1) * (e[5] - e[4] + 1);
    const size_t perBlock = std::max<size_t>(1, block / row);
    for (size_t first = 0; first < rows; first += perBlock)
    {
      const size_t count = std::min(perBlock, rows - first);
      sent.resize(count * row);
      reduced.resize(sent.size());
      fill(e, first, count, sent.data());
      done += count;
      if (progress)
      {
        progress(static_cast<double>(done) / total);
      }
      // Only the owner reads the reduced values.
      controller->Reduce(
        sent.data(), reduced.data(), static_cast<vtkIdType>(sent.size()), op, static_cast<int>(p));
      if (static_cast<int>(p) == local)
      {
        receive(e, first, count, reduced.data());
      }
    }
  }
}
}

void SumOverPieces(vtkMultiProcessController* controller, const int dimensions[3],
  const std::vector<int>& extents, const std::uint32_t* values, std::vector<std::uint32_t>& own)
{
  const size_t nx = dimensions[0], ny = dimensions[1];
  own.clear();
  const int local = controller->GetLocalProcessId();
  if (6 * static_cast<size_t>(local) < extents.size() && !IsEmpty(extents.data() + 6 * local))
  {
    const int* e = extents.data() + 6 * local;
    own.resize(3 * static_cast<size_t>(e[1] - e[0] + 1) * (e[3] - e[2] + 1) * (e[5] - e[4] + 1));
  }
  ReduceBlocks<std::uint32_t>(
    controller, extents, 3, vtkCommunicator::SUM_OP, size_t(1) << 22,
    [&](const int* e, size_t first, size_t count, std::uint32_t* block)
    {
      const size_t row = 3 * static_cast<size_t>(e[1] - e[0] + 1);
      const size_t rowsY = e[3] - e[2] + 1;
      for (size_t r = 0; r < count; ++r)
      {
        const size_t y = e[2] + (first + r) % rowsY, z = e[4] + (first + r) / rowsY;
        const std::uint32_t* from = values + 3 * (e[0] + nx * (y + ny * z));
        std::copy(from, from + row, block + r * row);
      }
    },
    [&](const int* e, size_t first, size_t count, const std::uint32_t* sums)
    {
      const size_t row = 3 * static_cast<size_t>(e[1] - e[0] + 1);
      std::copy(sums, sums + count * row, own.data() + first * row);
    });
}

void ReduceOverPieces(vtkMultiProcessController* controller, const std::vector<int>& extents,
  int components, int operation, const PieceRows<double>& fill,
  const PieceRows<const double>& receive, const std::function<void(double)>& progress)
{
  ReduceBlocks<double>(
    controller, extents, components, operation, size_t(1) << 20, fill, receive, progress);
}

bool ProcessBlock(vtkMultiProcessController* controller, const int whole[6], int block[6])
{
  vtkNew<vtkExtentTranslator> translator;
  int extent[6];
  std::copy(whole, whole + 6, extent);
  return translator->PieceToExtentThreadSafe(controller->GetLocalProcessId(),
           controller->GetNumberOfProcesses(), 0, extent, block, vtkExtentTranslator::BLOCK_MODE,
           0) != 0;
}

bool ExtentHolds(const int outer[6], const int inner[6])
{
  for (int a = 0; a < 3; ++a)
  {
    if (inner[2 * a] < outer[2 * a] || outer[2 * a + 1] < inner[2 * a + 1])
    {
      return false;
    }
  }
  return true;
}

long long ExtentPoints(const int extent[6])
{
  long long points = 1;
  for (int a = 0; a < 3; ++a)
  {
    points *= std::max(0, extent[2 * a + 1] - extent[2 * a] + 1);
  }
  return points;
}

namespace
{
constexpr int ExtentValuesTag = 8274;

// The intersection of two extents; false when empty.
bool Intersect(const int* a, const int* b, int* out)
{
  bool some = true;
  for (int i = 0; i < 3; ++i)
  {
    out[2 * i] = std::max(a[2 * i], b[2 * i]);
    out[2 * i + 1] = std::min(a[2 * i + 1], b[2 * i + 1]);
    some = some && out[2 * i] <= out[2 * i + 1];
  }
  return some;
}

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

// `count` values copied from `from` to `to`, or added to them with `add` (modulo 2^32 for
// unsigned values).
template <typename T>
void CopyOrAdd(const T* from, long long count, bool add, T* to)
{
  for (long long i = 0; i < count; ++i)
  {
    to[i] = add ? static_cast<T>(to[i] + from[i]) : from[i];
  }
}

// The values of `part` of an array over `extent`, packed row after row.
template <typename T>
void Pack(const T* values, const int* extent, const int* part, int components, std::vector<T>& out)
{
  out.resize(static_cast<size_t>(components * ExtentPoints(part)));
  T* at = out.data();
  ForEachRow(extent, part, components,
    [&](long long offset, long long count) { at = std::copy_n(values + offset, count, at); });
}

// Packed values of `part` copied or added into an array over `extent`.
template <typename T>
void Unpack(const std::vector<T>& packed, const int* extent, const int* part, int components,
  bool add, T* into)
{
  const T* at = packed.data();
  ForEachRow(extent, part, components,
    [&](long long offset, long long count)
    {
      CopyOrAdd(at, count, add, into + offset);
      at += count;
    });
}

// Collective: the data type, components and association (0 points, 1 cells) of the arrays
// that processes pass (nullptr: none) in form; false when they differ. Where no process
// passes one, form[0] is the largest int.
bool AgreeOnArrays(
  vtkMultiProcessController* controller, vtkDataArray* array, int association, int form[3])
{
  constexpr int none = std::numeric_limits<int>::max();
  int local[6] = { none, none, none, -none, -none, -none };
  if (array)
  {
    local[0] = local[3] = array->GetDataType();
    local[1] = local[4] = array->GetNumberOfComponents();
    local[2] = local[5] = association;
  }
  int high[3];
  controller->AllReduce(local, form, 3, vtkCommunicator::MIN_OP);
  controller->AllReduce(local + 3, high, 3, vtkCommunicator::MAX_OP);
  return form[0] == none || std::equal(form, form + 3, high);
}

// Collective: the name of the array of the first process that passes one ("" for none).
std::string NameOfFirst(vtkMultiProcessController* controller, vtkDataArray* array)
{
  const int processes = controller->GetNumberOfProcesses();
  const int mine = array ? controller->GetLocalProcessId() : processes;
  int first = processes;
  controller->AllReduce(&mine, &first, 1, vtkCommunicator::MIN_OP);
  std::string name = array && array->GetName() ? array->GetName() : "";
  if (first == processes)
  {
    return name;
  }
  int length = static_cast<int>(name.size());
  controller->Broadcast(&length, 1, first);
  name.resize(static_cast<size_t>(length));
  if (length > 0)
  {
    controller->Broadcast(&name[0], length, first);
  }
  return name;
}
}

//------------------------------------------------------------------------------
bool ExtentsCover(const std::vector<int>& extents, const int wanted[6])
{
  // What no extent so far holds, as boxes: each extent cuts the part of a box it holds out,
  // leaving at most two slabs of the box along each axis.
  std::vector<std::array<int, 6>> left;
  if (!IsEmpty(wanted))
  {
    left.push_back({ { wanted[0], wanted[1], wanted[2], wanted[3], wanted[4], wanted[5] } });
  }
  for (size_t p = 0; p + 6 <= extents.size() && !left.empty(); p += 6)
  {
    std::vector<std::array<int, 6>> next;
    for (auto box : left)
    {
      int common[6];
      if (!Intersect(box.data(), extents.data() + p, common))
      {
        next.push_back(box);
        continue;
      }
      for (int a = 0; a < 3; ++a)
      {
        if (box[2 * a] < common[2 * a])
        {
          auto below = box;
          below[2 * a + 1] = common[2 * a] - 1;
          next.push_back(below);
        }
        if (box[2 * a + 1] > common[2 * a + 1])
        {
          auto above = box;
          above[2 * a] = common[2 * a + 1] + 1;
          next.push_back(above);
        }
        box[2 * a] = common[2 * a];
        box[2 * a + 1] = common[2 * a + 1];
      }
    }
    left = std::move(next);
  }
  return left.empty();
}

template <typename T>
long long ExchangeExtents(vtkMultiProcessController* controller, const int held[6],
  const int owned[6], const T* values, const int wanted[6], T* into, int components, bool add)
{
  const int local = controller->GetLocalProcessId();
  const int processes = controller->GetNumberOfProcesses();
  int mine[12];
  std::copy_n(owned, 6, mine);
  std::copy_n(wanted, 6, mine + 6);
  std::vector<int> all(12 * static_cast<size_t>(processes));
  controller->AllGather(mine, all.data(), 12);
  std::vector<T> buffer;
  long long sent = 0;
  int part[6];
  if (Intersect(owned, wanted, part))
  {
    // This process's own points, row by row without a packed copy (which could be the
    // whole extent).
    ForEachRowOf(held, wanted, part, components,
      [&](long long from, long long to, long long count)
      { CopyOrAdd(values + from, count, add, into + to); });
  }
  // The peers: processes that want points this one owns, or own points it wants.
  std::vector<int> peers;
  std::vector<std::array<int, 6>> sends, receives;
  for (int q = 0; q < processes; ++q)
  {
    std::array<int, 6> out, in;
    const bool send = q != local && Intersect(owned, all.data() + 12 * q + 6, out.data());
    const bool receive = q != local && Intersect(all.data() + 12 * q, wanted, in.data());
    if (send || receive)
    {
      peers.push_back(q);
      sends.push_back(send ? out : std::array<int, 6>{ { 0, -1, 0, -1, 0, -1 } });
      receives.push_back(receive ? in : std::array<int, 6>{ { 0, -1, 0, -1, 0, -1 } });
    }
  }
  WithEachPeer(local, peers,
    [&](size_t k, bool send)
    {
      const int* piece = send ? sends[k].data() : receives[k].data();
      if (ExtentPoints(piece) == 0)
      {
        return;
      }
      if (send)
      {
        Pack(values, held, piece, components, buffer);
        controller->Send(reinterpret_cast<const char*>(buffer.data()),
          static_cast<vtkIdType>(buffer.size() * sizeof(T)), peers[k], ExtentValuesTag);
        sent += static_cast<long long>(buffer.size() * sizeof(T));
        return;
      }
      buffer.resize(static_cast<size_t>(components * ExtentPoints(piece)));
      controller->Receive(reinterpret_cast<char*>(buffer.data()),
        static_cast<vtkIdType>(buffer.size() * sizeof(T)), peers[k], ExtentValuesTag);
      Unpack(buffer, wanted, piece, components, add, into);
    });
  return sent;
}

template VOLILLUMFILTERS_EXPORT long long ExchangeExtents<unsigned char>(vtkMultiProcessController*,
  const int*, const int*, const unsigned char*, const int*, unsigned char*, int, bool);
template VOLILLUMFILTERS_EXPORT long long ExchangeExtents<std::uint16_t>(vtkMultiProcessController*,
  const int*, const int*, const std::uint16_t*, const int*, std::uint16_t*, int, bool);
template VOLILLUMFILTERS_EXPORT long long ExchangeExtents<std::uint32_t>(vtkMultiProcessController*,
  const int*, const int*, const std::uint32_t*, const int*, std::uint32_t*, int, bool);

bool AllOk(vtkMultiProcessController* controller, bool ok)
{
  if (!controller)
  {
    return ok;
  }
  int mine = ok ? 1 : 0;
  int all = 0;
  controller->AllReduce(&mine, &all, 1, vtkCommunicator::MIN_OP);
  return all != 0;
}

//------------------------------------------------------------------------------
bool AgreeOnGeometry(
  vtkMultiProcessController* controller, vtkImageData* piece, vtkImageData* shape)
{
  const int processes = controller->GetNumberOfProcesses();
  const bool has = piece && piece->GetNumberOfPoints() > 0;
  const int mine = has ? controller->GetLocalProcessId() : processes;
  int first = processes;
  controller->AllReduce(&mine, &first, 1, vtkCommunicator::MIN_OP);
  if (first == processes)
  {
    return true;
  }
  // Origin, spacing, direction matrix.
  double geometry[15] = {};
  if (has)
  {
    piece->GetOrigin(geometry);
    piece->GetSpacing(geometry + 3);
    std::copy_n(piece->GetDirectionMatrix()->GetData(), 9, geometry + 6);
  }
  double agreed[15];
  std::copy_n(geometry, 15, agreed);
  controller->Broadcast(agreed, 15, first);
  bool same = true;
  const double tolerance =
    1e-9 * std::max({ std::abs(agreed[3]), std::abs(agreed[4]), std::abs(agreed[5]) });
  for (int i = 0; has && i < 15; ++i)
  {
    same = same && std::abs(geometry[i] - agreed[i]) <= (i < 6 ? tolerance : 1e-9);
  }
  shape->SetOrigin(agreed);
  shape->SetSpacing(agreed + 3);
  shape->SetDirectionMatrix(agreed + 6);
  return AllOk(controller, same);
}

//------------------------------------------------------------------------------
ParallelMessages::ParallelMessages(vtkMultiProcessController* controller, vtkAlgorithm* filter)
  : Controller(controller)
  , Filter(filter)
{
  if (this->Controller)
  {
    this->Observers[0] =
      filter->AddObserver(vtkCommand::ErrorEvent, this, &ParallelMessages::Collect);
    this->Observers[1] =
      filter->AddObserver(vtkCommand::WarningEvent, this, &ParallelMessages::Collect);
  }
}

//------------------------------------------------------------------------------
void ParallelMessages::Collect(vtkObject* caller, unsigned long event, void* text)
{
  // vtkOutputWindowDisplayErrorText (and ...WarningText) sends "ERROR: In <file>, line <n>"
  // (or "Warning: In ...") on a line of its own, then the object's description, ": " and the
  // message, then blank lines: only the message is kept.
  std::string message = text ? static_cast<const char*>(text) : "";
  if (message.rfind("ERROR: In ", 0) == 0 || message.rfind("Warning: In ", 0) == 0)
  {
    const size_t line = message.find('\n');
    message.erase(0, line == std::string::npos ? message.size() : line + 1);
  }
  const std::string description = caller->GetObjectDescription() + ": ";
  if (message.rfind(description, 0) == 0)
  {
    message.erase(0, description.size());
  }
  message.erase(message.find_last_not_of(" \n") + 1);
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Collected += event == vtkCommand::ErrorEvent ? 'E' : 'W';
  this->Collected += message;
  this->Collected += '\0';
}

//------------------------------------------------------------------------------
ParallelMessages::~ParallelMessages()
{
  vtkMultiProcessController* controller = this->Controller;
  if (!controller)
  {
    return;
  }
  this->Filter->RemoveObserver(this->Observers[0]);
  this->Filter->RemoveObserver(this->Observers[1]);
  const int processes = controller->GetNumberOfProcesses();
  const bool first = controller->GetLocalProcessId() == 0;
  vtkIdType length = static_cast<vtkIdType>(this->Collected.size());
  std::vector<vtkIdType> lengths(first ? processes : 0), offsets(first ? processes : 0);
  controller->Gather(&length, lengths.data(), 1, 0);
  vtkIdType total = 0;
  for (int p = 0; first && p < processes; ++p)
  {
    offsets[p] = total;
    total += lengths[p];
  }
  // Every process takes part even with nothing to say (a zero length).
  std::vector<char> all(std::max<vtkIdType>(total, 1));
  char none = 0;
  controller->GatherV(this->Collected.empty() ? &none : &this->Collected[0], all.data(), length,
    lengths.data(), offsets.data(), 0);
  if (!first || total == 0)
  {
    return;
  }
  std::vector<std::string> collected(processes);
  for (int p = 0; p < processes; ++p)
  {
    collected[p].assign(all.data() + offsets[p], static_cast<size_t>(lengths[p]));
  }
  vtkAlgorithm* filter = this->Filter;
  for (const Message& message : Report(collected))
  {
    if (message.Error)
    {
      vtkErrorWithObjectMacro(filter, << message.Text);
    }
    else
    {
      vtkWarningWithObjectMacro(filter, << message.Text);
    }
  }
}

//------------------------------------------------------------------------------
std::vector<ParallelMessages::Message> ParallelMessages::Report(
  const std::vector<std::string>& collected)
{
  // Each distinct message (severity and text) with the processes that reported it.
  std::vector<std::pair<std::string, std::vector<int>>> distinct;
  for (int p = 0; p < static_cast<int>(collected.size()); ++p)
  {
    const std::string& messages = collected[p];
    for (size_t at = 0; at < messages.size();)
    {
      size_t end = messages.find('\0', at);
      end = end == std::string::npos ? messages.size() : end;
      const std::string message = messages.substr(at, end - at);
      at = end + 1;
      auto found = std::find_if(distinct.begin(), distinct.end(),
        [&](const std::pair<std::string, std::vector<int>>& d) { return d.first == message; });
      if (found == distinct.end())
      {
        distinct.emplace_back(message, std::vector<int>());
        found = distinct.end() - 1;
      }
      if (found->second.empty() || found->second.back() != p)
      {
        found->second.push_back(p);
      }
    }
  }
  std::vector<Message> report;
  for (const auto& d : distinct)
  {
    const std::vector<int>& who = d.second;
    std::ostringstream text;
    text << (who.size() == 1 ? "Process " : "Processes ");
    // Runs of consecutive processes as ranges: "0-2, 5".
    for (size_t i = 0; i < who.size();)
    {
      size_t j = i;
      while (j + 1 < who.size() && who[j + 1] == who[j] + 1)
      {
        ++j;
      }
      text << (i > 0 ? ", " : "") << who[i];
      if (j > i)
      {
        text << "-" << who[j];
      }
      i = j + 1;
    }
    text << " of " << collected.size() << ": " << d.first.substr(d.first.empty() ? 0 : 1);
    report.push_back({ d.first.empty() || d.first[0] != 'W', text.str() });
  }
  return report;
}

//------------------------------------------------------------------------------
bool MustUpdateTogether(
  vtkMultiProcessController* controller, vtkAlgorithm* filter, vtkMTimeType read)
{
  if (!controller)
  {
    return true;
  }
  vtkDataObject* output = filter->GetOutputDataObject(0);
  read = std::max(read, filter->GetMTime());
  if (AllOk(controller, output && output->GetUpdateTime() > read))
  {
    return false;
  }
  filter->Modified();
  return true;
}

//------------------------------------------------------------------------------
vtkImageData* BlockPointScalars::Update(vtkMultiProcessController* controller, const int whole[6],
  const int* block, vtkImageData* input, vtkDataArray* cells, int component, std::string& error)
{
  const bool mine = block && input && cells;
  const int* extent = mine ? input->GetExtent() : nullptr;
  const bool kept = !mine ||
    (this->Points && this->Source == cells && this->SourceTime == cells->GetMTime() &&
      std::equal(extent, extent + 6, this->Extent) && this->Component == component);
  if (AllOk(controller, kept))
  {
    return mine ? this->Points.Get() : nullptr;
  }
  this->Points = nullptr;
  // Every array with a block has the same type and components (the bytes of a cell travel).
  int form[3];
  if (!AgreeOnArrays(controller, mine ? cells : nullptr, 1, form))
  {
    error = "The pieces' cell scalars differ in type or components.";
    return nullptr;
  }
  // Cells are given by their first point: those of an extent of points [a, b] are [a, b - 1].
  // A block owns its cells; a point of it is used by the cells from the one before it to its
  // own along each axis, within the image.
  int held[6] = { 0, -1, 0, -1, 0, -1 }, owned[6] = { 0, -1, 0, -1, 0, -1 },
      wanted[6] = { 0, -1, 0, -1, 0, -1 };
  if (mine)
  {
    for (int a = 0; a < 3; ++a)
    {
      held[2 * a] = extent[2 * a];
      held[2 * a + 1] = extent[2 * a + 1] - 1;
      owned[2 * a] = block[2 * a];
      owned[2 * a + 1] = block[2 * a + 1] - 1;
      wanted[2 * a] = std::max(block[2 * a] - 1, whole[2 * a]);
      wanted[2 * a + 1] = std::min(block[2 * a + 1], whole[2 * a + 1] - 1);
    }
  }
  const int bytes = mine ? cells->GetNumberOfComponents() * cells->GetDataTypeSize() : 1;
  const long long count = ExtentPoints(wanted);
  std::vector<unsigned char> values(static_cast<size_t>(bytes * count));
  ExchangeExtents<unsigned char>(controller, held, owned,
    mine ? static_cast<const unsigned char*>(cells->GetVoidPointer(0)) : nullptr, wanted,
    values.data(), bytes, false);
  if (!mine || count == 0)
  {
    return nullptr;
  }
  // The cells around the block as an image of their own, converted as a serial run converts
  // the whole image's; its points of the block are the block's.
  vtkNew<vtkImageData> around;
  around->SetExtent(wanted[0], wanted[1] + 1, wanted[2], wanted[3] + 1, wanted[4], wanted[5] + 1);
  around->SetOrigin(input->GetOrigin());
  around->SetSpacing(input->GetSpacing());
  auto gathered = vtk::TakeSmartPointer(cells->NewInstance());
  gathered->SetName(cells->GetName());
  gathered->SetNumberOfComponents(cells->GetNumberOfComponents());
  gathered->SetNumberOfTuples(count);
  std::memcpy(gathered->GetVoidPointer(0), values.data(), values.size());
  around->GetCellData()->AddArray(gathered);
  const PointScalars converted =
    ToPointScalars(around, gathered, true, component, PointScalars(), error);
  if (!converted.Array)
  {
    return nullptr;
  }
  this->Points = vtkSmartPointer<vtkImageData>::New();
  this->Points->SetExtent(const_cast<int*>(block));
  this->Points->SetOrigin(input->GetOrigin());
  this->Points->SetSpacing(input->GetSpacing());
  this->Points->SetDirectionMatrix(input->GetDirectionMatrix());
  auto points = vtk::TakeSmartPointer(converted.Array->NewInstance());
  points->SetName(cells->GetName());
  points->SetNumberOfComponents(1);
  points->SetNumberOfTuples(this->Points->GetNumberOfPoints());
  // The block's rows of the converted points (one value a point), byte for byte.
  const auto* from = static_cast<const unsigned char*>(converted.Array->GetVoidPointer(0));
  auto* to = static_cast<unsigned char*>(points->GetVoidPointer(0));
  ForEachRow(around->GetExtent(), block, converted.Array->GetDataTypeSize(),
    [&](long long offset, long long count) { to = std::copy_n(from + offset, count, to); });
  this->Points->GetPointData()->SetScalars(points);
  this->Source = cells;
  this->SourceTime = cells->GetMTime();
  std::copy_n(extent, 6, this->Extent);
  this->Component = component;
  return this->Points;
}

//------------------------------------------------------------------------------
vtkImageData* BlockOfPieces::Update(vtkMultiProcessController* controller, vtkImageData* shape,
  const int* block, vtkImageData* piece, vtkDataArray* array, bool onCells, std::string& error)
{
  const int none[6] = { 0, -1, 0, -1, 0, -1 };
  const int* extent = piece ? piece->GetExtent() : none;
  const int* wantedPoints = block ? block : none;
  // The array's content, not its time: an upstream filter whose output does not hold the
  // block asked of it runs again at every update, with new arrays of the same values.
  const int components = array ? array->GetNumberOfComponents() : 0;
  const std::uint64_t fingerprint =
    HashArray(array, HashBytes(&components, sizeof(components), onCells ? 1 : 0));
  const bool kept = (!block || this->Block) && (!piece || array) &&
    fingerprint == this->Fingerprint && std::equal(extent, extent + 6, this->Extent) &&
    std::equal(wantedPoints, wantedPoints + 6, this->BlockExtent);
  if (AllOk(controller, kept))
  {
    if (block)
    {
      // (each a change only if it changed)
      this->Block->SetOrigin(shape->GetOrigin());
      this->Block->SetSpacing(shape->GetSpacing());
      this->Block->SetDirectionMatrix(shape->GetDirectionMatrix()->GetData());
    }
    return block ? this->Block.Get() : nullptr;
  }
  this->Block = nullptr;
  this->Fingerprint = 0;
  std::copy_n(none, 6, this->Extent);
  const long long tuples = !piece ? 0
    : onCells                     ? piece->GetNumberOfCells()
                                  : piece->GetNumberOfPoints();
  if (piece && !array && error.empty())
  {
    error = "This process's piece has no numeric array to illuminate.";
  }
  else if (array && array->GetNumberOfTuples() != tuples)
  {
    error = "This process's array to illuminate does not have a value for every point or cell "
            "of its piece.";
  }
  if (!AllOk(controller, error.empty()))
  {
    return nullptr;
  }
  int form[3];
  if (!AgreeOnArrays(controller, array, onCells ? 1 : 0, form))
  {
    error = "The pieces' arrays to illuminate differ in type, components or association.";
    return nullptr;
  }
  const std::string name = NameOfFirst(controller, array);
  // Cells are given by their first point: those of an extent of points [a, b] are [a, b - 1]
  // (a piece one point thick holds none of the volume's cells).
  int held[6], wanted[6];
  std::copy_n(piece ? extent : none, 6, held);
  std::copy_n(wantedPoints, 6, wanted);
  if (form[2] == 1)
  {
    for (int a = 0; a < 3; ++a)
    {
      --held[2 * a + 1];
      --wanted[2 * a + 1];
    }
  }
  const std::vector<int> pieces = GatherExtents(controller, held);
  const bool covered = !block || ExtentsCover(pieces, wanted);
  if (!AllOk(controller, covered))
  {
    if (!covered)
    {
      error = "The pieces leave part of this process's block of the image uncovered.";
    }
    return nullptr;
  }
  const int bytes = form[1] * vtkDataArray::GetDataTypeSize(form[0]);
  auto values = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(form[0]));
  values->SetName(name.c_str());
  values->SetNumberOfComponents(form[1]);
  values->SetNumberOfTuples(ExtentPoints(wanted));
  ExchangeExtents<unsigned char>(controller, held, held,
    array ? static_cast<const unsigned char*>(array->GetVoidPointer(0)) : nullptr, wanted,
    static_cast<unsigned char*>(values->GetVoidPointer(0)), bytes, false);
  if (block)
  {
    this->Block = vtkSmartPointer<vtkImageData>::New();
    this->Block->SetExtent(const_cast<int*>(block));
    this->Block->SetOrigin(shape->GetOrigin());
    this->Block->SetSpacing(shape->GetSpacing());
    this->Block->SetDirectionMatrix(shape->GetDirectionMatrix()->GetData());
    this->Block->GetAttributes(form[2] == 1 ? vtkDataObject::CELL : vtkDataObject::POINT)
      ->SetScalars(values);
  }
  this->Fingerprint = fingerprint;
  std::copy_n(extent, 6, this->Extent);
  std::copy_n(wantedPoints, 6, this->BlockExtent);
  return this->Block;
}

}
