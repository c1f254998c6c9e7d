#include "vtkMultiLightIlluminationVolume.h"

#include "DistributedPropagation.h"
#include "ImageExtents.h"
#include "ParallelCollectives.h"
#include "RayMarchKernel.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

#include <algorithm>
#include <iterator>

vtkStandardNewMacro(vtkMultiLightIlluminationVolume);

namespace
{
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
  const std::vector<volillum::PropagationTask>& selective, const RecordPlan& plan,
  const std::vector<volillum::PropagationTask>& full, size_t changed, size_t lights, bool dragged)
{
  if (this->CostEstimate == ChangedLightFraction)
  {
    return 2 * changed <= lights;
  }
  namespace cost = volillum::PropagationCost;
  double record = 0.0;
  if (plan.Subtracted >= 0)
  {
    record += cost::SubtractRecord;
  }
  if (plan.Record >= 0)
  {
    record += this->RecordedLight >= 0 ? cost::ReusedRecord : cost::NewRecord;
  }
  this->LastSelectiveCost =
    volillum::EstimatePropagationCost(selective, this->CoherentPropagation) + record;
  this->LastFullCost =
    volillum::EstimatePropagationCost(full, this->CoherentPropagation) + cost::Clear;
  if (dragged && plan.Record >= 0 && plan.Subtracted < 0)
  {
    // A light changed alone twice in a row is being dragged: a record started now makes each
    // of the drag's later updates subtract it and add the new state only.
    std::vector<volillum::PropagationTask> added;
    std::copy_if(selective.begin(), selective.end(), std::back_inserter(added),
      [](const volillum::PropagationTask& task) { return task.Recorded; });
    return volillum::EstimatePropagationCost(added, this->CoherentPropagation) +
      cost::SubtractRecord <=
      this->LastFullCost;
  }
  return this->LastSelectiveCost <= this->LastFullCost;
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
  this->LastSelectiveCost = this->LastFullCost = -1.0;
  const std::vector<int> changed = this->Applied.ChangedLights(lights);
  const int alone = changed.size() == 1 ? changed[0] : -1;
  const bool dragged = alone >= 0 && alone == this->LoneLight;
  this->LoneLight = alone;
  if (!mustRecompute)
  {
    // Remove the applied states of the changed lights and add their new states, after the
    // work an earlier update left pending (see RecordPlan for the recorded light).
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
    selective = this->ChooseSelective(
      work, plan, full, changed.size(), std::max(lights.size(), applied.size()), dragged);
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
  this->LastStatistics = volillum::PropagationStatistics();
  // The processes with a piece (of the data and so of the illumination grid) sweep. The
  // others know no lights (they have no frame for them) and only take part in the
  // collective calls.
  volillum::DistributedPropagation distribution(controller, extents);
  const int* own = &extents[6 * controller->GetLocalProcessId()];
  const long long points = volillum::ExtentPoints(own);
  // Every process makes the same kind of update.
  const bool mustRecompute = !volillum::AllOk(controller,
    !distribution.Sweeps() || !this->MustRecompute(lights, points, inputModified, true));
  double bounds[6];
  target.GetBounds(bounds);
  bool selective = false;
  RecordPlan plan;
  std::vector<volillum::PropagationTask> work, remaining;
  std::vector<std::vector<volillum::PropagationTask>> sweeps;
  if (distribution.Sweeps())
  {
    selective = this->PrepareUpdate(lights, bounds, points, mustRecompute, work, plan);
    sweeps = volillum::PlanSweeps(
      work, this->CoherentPropagation, this->MaximumPassesPerUpdate, remaining);
  }
  distribution.Propagate(volume, piece, target, sweeps, own, this->Illumination,
    this->LastStatistics, [this](double f) { this->ReportProgress(f); });
  this->BandPoints = distribution.GetBandPoints();
  this->SentBytes = distribution.GetSentBytes();
  if (distribution.Sweeps())
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
