#include "DistributedPropagation.h"

#include "DistributedClassification.h"
#include "ImageExtents.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <cstdint>

namespace volillum
{

namespace
{
constexpr int LatticeTag = 8300; // and up: one a lattice
// Slices of a wedge's classification or units that travel at once (SweepWedges).
constexpr int WedgeSlices = 16;

// The rows of the bands of a sweep: `count` bands over `n` rows, at least a row each; a band's
// own rows (the last band's also the lattices' extra row n) and its window (its own rows and
// `halo` either side: the lattice rows it reads).
struct BandRows
{
  int N;
  int Count;
  int Halo;

  void Own(int m, int& first, int& last) const
  {
    first = static_cast<int>(static_cast<long long>(this->N) * m / this->Count);
    last = static_cast<int>(static_cast<long long>(this->N) * (m + 1) / this->Count) - 1;
    last = last == this->N - 1 ? this->N : last;
  }

  void Window(int m, int& first, int& last) const
  {
    this->Own(m, first, last);
    first = std::max(0, first - this->Halo);
    last = std::min(this->N, last + this->Halo);
  }
};

// A wedge sweep's axes (along the sweep, along its rows, across them) and how its slices
// travel in chunks of WedgeSlices (one collective exchange a chunk).
struct WedgeLayout
{
  int Axis;
  int C;
  int B;
  bool Sweeping;

  // The extent of slices [k0, k1) of grid g with the rows [first[k], last[k]] of each (none
  // for a process that does not sweep).
  void Chunk(const GridGeometry& g, const std::vector<int>& first, const std::vector<int>& last,
    int k0, int k1, int extent[6]) const
  {
    for (int a = 0; a < 3; ++a)
    {
      extent[2 * a] = 0;
      extent[2 * a + 1] = g.Dimensions[a] - 1;
    }
    extent[2 * this->Axis] = k0;
    extent[2 * this->Axis + 1] = k1 - 1;
    extent[2 * this->C] =
      this->Sweeping ? *std::min_element(&first[k0], &first[k0] + (k1 - k0)) : 0;
    extent[2 * this->C + 1] =
      this->Sweeping ? *std::max_element(&last[k0], &last[k0] + (k1 - k0)) : -1;
  }

  // The offset in a buffer over such an extent (x fastest) of the first point of row r of
  // slice k, with the offset between points along B.
  long long Offset(const int extent[6], int k, int r, long long& strideB) const
  {
    const long long nx = extent[1] - extent[0] + 1, ny = extent[3] - extent[2] + 1;
    const long long stride[3] = { 1, nx, nx * ny };
    strideB = stride[this->B];
    return (k - extent[2 * this->Axis]) * stride[this->Axis] +
      (r - extent[2 * this->C]) * stride[this->C];
  }
};

// Collective: the classification of a wedge's rows (dataFirst[a] to dataLast[a] of each
// slice a along the layout's axis) gathered from the blocks, a chunk of slices at a time
// (every process takes part in each chunk's exchange). Returns the bytes this process sent.
long long GatherWedgeMaterial(vtkMultiProcessController* controller, const ClassifiedVolume& volume,
  const VolumePiece& piece, const WedgeLayout& layout, const std::vector<int>& dataFirst,
  const std::vector<int>& dataLast, WedgeVolume& material)
{
  const GridGeometry& data = piece.Whole;
  const int axis = layout.Axis, b = layout.B;
  material.Volume.Geometry = data;
  material.Volume.Channels = volume.Channels;
  material.Volume.Scale = volume.Scale;
  long long held = 0;
  for (int a = 0; a < data.Dimensions[axis] && layout.Sweeping; ++a)
  {
    material.First.push_back(dataFirst[a]);
    material.Base.push_back(held);
    held += static_cast<long long>(data.Dimensions[b]) * (dataLast[a] - dataFirst[a] + 1);
  }
  material.Volume.Properties.resize(static_cast<size_t>(volume.Channels * held));
  const int channels = volume.Channels, nb = data.Dimensions[b];
  std::vector<PackedValue> gathered;
  long long sent = 0;
  for (int a0 = 0; a0 < data.Dimensions[axis]; a0 += WedgeSlices)
  {
    const int a1 = std::min(a0 + WedgeSlices, data.Dimensions[axis]);
    int wanted[6];
    layout.Chunk(data, dataFirst, dataLast, a0, a1, wanted);
    gathered.resize(static_cast<size_t>(channels * ExtentPoints(wanted)));
    sent += GatherClassificationValues(controller, volume, piece, wanted, gathered.data());
    for (int a = a0; a < a1 && layout.Sweeping; ++a)
    {
      for (int r = dataFirst[a]; r <= dataLast[a]; ++r)
      {
        long long strideB;
        const PackedValue* from = gathered.data() + channels * layout.Offset(wanted, a, r, strideB);
        PackedValue* to = material.Volume.Properties.data() +
          channels * (material.Base[a] + static_cast<long long>(nb) * (r - dataFirst[a]));
        for (int i = 0; i < nb; ++i)
        {
          std::copy_n(from + channels * strideB * i, channels, to + channels * i);
        }
      }
    }
  }
  return sent;
}

// Collective: a wedge's units (rows rowFirst[k] to rowLast[k] of each slice k) added to the
// processes whose pieces hold its points, a chunk of slices at a time: over the chunk's
// extent, zero beyond the wedge's rows (added to the pieces, the zeros change nothing where
// the extents of the wedges' chunks overlap). Returns the bytes this process sent.
long long MoveWedgeUnits(vtkMultiProcessController* controller, const GridGeometry& target,
  const WedgeLayout& layout, const std::vector<int>& rowFirst, const std::vector<int>& rowLast,
  const FixedPointIllumination& units, bool record, const int own[6],
  FixedPointIllumination& illumination)
{
  const int nt = target.Dimensions[layout.B];
  long long at = 0, sent = 0;
  std::vector<std::uint32_t> moved;
  for (int k0 = 0; k0 < target.Dimensions[layout.Axis]; k0 += WedgeSlices)
  {
    const int k1 = std::min(k0 + WedgeSlices, target.Dimensions[layout.Axis]);
    int rows[6];
    layout.Chunk(target, rowFirst, rowLast, k0, k1, rows);
    const long long start = at;
    for (const bool recorded : { false, true })
    {
      if (recorded && !record)
      {
        continue;
      }
      const auto& values = recorded ? units.Recorded : units.Values;
      moved.assign(static_cast<size_t>(3 * ExtentPoints(rows)), 0);
      at = start;
      for (int k = k0; k < k1 && layout.Sweeping; ++k)
      {
        for (int r = rowFirst[k]; r <= rowLast[k]; ++r, at += nt)
        {
          long long strideB;
          std::uint32_t* to = moved.data() + 3 * layout.Offset(rows, k, r, strideB);
          for (int n = 0; n < nt; ++n)
          {
            std::copy_n(values.data() + 3 * (at + n), 3, to + 3 * strideB * n);
          }
        }
      }
      auto& into = recorded ? illumination.Recorded : illumination.Values;
      sent += ExchangeExtents<std::uint32_t>(
        controller, rows, rows, moved.data(), own, into.data(), 3, true);
    }
  }
  return sent;
}
}

//------------------------------------------------------------------------------
DistributedPropagation::DistributedPropagation(
  vtkMultiProcessController* controller, const std::vector<int>& extents)
  : Controller(controller)
{
  const int local = controller->GetLocalProcessId();
  for (int p = 0; p < controller->GetNumberOfProcesses(); ++p)
  {
    if (ExtentPoints(&extents[6 * p]) > 0)
    {
      this->Me = p == local ? static_cast<int>(this->Participants.size()) : this->Me;
      this->Participants.push_back(p);
    }
  }
}

//------------------------------------------------------------------------------
void DistributedPropagation::Propagate(const ClassifiedVolume& volume, const VolumePiece& piece,
  const GridGeometry& target, const std::vector<std::vector<PropagationTask>>& sweeps,
  const int own[6], FixedPointIllumination& illumination, PropagationStatistics& statistics,
  const std::function<void(double)>& progress)
{
  // A sweep's directional tasks run over bands of rows, each of its point or spot lights'
  // over wedges of its rays.
  std::vector<std::vector<PropagationTask>> bandSweeps, wedgeSweeps;
  for (const auto& sweep : sweeps)
  {
    std::vector<PropagationTask> directional;
    for (auto& light : TasksByLight(sweep, directional))
    {
      wedgeSweeps.push_back(std::move(light));
    }
    if (!directional.empty())
    {
      bandSweeps.push_back(std::move(directional));
    }
  }
  // The row axes of the band sweeps (z for sweeps along x and y, y for sweeps along z),
  // whether a task is recorded and the number of wedge sweeps, agreed by all; then the
  // groups of the wedge sweeps.
  int mine[5] = { 0, 0, 0, 0, static_cast<int>(wedgeSweeps.size()) };
  for (const auto& sweep : bandSweeps)
  {
    mine[SweepRowAxis(sweep[0].Group)] = 1;
  }
  for (const auto& sweep : sweeps)
  {
    mine[3] = std::max<int>(mine[3],
      std::any_of(sweep.begin(), sweep.end(), [](const PropagationTask& t) { return t.Recorded; }));
    statistics.Sweeps += 1;
    statistics.LightSweeps += static_cast<long long>(sweep.size());
  }
  int agreed[5];
  this->Controller->AllReduce(mine, agreed, 5, vtkCommunicator::MAX_OP);
  std::vector<int> groups(agreed[4], -1), wedgeGroups(agreed[4]);
  for (size_t i = 0; i < wedgeSweeps.size(); ++i)
  {
    groups[i] = wedgeSweeps[i][0].Group;
  }
  if (agreed[4] > 0)
  {
    this->Controller->AllReduce(
      groups.data(), wedgeGroups.data(), agreed[4], vtkCommunicator::MAX_OP);
  }
  Context context{ volume, piece, target, own, agreed[3] != 0, illumination, statistics, nullptr, 0,
    bandSweeps.size() + wedgeGroups.size() };
  context.Progress = [&context, &progress](double f)
  { progress((context.Swept + f) / context.Total); };
  for (const int rowAxis : { 2, 1 })
  {
    if (agreed[rowAxis])
    {
      this->SweepBands(context, rowAxis, bandSweeps);
    }
  }
  this->SweepWedges(context, wedgeSweeps, wedgeGroups);
}

//------------------------------------------------------------------------------
void DistributedPropagation::SweepBands(
  Context& context, int rowAxis, const std::vector<std::vector<PropagationTask>>& sweeps)
{
  const GridGeometry& target = context.Target;
  const GridGeometry& data = context.Piece.Whole;
  // The sweeps with these rows, and the lattice rows a band reads beyond its own.
  std::vector<size_t> mine;
  int halo = 1;
  for (size_t i = 0; i < sweeps.size(); ++i)
  {
    if (SweepRowAxis(sweeps[i][0].Group) == rowAxis)
    {
      mine.push_back(i);
      halo = std::max(halo, LatticeHalo(target, sweeps[i]));
    }
  }
  // A band for each of the first processes with a piece.
  const int n = target.Dimensions[rowAxis];
  const BandRows bands{ n, std::max(1, std::min(static_cast<int>(this->Participants.size()), n)),
    halo };
  const int b = this->Me < bands.Count ? this->Me : -1;
  SweepBand band;
  int rows[6] = { 0, -1, 0, -1, 0, -1 };   // the band's extent of the illumination grid
  int wanted[6] = { 0, -1, 0, -1, 0, -1 }; // the band of the data grid it reads
  if (b >= 0)
  {
    bands.Own(b, band.First, band.Last);
    band.Last = std::min(band.Last, n - 1);
    band.Halo = halo;
    // The data all of its sweeps read.
    int low = data.Dimensions[rowAxis], high = -1;
    for (const size_t i : mine)
    {
      int first, last;
      BandOfData(data, target, sweeps[i], band, halo, first, last);
      low = std::min(low, first);
      high = std::max(high, last);
    }
    for (int a = 0; a < 3; ++a)
    {
      rows[2 * a + 1] = target.Dimensions[a] - 1;
      wanted[2 * a + 1] = data.Dimensions[a] - 1;
    }
    rows[2 * rowAxis] = band.First;
    rows[2 * rowAxis + 1] = band.Last;
    wanted[2 * rowAxis] = low;
    wanted[2 * rowAxis + 1] = high;
  }
  ClassifiedVolume slab;
  this->SentBytes +=
    GatherClassification(this->Controller, context.Volume, context.Piece, wanted, slab);
  this->BandPoints = std::max(this->BandPoints, ExtentPoints(wanted));

  FixedPointIllumination units;
  units.Reset(ExtentPoints(rows), context.Illumination.Scale);
  if (context.Record)
  {
    units.StartRecord();
  }
  if (b >= 0)
  {
    const EmptyBlocks empty(slab);
    auto exchange = [&](const std::vector<float*>& lattices, size_t rowValues, int firstRow)
    { this->ExchangeLatticeRows(band, n, bands.Count, lattices, rowValues, firstRow); };
    for (const size_t i : mine)
    {
      PropagateSweepBand(slab, target, sweeps[i], band, units, exchange, context.Statistics, &empty,
        context.Progress);
      ++context.Swept;
    }
  }
  // Each band's units to the processes whose pieces hold its points (bands do not overlap).
  this->MoveUnits(context, rows, units);
}

//------------------------------------------------------------------------------
void DistributedPropagation::ExchangeLatticeRows(const SweepBand& band, int rows, int count,
  const std::vector<float*>& lattices, size_t rowValues, int firstRow)
{
  // Each band sends the bands whose windows meet its own rows those rows and gets from the
  // bands whose rows meet its window theirs: the bands up to `reach` away either side (bands
  // hold n / count rows or one more). Bands d apart meet in two steps: first the pairs whose
  // lower band lies in an even block of d bands, then the others, the lower band of a pair
  // sending first; every band is in one pair a step, so no blocking send waits in a cycle, and
  // the exchange takes 2 reach steps however many bands there are (2 when bands hold at least
  // `halo` rows).
  const BandRows bands{ rows, count, band.Halo };
  const int b = this->Me;
  const int reach = (band.Halo + rows / count - 1) / (rows / count);
  for (int d = 1; d <= reach; ++d)
  {
    for (const bool lowerFirst : { true, false })
    {
      const int m = ((b / d) % 2 == 0) == lowerFirst ? b + d : b - d;
      if (m < 0 || m >= count)
      {
        continue;
      }
      const int process = this->Participants[m];
      for (const bool send : { m > b, m < b })
      {
        // Sent: this band's rows in m's window; received: m's rows in this band's.
        int first, last, windowFirst, windowLast;
        bands.Own(send ? b : m, first, last);
        bands.Window(send ? m : b, windowFirst, windowLast);
        first = std::max(first, windowFirst);
        last = std::min(last, windowLast);
        if (first > last)
        {
          continue;
        }
        const vtkIdType size = static_cast<vtkIdType>(rowValues) * (last - first + 1);
        for (size_t j = 0; j < lattices.size(); ++j)
        {
          float* at = lattices[j] + rowValues * (first - firstRow);
          const int tag = LatticeTag + static_cast<int>(j);
          if (send)
          {
            this->Controller->Send(at, size, process, tag);
            this->SentBytes += size * static_cast<long long>(sizeof(float));
          }
          else
          {
            this->Controller->Receive(at, size, process, tag);
          }
        }
      }
    }
  }
}

//------------------------------------------------------------------------------
void DistributedPropagation::MoveUnits(
  Context& context, const int rows[6], const FixedPointIllumination& units)
{
  this->SentBytes += ExchangeExtents<std::uint32_t>(this->Controller, rows, rows,
    units.Values.data(), context.Own, context.Illumination.Values.data(), 3, true);
  if (context.Record)
  {
    this->SentBytes += ExchangeExtents<std::uint32_t>(this->Controller, rows, rows,
      units.Recorded.data(), context.Own, context.Illumination.Recorded.data(), 3, true);
  }
}

//------------------------------------------------------------------------------
void DistributedPropagation::SweepWedges(Context& context,
  const std::vector<std::vector<PropagationTask>>& sweeps, const std::vector<int>& groups)
{
  if (groups.empty())
  {
    return;
  }
  const GridGeometry& target = context.Target;
  const GridGeometry& data = context.Piece.Whole;
  // The whole grid's empty blocks: those every process's block finds empty.
  EmptyBlocks empty(data, context.Volume, context.Piece.Offset);
  std::vector<char> marks(empty.Marks().size());
  this->Controller->AllReduce(empty.Marks().data(), marks.data(),
    static_cast<vtkIdType>(marks.size()), vtkCommunicator::MIN_OP);
  empty.Marks() = std::move(marks);
  empty.Update();
  for (size_t i = 0; i < groups.size(); ++i)
  {
    const int axis = groups[i] / 2, c = SweepRowAxis(groups[i]);
    const WedgeLayout layout{ axis, c, 3 - axis - c, this->Me >= 0 };
    SweepWedge wedge;
    std::vector<int> dataFirst, dataLast, rowFirst, rowLast;
    if (layout.Sweeping)
    {
      wedge =
        SplitIntoWedges(target, sweeps[i], static_cast<int>(this->Participants.size()))[this->Me];
      WedgeOfData(data, target, sweeps[i], wedge, dataFirst, dataLast);
      WedgeRows(target, sweeps[i], wedge, rowFirst, rowLast);
    }
    // The wedge's material, per slice its rows.
    WedgeVolume material;
    this->SentBytes += GatherWedgeMaterial(
      this->Controller, context.Volume, context.Piece, layout, dataFirst, dataLast, material);
    this->BandPoints = std::max(this->BandPoints,
      static_cast<long long>(material.Volume.Properties.size()) / context.Volume.Channels);
    long long points = 0;
    for (size_t k = 0; k < rowFirst.size(); ++k)
    {
      points +=
        static_cast<long long>(target.Dimensions[layout.B]) * (rowLast[k] - rowFirst[k] + 1);
    }
    FixedPointIllumination units;
    units.Reset(points, context.Illumination.Scale);
    if (context.Record)
    {
      units.StartRecord();
    }
    if (layout.Sweeping)
    {
      PropagateSweepWedge(
        material, target, sweeps[i], wedge, units, context.Statistics, &empty, context.Progress);
    }
    material = WedgeVolume();
    this->SentBytes += MoveWedgeUnits(this->Controller, target, layout, rowFirst, rowLast, units,
      context.Record, context.Own, context.Illumination);
    ++context.Swept;
  }
}

}
