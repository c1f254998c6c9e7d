#include "vtkMultiLightIlluminationVolume.h"

#include "IlluminationParallel.h"
#include "RayMarchKernel.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

#include <algorithm>

vtkStandardNewMacro(vtkMultiLightIlluminationVolume);

namespace
{
constexpr int LatticeTag = 8300; // and up: one a lattice
// Slices of a wedge's classification or units that travel at once (SweepWedges).
constexpr int WedgeSlices = 16;

long long LightPropagations(const std::vector<volillum::PropagationTask>& tasks)
{
  return static_cast<long long>(tasks.size());
}

// Largest channel radiance summed over the lights that are on: a bound on the illumination
// they give any point.
double RadianceBound(const std::vector<volillum::LightState>& lights)
{
  double bound = 0.0;
  for (const auto& light : lights)
  {
    if (light.On)
    {
      const auto r = light.Radiance();
      bound += std::max(r[0], std::max(r[1], r[2]));
    }
  }
  return bound;
}
}

//------------------------------------------------------------------------------
int vtkMultiLightIlluminationVolume::GetNumberOfPendingPasses() const
{
  return volillum::CountSweeps(this->Pending, this->CoherentPropagation);
}

//------------------------------------------------------------------------------
bool vtkMultiLightIlluminationVolume::ChooseSelective(
  const std::vector<volillum::PropagationTask>& selective,
  const std::vector<volillum::PropagationTask>& full, size_t changed, size_t lights) const
{
  if (this->CostEstimate == ChangedLightFraction)
  {
    return 2 * changed <= lights;
  }
  const int selectiveSweeps = volillum::CountSweeps(selective, this->CoherentPropagation);
  const int fullSweeps = volillum::CountSweeps(full, this->CoherentPropagation);
  if (selectiveSweeps != fullSweeps)
  {
    return selectiveSweeps < fullSweeps;
  }
  return LightPropagations(selective) <= LightPropagations(full);
}

//------------------------------------------------------------------------------
vtkMultiLightIlluminationVolume::RecordPlan vtkMultiLightIlluminationVolume::PlanRecord(
  const std::vector<int>& changed, size_t lights) const
{
  RecordPlan plan;
  if (!this->RecordEditedLight)
  {
    return plan;
  }
  const int recorded = this->RecordedLight;
  if (recorded >= 0 && std::find(changed.begin(), changed.end(), recorded) != changed.end())
  {
    plan.Subtracted = recorded;
    plan.Record = recorded < static_cast<int>(lights) ? recorded : -1;
  }
  else if (changed.size() == 1 && changed[0] < static_cast<int>(lights))
  {
    plan.Record = changed[0]; // another light changed alone: the one likely to change next
  }
  else
  {
    plan.Kept = recorded; // the recorded light does not change: its record stays exact
  }
  return plan;
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::StartRecord(const RecordPlan& plan)
{
  this->RecordedLight = -1; // until the update is complete
  if (plan.Subtracted >= 0)
  {
    this->Illumination.SubtractRecord();
  }
  if (plan.Record >= 0)
  {
    this->Illumination.StartRecord();
  }
  else if (plan.Kept < 0)
  {
    // Released before a full update allocates: its peak memory holds no record.
    this->Illumination.DropRecord();
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::FinishRecord(
  const RecordPlan& plan, std::vector<volillum::PropagationTask>& remaining)
{
  // A new record is complete once none of its tasks is left for later.
  const bool complete = std::none_of(remaining.begin(), remaining.end(),
    [](const volillum::PropagationTask& t) { return t.Recorded; });
  for (auto& task : remaining)
  {
    task.Recorded = false;
  }
  if (plan.Record >= 0 && complete)
  {
    this->RecordedLight = plan.Record;
  }
  else if (plan.Kept >= 0)
  {
    this->RecordedLight = plan.Kept;
  }
  else
  {
    this->Illumination.DropRecord();
  }
}

//------------------------------------------------------------------------------
bool vtkMultiLightIlluminationVolume::MustRecompute(const std::vector<volillum::LightState>& lights,
  long long points, bool inputModified, bool distributed) const
{
  // The illumination's fixed-point scale must hold every total an update can show (the
  // states applied, the pending work and the new states together) and keep the precision of
  // the new lights' totals.
  const double bound = RadianceBound(lights);
  double largest = bound + RadianceBound(this->Applied.GetApplied());
  for (const auto& task : this->Pending)
  {
    largest += RadianceBound({ task.Light });
  }
  return inputModified || !this->Valid || !this->SelectiveUpdates ||
    distributed != this->DistributedLayout || this->Illumination.NumberOfPoints() != points ||
    !this->Illumination.Holds(largest, bound);
}

//------------------------------------------------------------------------------
bool vtkMultiLightIlluminationVolume::PrepareUpdate(const std::vector<volillum::LightState>& lights,
  const double bounds[6], long long points, bool mustRecompute,
  std::vector<volillum::PropagationTask>& work, RecordPlan& plan)
{
  std::vector<volillum::PropagationTask> full;
  for (const auto& light : lights)
  {
    const auto tasks = volillum::TasksForLight(light, +1, bounds);
    full.insert(full.end(), tasks.begin(), tasks.end());
  }
  const auto& applied = this->Applied.GetApplied();
  bool selective = false;
  if (!mustRecompute)
  {
    // Remove the applied states of the changed lights and add their new states, after the
    // work an earlier update left pending (see RecordPlan for the recorded light).
    const std::vector<int> changed = this->Applied.ChangedLights(lights);
    plan = this->PlanRecord(changed, lights.size());
    std::vector<volillum::PropagationTask> changes;
    for (int i : changed)
    {
      if (i < static_cast<int>(applied.size()) && i != plan.Subtracted)
      {
        const auto removal = volillum::TasksForLight(applied[i], -1, bounds);
        changes.insert(changes.end(), removal.begin(), removal.end());
      }
      if (i < static_cast<int>(lights.size()))
      {
        auto addition = volillum::TasksForLight(lights[i], +1, bounds);
        for (auto& task : addition)
        {
          task.Recorded = i == plan.Record;
        }
        changes.insert(changes.end(), addition.begin(), addition.end());
      }
    }
    work = this->Pending;
    work.insert(work.end(), changes.begin(), changes.end());
    selective =
      this->ChooseSelective(work, full, changed.size(), std::max(lights.size(), applied.size()));
  }
  this->Valid = false;
  if (!selective)
  {
    plan = RecordPlan();
  }
  this->StartRecord(plan);
  if (!selective)
  {
    this->Illumination.Reset(
      points, volillum::FixedPointIllumination::ScaleFor(RadianceBound(lights)));
    work = full;
  }
  this->LastStatistics = volillum::PropagationStatistics();
  return selective;
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::CommitUpdate(bool selective, const RecordPlan& plan,
  std::vector<volillum::PropagationTask>& remaining,
  const std::vector<volillum::LightState>& lights, bool distributed, UpdateReport& report)
{
  this->FinishRecord(plan, remaining);
  this->Pending = remaining;
  this->Applied.Commit(lights);
  this->Valid = true;
  this->DistributedLayout = distributed;
  report.Mode = selective ? 1 : 0;
  report.Passes = this->LastStatistics.Sweeps;
  report.PendingPasses = this->GetNumberOfPendingPasses();
}

//------------------------------------------------------------------------------
bool vtkMultiLightIlluminationVolume::ComputeIllumination(const volillum::ClassifiedVolume& volume,
  const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
  bool inputModified, float* rgb, UpdateReport& report)
{
  double bounds[6];
  target.GetBounds(bounds);
  RecordPlan plan;
  std::vector<volillum::PropagationTask> work;
  const bool selective = this->PrepareUpdate(lights, bounds, target.NumberOfPoints(),
    this->MustRecompute(lights, target.NumberOfPoints(), inputModified, false), work, plan);
  std::vector<volillum::PropagationTask> remaining;
  // In a parallel run every process propagates its share of the sweeps into its own units
  // (OutputIllumination sums them); such a run does not stop halfway.
  const volillum::SweepShare share = this->GetSweepShare();
  auto progress = [this, &share](double f)
  { return this->ReportProgress(f) || share.Processes > 1; };
  if (!volillum::PropagateTasks(volume, target, work, this->CoherentPropagation,
        this->MaximumPassesPerUpdate, this->Illumination, remaining, this->LastStatistics, progress,
        this->GetEmptyBlocks(), true, share))
  {
    // The accumulated illumination is partly updated: the next update starts afresh.
    this->Pending.clear();
    this->Applied.Reset();
    this->Illumination.DropRecord();
    return false;
  }
  this->CommitUpdate(selective, plan, remaining, lights, false, report);
  this->OutputIllumination(this->Illumination, target, rgb);
  return true;
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::AddOutputFieldData(vtkFieldData* fieldData)
{
  if (this->DistributedLayout)
  {
    volillum::AddCountFieldData(fieldData, "BandPoints", this->BandPoints);
    volillum::AddCountFieldData(fieldData, "SentBytes", this->SentBytes);
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::ComputeDistributedIllumination(
  vtkMultiProcessController* controller, const volillum::ClassifiedVolume& volume,
  const volillum::VolumePiece& piece, const std::vector<volillum::LightState>& lights,
  const volillum::GridGeometry& target, const std::vector<int>& extents, bool inputModified,
  float* rgb, UpdateReport& report)
{
  this->BandPoints = 0;
  this->SentBytes = 0;
  this->LastStatistics = volillum::PropagationStatistics();
  // The processes with a piece (of the data and so of the illumination grid) sweep. The
  // others know no lights (they have no frame for them) and only take part in the
  // collective calls.
  Bands bands;
  bands.Controller = controller;
  const int local = controller->GetLocalProcessId();
  for (int p = 0; p < controller->GetNumberOfProcesses(); ++p)
  {
    if (volillum::ExtentPoints(&extents[6 * p]) > 0)
    {
      bands.Me = p == local ? static_cast<int>(bands.Participants.size()) : bands.Me;
      bands.Participants.push_back(p);
    }
  }
  const int* own = &extents[6 * local];
  const long long points = volillum::ExtentPoints(own);
  // Every process makes the same kind of update.
  const bool mustRecompute = !volillum::AllOk(
    controller, bands.Me < 0 || !this->MustRecompute(lights, points, inputModified, true));
  double bounds[6];
  target.GetBounds(bounds);
  bool selective = false;
  RecordPlan plan;
  std::vector<volillum::PropagationTask> work, remaining;
  std::vector<std::vector<volillum::PropagationTask>> sweeps;
  if (bands.Me >= 0)
  {
    selective = this->PrepareUpdate(lights, bounds, points, mustRecompute, work, plan);
    sweeps = volillum::PlanSweeps(
      work, this->CoherentPropagation, this->MaximumPassesPerUpdate, remaining);
  }
  // A sweep's directional tasks run over bands of rows, each of its point or spot lights'
  // over wedges of its rays.
  std::vector<std::vector<volillum::PropagationTask>> bandSweeps, wedgeSweeps;
  for (const auto& sweep : sweeps)
  {
    std::vector<volillum::PropagationTask> directional;
    for (auto& light : volillum::TasksByLight(sweep, directional))
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
    mine[volillum::SweepRowAxis(sweep[0].Group)] = 1;
  }
  for (const auto& sweep : sweeps)
  {
    mine[3] = std::max<int>(mine[3],
      std::any_of(
        sweep.begin(), sweep.end(), [](const volillum::PropagationTask& t) { return t.Recorded; }));
    this->LastStatistics.Sweeps += 1;
    this->LastStatistics.LightSweeps += static_cast<long long>(sweep.size());
  }
  int agreed[5];
  controller->AllReduce(mine, agreed, 5, vtkCommunicator::MAX_OP);
  std::vector<int> groups(agreed[4], -1), wedgeGroups(agreed[4]);
  for (size_t i = 0; i < wedgeSweeps.size(); ++i)
  {
    groups[i] = wedgeSweeps[i][0].Group;
  }
  if (agreed[4] > 0)
  {
    controller->AllReduce(groups.data(), wedgeGroups.data(), agreed[4], vtkCommunicator::MAX_OP);
  }
  const size_t total = bandSweeps.size() + wedgeGroups.size();
  size_t swept = 0;
  for (const int rowAxis : { 2, 1 })
  {
    if (agreed[rowAxis])
    {
      this->SweepBands(
        bands, rowAxis, volume, piece, target, bandSweeps, agreed[3] != 0, own, swept, total);
    }
  }
  this->SweepWedges(
    bands, volume, piece, target, wedgeSweeps, wedgeGroups, agreed[3] != 0, own, swept, total);
  if (bands.Me >= 0)
  {
    this->CommitUpdate(selective, plan, remaining, lights, true, report);
    this->Illumination.ToFloat(rgb);
  }
  else
  {
    // Nothing applied here: the next update of this process recomputes every light, as the
    // others' do after a change of layout.
    this->Illumination = volillum::FixedPointIllumination();
    this->Applied.Reset();
    this->Pending.clear();
    this->Valid = false;
    this->DistributedLayout = true;
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::SweepBands(const Bands& bands, int rowAxis,
  const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
  const volillum::GridGeometry& target,
  const std::vector<std::vector<volillum::PropagationTask>>& sweeps, bool record, const int own[6],
  size_t& swept, size_t total)
{
  vtkMultiProcessController* controller = bands.Controller;
  // The sweeps with these rows, and the lattice rows a band reads beyond its own.
  std::vector<size_t> mine;
  int halo = 1;
  for (size_t i = 0; i < sweeps.size(); ++i)
  {
    if (volillum::SweepRowAxis(sweeps[i][0].Group) == rowAxis)
    {
      mine.push_back(i);
      halo = std::max(halo, volillum::LatticeHalo(target, sweeps[i]));
    }
  }
  // A band for each of the first processes with a piece, at least a row each; its own rows
  // (the last band's also the lattices' extra row n) and the lattice rows it reads (its
  // window: its own and `halo` either side).
  const int n = target.Dimensions[rowAxis];
  const int count = std::max(1, std::min(static_cast<int>(bands.Participants.size()), n));
  const int b = bands.Me < count ? bands.Me : -1;
  auto ownRows = [n, count](int m, int& first, int& last)
  {
    first = static_cast<int>(static_cast<long long>(n) * m / count);
    last = static_cast<int>(static_cast<long long>(n) * (m + 1) / count) - 1;
    last = last == n - 1 ? n : last;
  };
  auto windowRows = [&](int m, int& first, int& last)
  {
    ownRows(m, first, last);
    first = std::max(0, first - halo);
    last = std::min(n, last + halo);
  };
  volillum::SweepBand band;
  int rows[6] = { 0, -1, 0, -1, 0, -1 };   // the band's extent of the illumination grid
  int wanted[6] = { 0, -1, 0, -1, 0, -1 }; // the band of the data grid it reads
  if (b >= 0)
  {
    ownRows(b, band.First, band.Last);
    band.Last = std::min(band.Last, n - 1);
    band.Halo = halo;
    // The data all of its sweeps read.
    int low = piece.Whole.Dimensions[rowAxis], high = -1;
    for (const size_t i : mine)
    {
      int first, last;
      volillum::BandOfData(piece.Whole, target, sweeps[i], band, halo, first, last);
      low = std::min(low, first);
      high = std::max(high, last);
    }
    for (int a = 0; a < 3; ++a)
    {
      rows[2 * a + 1] = target.Dimensions[a] - 1;
      wanted[2 * a + 1] = piece.Whole.Dimensions[a] - 1;
    }
    rows[2 * rowAxis] = band.First;
    rows[2 * rowAxis + 1] = band.Last;
    wanted[2 * rowAxis] = low;
    wanted[2 * rowAxis + 1] = high;
  }
  volillum::ClassifiedVolume slab;
  this->SentBytes += GatherClassification(controller, volume, piece, wanted, slab);
  this->BandPoints = std::max(this->BandPoints, volillum::ExtentPoints(wanted));

  volillum::FixedPointIllumination units;
  units.Reset(volillum::ExtentPoints(rows), this->Illumination.Scale);
  if (record)
  {
    units.StartRecord();
  }
  if (b >= 0)
  {
    const volillum::EmptyBlocks empty(slab);
    // After every slice each band sends the bands whose windows meet its own rows those rows
    // and gets from the bands whose rows meet its window theirs: the bands up to `reach` away
    // either side (bands hold n / count rows or one more). Bands d apart meet in two steps:
    // first the pairs whose lower band lies in an even block of d bands, then the others, the
    // lower band of a pair sending first; every band is in one pair a step, so no blocking
    // send waits in a cycle, and the exchange takes 2 reach steps however many bands there
    // are (2 when bands hold at least `halo` rows).
    const int reach = (halo + n / count - 1) / (n / count);
    auto exchange = [&](const std::vector<float*>& lattices, size_t rowValues, int firstRow)
    {
      for (int d = 1; d <= reach; ++d)
      {
        for (const bool lowerFirst : { true, false })
        {
          const int m = ((b / d) % 2 == 0) == lowerFirst ? b + d : b - d;
          if (m < 0 || m >= count)
          {
            continue;
          }
          const int process = bands.Participants[m];
          for (const bool send : { m > b, m < b })
          {
            // Sent: this band's rows in m's window; received: m's rows in this band's.
            int first, last, windowFirst, windowLast;
            ownRows(send ? b : m, first, last);
            windowRows(send ? m : b, windowFirst, windowLast);
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
                controller->Send(at, size, process, tag);
                this->SentBytes += size * static_cast<long long>(sizeof(float));
              }
              else
              {
                controller->Receive(at, size, process, tag);
              }
            }
          }
        }
      }
    };
    for (const size_t i : mine)
    {
      volillum::PropagateSweepBand(slab, target, sweeps[i], band, units, exchange,
        this->LastStatistics, &empty, [&](double f) { this->ReportProgress((swept + f) / total); });
      ++swept;
    }
  }
  // Each band's units to the processes whose pieces hold its points (bands do not overlap).
  this->SentBytes += volillum::ExchangeExtents<std::uint32_t>(
    controller, rows, rows, units.Values.data(), own, this->Illumination.Values.data(), 3, true);
  if (record)
  {
    this->SentBytes += volillum::ExchangeExtents<std::uint32_t>(controller, rows, rows,
      units.Recorded.data(), own, this->Illumination.Recorded.data(), 3, true);
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::SweepWedges(const Bands& bands,
  const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
  const volillum::GridGeometry& target,
  const std::vector<std::vector<volillum::PropagationTask>>& sweeps, const std::vector<int>& groups,
  bool record, const int own[6], size_t& swept, size_t total)
{
  vtkMultiProcessController* controller = bands.Controller;
  const bool sweeping = bands.Me >= 0;
  const int count = static_cast<int>(bands.Participants.size());
  const volillum::GridGeometry& data = piece.Whole;
  if (groups.empty())
  {
    return;
  }
  // The whole grid's empty blocks: those every process's block finds empty.
  volillum::EmptyBlocks empty(data, volume, piece.Offset);
  std::vector<char> marks(empty.Marks().size());
  controller->AllReduce(empty.Marks().data(), marks.data(), static_cast<vtkIdType>(marks.size()),
    vtkCommunicator::MIN_OP);
  empty.Marks() = std::move(marks);
  empty.Update();
  for (size_t i = 0; i < groups.size(); ++i)
  {
    const int axis = groups[i] / 2, c = volillum::SweepRowAxis(groups[i]), b = 3 - axis - c;
    volillum::SweepWedge wedge;
    std::vector<int> dataFirst, dataLast, rowFirst, rowLast;
    if (sweeping)
    {
      wedge = volillum::SplitIntoWedges(target, sweeps[i], count)[bands.Me];
      volillum::WedgeOfData(data, target, sweeps[i], wedge, dataFirst, dataLast);
      volillum::WedgeRows(target, sweeps[i], wedge, rowFirst, rowLast);
    }
    // The slices travel in chunks of WedgeSlices (one collective exchange a chunk): the extent
    // of slices [k0, k1) of grid g with the rows [first[k], last[k]] of each (none for a
    // process that does not sweep), and the offset in a buffer over such an extent (x fastest)
    // of the first point of row r of slice k, with the offset between points along b.
    auto chunk = [&](const volillum::GridGeometry& g, const std::vector<int>& first,
                   const std::vector<int>& last, int k0, int k1, int extent[6])
    {
      for (int a = 0; a < 3; ++a)
      {
        extent[2 * a] = 0;
        extent[2 * a + 1] = g.Dimensions[a] - 1;
      }
      extent[2 * axis] = k0;
      extent[2 * axis + 1] = k1 - 1;
      extent[2 * c] = sweeping ? *std::min_element(&first[k0], &first[k0] + (k1 - k0)) : 0;
      extent[2 * c + 1] = sweeping ? *std::max_element(&last[k0], &last[k0] + (k1 - k0)) : -1;
    };
    auto offsetIn = [&](const int extent[6], int k, int r, long long& strideB)
    {
      const long long nx = extent[1] - extent[0] + 1, ny = extent[3] - extent[2] + 1;
      const long long stride[3] = { 1, nx, nx * ny };
      strideB = stride[b];
      return (k - extent[2 * axis]) * stride[axis] + (r - extent[2 * c]) * stride[c];
    };
    // The wedge's material, per slice its rows (every process takes part in each chunk's
    // exchange).
    volillum::WedgeVolume material;
    material.Volume.Geometry = data;
    material.Volume.Channels = volume.Channels;
    material.Volume.Scale = volume.Scale;
    long long held = 0;
    for (int a = 0; a < data.Dimensions[axis] && sweeping; ++a)
    {
      material.First.push_back(dataFirst[a]);
      material.Base.push_back(held);
      held += static_cast<long long>(data.Dimensions[b]) * (dataLast[a] - dataFirst[a] + 1);
    }
    material.Volume.Properties.resize(static_cast<size_t>(volume.Channels * held));
    const int channels = volume.Channels, nb = data.Dimensions[b];
    std::vector<volillum::PackedValue> gathered;
    for (int a0 = 0; a0 < data.Dimensions[axis]; a0 += WedgeSlices)
    {
      const int a1 = std::min(a0 + WedgeSlices, data.Dimensions[axis]);
      int wanted[6];
      chunk(data, dataFirst, dataLast, a0, a1, wanted);
      gathered.resize(static_cast<size_t>(channels * volillum::ExtentPoints(wanted)));
      this->SentBytes +=
        GatherClassificationValues(controller, volume, piece, wanted, gathered.data());
      for (int a = a0; a < a1 && sweeping; ++a)
      {
        for (int r = dataFirst[a]; r <= dataLast[a]; ++r)
        {
          long long strideB;
          const volillum::PackedValue* from =
            gathered.data() + channels * offsetIn(wanted, a, r, strideB);
          volillum::PackedValue* to = material.Volume.Properties.data() +
            channels * (material.Base[a] + static_cast<long long>(nb) * (r - dataFirst[a]));
          for (int i = 0; i < nb; ++i)
          {
            std::copy_n(from + channels * strideB * i, channels, to + channels * i);
          }
        }
      }
    }
    gathered = std::vector<volillum::PackedValue>();
    this->BandPoints = std::max(this->BandPoints, held);

    long long points = 0;
    for (size_t k = 0; k < rowFirst.size(); ++k)
    {
      points += static_cast<long long>(target.Dimensions[b]) * (rowLast[k] - rowFirst[k] + 1);
    }
    volillum::FixedPointIllumination units;
    units.Reset(points, this->Illumination.Scale);
    if (record)
    {
      units.StartRecord();
    }
    if (sweeping)
    {
      volillum::PropagateSweepWedge(material, target, sweeps[i], wedge, units, this->LastStatistics,
        &empty, [&](double f) { this->ReportProgress((swept + f) / total); });
    }
    material = volillum::WedgeVolume();
    // The wedge's units to the processes whose pieces hold its points, a chunk of slices at a
    // time: over the chunk's extent, zero beyond the wedge's rows (added to the pieces, the
    // zeros change nothing where the extents of the wedges' chunks overlap).
    const int nt = target.Dimensions[b];
    long long at = 0;
    std::vector<std::uint32_t> moved;
    for (int k0 = 0; k0 < target.Dimensions[axis]; k0 += WedgeSlices)
    {
      const int k1 = std::min(k0 + WedgeSlices, target.Dimensions[axis]);
      int rows[6];
      chunk(target, rowFirst, rowLast, k0, k1, rows);
      const long long start = at;
      for (const bool recorded : { false, true })
      {
        if (recorded && !record)
        {
          continue;
        }
        const auto& values = recorded ? units.Recorded : units.Values;
        moved.assign(static_cast<size_t>(3 * volillum::ExtentPoints(rows)), 0);
        at = start;
        for (int k = k0; k < k1 && sweeping; ++k)
        {
          for (int r = rowFirst[k]; r <= rowLast[k]; ++r, at += nt)
          {
            long long strideB;
            std::uint32_t* to = moved.data() + 3 * offsetIn(rows, k, r, strideB);
            for (int n = 0; n < nt; ++n)
            {
              std::copy_n(values.data() + 3 * (at + n), 3, to + 3 * strideB * n);
            }
          }
        }
        auto& into = recorded ? this->Illumination.Recorded : this->Illumination.Values;
        this->SentBytes += volillum::ExchangeExtents<std::uint32_t>(
          controller, rows, rows, moved.data(), own, into.data(), 3, true);
      }
    }
    ++swept;
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CostEstimate: " << this->CostEstimate << "\n";
  os << indent << "SelectiveUpdates: " << this->SelectiveUpdates << "\n";
  os << indent << "CoherentPropagation: " << this->CoherentPropagation << "\n";
  os << indent << "MaximumPassesPerUpdate: " << this->MaximumPassesPerUpdate << "\n";
  os << indent << "RecordEditedLight: " << this->RecordEditedLight << "\n";
  os << indent << "RecordedLight: " << this->RecordedLight << "\n";
  os << indent << "DistributedSweeps: " << this->DistributedSweeps << "\n";
}
