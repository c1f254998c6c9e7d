#include "ImageBlocks.h"

#include "ImageExtents.h"
#include "ParallelCollectives.h"
#include "TravellingPieces.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <vector>

namespace volillum
{

namespace
{
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

// Whether this process's `array` (nullptr: none) can be lit over its `piece` (nullptr: none):
// a value for each of its points (or cells); else the reason in error.
bool PieceArrayUsable(vtkImageData* piece, vtkDataArray* array, bool onCells, std::string& error)
{
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
  return error.empty();
}

// The origin, spacing and direction of `shape` set on `image`.
void TakeGeometry(vtkImageData* shape, vtkImageData* image)
{
  image->SetOrigin(shape->GetOrigin());
  image->SetSpacing(shape->GetSpacing());
  image->SetDirectionMatrix(shape->GetDirectionMatrix()->GetData());
}

// An image of the cells `wanted` (given by their first points) with the cell array `values`
// (bytes, of the type and components of `cells`), over the geometry of `input`.
vtkSmartPointer<vtkImageData> CellsAround(const int wanted[6], vtkImageData* input,
  vtkDataArray* cells, const std::vector<unsigned char>& values)
{
  auto around = vtkSmartPointer<vtkImageData>::New();
  around->SetExtent(wanted[0], wanted[1] + 1, wanted[2], wanted[3] + 1, wanted[4], wanted[5] + 1);
  around->SetOrigin(input->GetOrigin());
  around->SetSpacing(input->GetSpacing());
  auto gathered = vtk::TakeSmartPointer(cells->NewInstance());
  gathered->SetName(cells->GetName());
  gathered->SetNumberOfComponents(cells->GetNumberOfComponents());
  gathered->SetNumberOfTuples(ExtentPoints(wanted));
  std::memcpy(gathered->GetVoidPointer(0), values.data(), values.size());
  around->GetCellData()->AddArray(gathered);
  return around;
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
  vtkMultiProcessController* controller, const char* litArray, vtkImageData* piece)
{
  const int processes = controller->GetNumberOfProcesses();
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  vtkNew<vtkImageData> travelling;
  if (piece && piece->GetNumberOfPoints() > 0)
  {
    piece->GetExtent(extent);
    travelling->CopyStructure(piece);
    CopyLitArrays(litArray, piece, travelling);
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
    if (ExtentIsEmpty(e) || !image)
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
      if (ExtentIsEmpty(e) || !image)
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
vtkImageData* BlockPointScalars::Update(vtkMultiProcessController* controller, const int whole[6],
  const int* block, vtkImageData* input, vtkDataArray* cells, int component,
  const CellsToPoints& convert, std::string& error)
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
  vtkSmartPointer<vtkImageData> around = CellsAround(wanted, input, cells, values);
  const vtkSmartPointer<vtkDataArray> converted =
    convert(around, around->GetCellData()->GetArray(0), component, error);
  if (!converted)
  {
    return nullptr;
  }
  this->Points = vtkSmartPointer<vtkImageData>::New();
  this->Points->SetExtent(const_cast<int*>(block));
  this->Points->SetOrigin(input->GetOrigin());
  this->Points->SetSpacing(input->GetSpacing());
  this->Points->SetDirectionMatrix(input->GetDirectionMatrix());
  auto points = vtk::TakeSmartPointer(converted->NewInstance());
  points->SetName(cells->GetName());
  points->SetNumberOfComponents(1);
  points->SetNumberOfTuples(this->Points->GetNumberOfPoints());
  // The block's rows of the converted points (one value a point), byte for byte.
  const auto* from = static_cast<const unsigned char*>(converted->GetVoidPointer(0));
  auto* to = static_cast<unsigned char*>(points->GetVoidPointer(0));
  ForEachRow(around->GetExtent(), block, converted->GetDataTypeSize(),
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
      TakeGeometry(shape, this->Block); // (each a change only if it changed)
    }
    return block ? this->Block.Get() : nullptr;
  }
  this->Block = nullptr;
  this->Fingerprint = 0;
  std::copy_n(none, 6, this->Extent);
  if (!AllOk(controller, PieceArrayUsable(piece, array, onCells, error)))
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
    TakeGeometry(shape, this->Block);
    this->Block->GetAttributes(form[2] == 1 ? vtkDataObject::CELL : vtkDataObject::POINT)
      ->SetScalars(values);
  }
  this->Fingerprint = fingerprint;
  std::copy_n(extent, 6, this->Extent);
  std::copy_n(wantedPoints, 6, this->BlockExtent);
  return this->Block;
}

}
