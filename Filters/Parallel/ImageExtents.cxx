#include "ImageExtents.h"

#include "ParallelCollectives.h"
#include "vtkCommunicator.h"
#include "vtkExtentTranslator.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace volillum
{

//------------------------------------------------------------------------------
bool ExtentIsEmpty(const int extent[6])
{
  return extent[1] < extent[0] || extent[3] < extent[2] || extent[5] < extent[4];
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
}

//------------------------------------------------------------------------------
bool ExtentsCover(const std::vector<int>& extents, const int wanted[6])
{
  // What no extent so far holds, as boxes: each extent cuts the part of a box it holds out,
  // leaving at most two slabs of the box along each axis.
  std::vector<std::array<int, 6>> left;
  if (!ExtentIsEmpty(wanted))
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

template VOLILLUMPARALLEL_EXPORT long long ExchangeExtents<unsigned char>(
  vtkMultiProcessController*, const int*, const int*, const unsigned char*, const int*,
  unsigned char*, int, bool);
template VOLILLUMPARALLEL_EXPORT long long ExchangeExtents<std::uint16_t>(
  vtkMultiProcessController*, const int*, const int*, const std::uint16_t*, const int*,
  std::uint16_t*, int, bool);
template VOLILLUMPARALLEL_EXPORT long long ExchangeExtents<std::uint32_t>(
  vtkMultiProcessController*, const int*, const int*, const std::uint32_t*, const int*,
  std::uint32_t*, int, bool);

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

}
