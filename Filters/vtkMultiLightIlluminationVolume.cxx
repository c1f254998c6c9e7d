#include "vtkMultiLightIlluminationVolume.h"

#include "IlluminationParallel.h"
#include "RayMarchKernel.h"
#include "vtkCommunicator.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

#include <algorithm>
#include <map>
#include <memory>

vtkStandardNewMacro(vtkMultiLightIlluminationVolume);

namespace
{
constexpr int RaysTag = 8300; // and up: two messages per sweep

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
bool vtkMultiLightIlluminationVolume::LightsDistributedPieces() const
{
  const auto states = this->GetLightStates();
  return this->DistributedSweeps &&
    std::none_of(states.begin(), states.end(),
      [](const volillum::LightState& l)
      { return l.On && l.Kind != volillum::LightKind::Directional; });
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::AddOutputFieldData(vtkFieldData* fieldData)
{
  if (this->DistributedLayout)
  {
    vtkNew<vtkIdTypeArray> slab;
    slab->SetName("SlabPoints");
    slab->InsertNextValue(this->SlabPoints);
    fieldData->AddArray(slab);
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::ComputeDistributedIllumination(
  vtkMultiProcessController* controller, const volillum::ClassifiedVolume& volume,
  const volillum::VolumePiece& piece, const std::vector<volillum::LightState>& lights,
  const volillum::GridGeometry& target, const std::vector<int>& extents, bool inputModified,
  float* rgb, UpdateReport& report)
{
  // The processes with a piece (of the data and so of the illumination grid) sweep: the i-th
  // of them the i-th slab of slices along each axis. The others know no lights (they have
  // no frame for them) and only take part in the collective calls.
  this->SlabPoints = 0;
  this->LastStatistics = volillum::PropagationStatistics();
  SlabSweeps slabs;
  slabs.Controller = controller;
  const int local = controller->GetLocalProcessId();
  for (int p = 0; p < controller->GetNumberOfProcesses(); ++p)
  {
    if (volillum::ExtentPoints(&extents[6 * p]) > 0)
    {
      slabs.Me = p == local ? static_cast<int>(slabs.Participants.size()) : slabs.Me;
      slabs.Participants.push_back(p);
    }
  }
  const int* own = &extents[6 * local];
  const long long points = volillum::ExtentPoints(own);
  // Every process makes the same kind of update.
  const bool mustRecompute = !volillum::AllOk(
    controller, slabs.Me < 0 || !this->MustRecompute(lights, points, inputModified, true));
  double bounds[6];
  target.GetBounds(bounds);
  bool selective = false;
  RecordPlan plan;
  std::vector<volillum::PropagationTask> work, remaining;
  std::vector<std::vector<volillum::PropagationTask>> sweeps;
  if (slabs.Me >= 0)
  {
    selective = this->PrepareUpdate(lights, bounds, points, mustRecompute, work, plan);
    sweeps = volillum::PlanSweeps(
      work, this->CoherentPropagation, this->MaximumPassesPerUpdate, remaining);
  }
  // The axes swept and whether a task is recorded, agreed by all.
  int mine[4] = { 0, 0, 0, 0 };
  for (const auto& sweep : sweeps)
  {
    mine[sweep[0].Group / 2] = 1;
    mine[3] = std::max<int>(mine[3],
      std::any_of(
        sweep.begin(), sweep.end(), [](const volillum::PropagationTask& t) { return t.Recorded; }));
    this->LastStatistics.Sweeps += 1;
    this->LastStatistics.LightSweeps += static_cast<long long>(sweep.size());
  }
  int agreed[4];
  controller->AllReduce(mine, agreed, 4, vtkCommunicator::MAX_OP);
  const int axes = agreed[0] + agreed[1] + agreed[2];
  int done = 0;
  for (int axis = 0; axis < 3; ++axis)
  {
    if (agreed[axis])
    {
      this->SweepSlabs(slabs, axis, volume, piece, target, sweeps, agreed[3] != 0, own);
      this->ReportProgress(static_cast<double>(++done) / axes);
    }
  }
  if (slabs.Me >= 0)
  {
    this->CommitUpdate(selective, plan, remaining, lights, true, report);
    this->Illumination.ToFloat(rgb);
  }
}

//------------------------------------------------------------------------------
void vtkMultiLightIlluminationVolume::SweepSlabs(const SlabSweeps& slabs, int axis,
  const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
  const volillum::GridGeometry& target,
  const std::vector<std::vector<volillum::PropagationTask>>& sweeps, bool record, const int own[6])
{
  vtkMultiProcessController* controller = slabs.Controller;
  const int participants = static_cast<int>(slabs.Participants.size());
  const int n = target.Dimensions[axis];
  volillum::SweepPart part;
  int slices[6] = { 0, -1, 0, -1, 0, -1 }; // the part's extent of the illumination grid
  int wanted[6] = { 0, -1, 0, -1, 0, -1 }; // the slab of the data grid it reads
  volillum::ClassifiedVolume slab;
  slab.Geometry = piece.Whole;
  slab.Channels = volume.Channels;
  slab.Scale = volume.Scale;
  if (slabs.Me >= 0)
  {
    part.First = static_cast<int>(static_cast<long long>(n) * slabs.Me / participants);
    part.Last = static_cast<int>(static_cast<long long>(n) * (slabs.Me + 1) / participants) - 1;
  }
  if (part.First <= part.Last)
  {
    int low, high;
    volillum::SlabOfPart(piece.Whole, target, axis, part, low, high);
    for (int a = 0; a < 3; ++a)
    {
      slices[2 * a + 1] = target.Dimensions[a] - 1;
      wanted[2 * a + 1] = piece.Whole.Dimensions[a] - 1;
    }
    slices[2 * axis] = part.First;
    slices[2 * axis + 1] = part.Last;
    wanted[2 * axis] = low;
    wanted[2 * axis + 1] = high;
    slab.Geometry.Dimensions[axis] = high - low + 1;
    slab.Geometry.Origin[axis] += low * piece.Whole.Spacing[axis];
  }
  // This process's classification covers `held` (indices in the whole data grid); it sends the
  // points of its block, less the boundary planes it shares with the blocks before it.
  int held[6] = { 0, -1, 0, -1, 0, -1 }, owned[6] = { 0, -1, 0, -1, 0, -1 };
  if (volume.Geometry.NumberOfPoints() > 0)
  {
    for (int a = 0; a < 3; ++a)
    {
      held[2 * a] = piece.Offset[a];
      held[2 * a + 1] = piece.Offset[a] + volume.Geometry.Dimensions[a] - 1;
      owned[2 * a] = piece.FirstCell[a] + (piece.FirstCell[a] > 0 ? 1 : 0);
      owned[2 * a + 1] = piece.LastCell[a] + 1;
    }
  }
  slab.Properties.resize(slab.Channels * static_cast<size_t>(volillum::ExtentPoints(wanted)));
  volillum::ExchangeExtents<volillum::PackedValue>(controller, held, owned,
    volume.Properties.data(), wanted, slab.Properties.data(), volume.Channels, false);
  this->SlabPoints = std::max(this->SlabPoints, volillum::ExtentPoints(wanted));
  std::unique_ptr<volillum::EmptyBlocks> empty;
  if (part.First <= part.Last)
  {
    empty = std::make_unique<volillum::EmptyBlocks>(slab);
  }

  // The sweeps along the axis, each a pipeline of the parts in its direction, run in rounds:
  // a part runs in the round of its place in its sweep's pipeline plus the sweeps of the same
  // group before it (so sweeps in opposite directions, and the sweeps of a group one after
  // the other, overlap), and after each round neighbours exchange the rays the next parts
  // start from (in the global order of pairs: no blocking send waits in a cycle).
  volillum::FixedPointIllumination units;
  units.Reset(volillum::ExtentPoints(slices), this->Illumination.Scale);
  if (record)
  {
    units.StartRecord();
  }
  struct Item
  {
    int Sweep, Sign, Rank; // Rank: sweeps of the same group before it
  };
  std::vector<Item> items;
  int inGroup[volillum::NumberOfPropagationGroups] = {};
  int rounds = 0;
  for (size_t i = 0; i < sweeps.size() && slabs.Me >= 0; ++i)
  {
    const int group = sweeps[i][0].Group;
    if (group / 2 == axis)
    {
      items.push_back({ static_cast<int>(i), group % 2 == 0 ? 1 : -1, inGroup[group]++ });
      rounds = std::max(rounds, participants + items.back().Rank);
    }
  }
  auto round = [participants](const Item& item, int m)
  { return (item.Sign > 0 ? m : participants - 1 - m) + item.Rank; };
  std::vector<int> peers; // the neighbouring slabs' processes
  for (const int m : { slabs.Me - 1, slabs.Me + 1 })
  {
    if (slabs.Me >= 0 && m >= 0 && m < participants)
    {
      peers.push_back(slabs.Participants[m]);
    }
  }
  std::map<int, std::vector<float>> rays; // by sweep: where the part before left them
  for (int r = 0; r < rounds; ++r)
  {
    for (const Item& item : items)
    {
      if (round(item, slabs.Me) == r)
      {
        volillum::PropagateSweepPart(slab, target, sweeps[item.Sweep], part, units,
          rays[item.Sweep], this->LastStatistics, empty.get());
      }
    }
    volillum::WithEachPeer(controller->GetLocalProcessId(), peers,
      [&](size_t k, bool send)
      {
        const int neighbour =
          peers[k] < controller->GetLocalProcessId() ? slabs.Me - 1 : slabs.Me + 1;
        for (const Item& item : items)
        {
          // Rays to the neighbour downstream of this part, or from the one upstream.
          const int from = send ? slabs.Me : neighbour;
          const int to = send ? neighbour : slabs.Me;
          if (to - from != item.Sign || round(item, from) != r)
          {
            continue;
          }
          const int tag = RaysTag + 2 * item.Sweep;
          auto& light = rays[item.Sweep];
          vtkIdType size = static_cast<vtkIdType>(light.size());
          if (send)
          {
            controller->Send(&size, 1, peers[k], tag);
            controller->Send(light.data(), size, peers[k], tag + 1);
            rays.erase(item.Sweep);
            continue;
          }
          controller->Receive(&size, 1, peers[k], tag);
          light.resize(static_cast<size_t>(size));
          controller->Receive(light.data(), size, peers[k], tag + 1);
        }
      });
  }
  // Each part's units to the processes whose pieces hold its points (parts do not overlap).
  volillum::ExchangeExtents<std::uint32_t>(controller, slices, slices, units.Values.data(), own,
    this->Illumination.Values.data(), 3, true);
  if (record)
  {
    volillum::ExchangeExtents<std::uint32_t>(controller, slices, slices, units.Recorded.data(), own,
      this->Illumination.Recorded.data(), 3, true);
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
