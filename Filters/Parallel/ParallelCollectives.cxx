#include "ParallelCollectives.h"

#include "ImageExtents.h"
#include "vtkAlgorithm.h"
#include "vtkBoundingBox.h"
#include "vtkCommunicator.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <limits>

namespace volillum
{

//------------------------------------------------------------------------------
vtkMultiProcessController* ParallelRun(vtkMultiProcessController* controller)
{
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
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
    total += ExtentIsEmpty(e) ? 0 : static_cast<size_t>(e[3] - e[2] + 1) * (e[5] - e[4] + 1);
  }
  const int local = controller->GetLocalProcessId();
  std::vector<T> sent, reduced;
  for (size_t p = 0; 6 * p < extents.size(); ++p)
  {
    const int* e = extents.data() + 6 * p;
    if (ExtentIsEmpty(e))
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
  if (6 * static_cast<size_t>(local) < extents.size() && !ExtentIsEmpty(extents.data() + 6 * local))
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

//------------------------------------------------------------------------------
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

}
