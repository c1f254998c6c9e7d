#include "PropagationSweep.h"

#include "vtkMath.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace volillum
{

using namespace propagation;

namespace
{
// The group that sweeps along axis toward the sign of component.
int GroupOf(int axis, double component)
{
  return 2 * axis + (component >= 0.0 ? 0 : 1);
}
}

std::vector<GroupWeight> AssignPropagationGroups(const LightState& light, const double bounds[6])
{
  std::vector<GroupWeight> groups;
  if (IsLightInside(light, bounds))
  {
    for (int g = 0; g < NumberOfPropagationGroups; ++g)
    {
      groups.push_back({ g, 1.0 });
    }
    return groups;
  }
  std::array<double, 3> t;
  if (light.Kind == LightKind::Directional)
  {
    t = light.Direction();
  }
  else
  {
    for (int a = 0; a < 3; ++a)
    {
      t[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]) - light.Position[a];
    }
    vtkMath::Normalize(t.data());
  }
  std::array<int, 3> order{ { 0, 1, 2 } };
  std::sort(
    order.begin(), order.end(), [&](int i, int j) { return std::abs(t[i]) > std::abs(t[j]); });
  const double t1 = std::abs(t[order[0]]);
  const double t2 = std::abs(t[order[1]]);
  const double t3 = std::abs(t[order[2]]);
  double beta = (t1 - t3 > 0.0) ? std::atan2(t2 - t3, t1 - t3) : vtkMath::Pi() / 4.0;
  // A group toward the box along an axis the light lies beyond carries every point (all of
  // a directional light's groups do).
  const auto carriesAll = [&](int a)
  {
    return light.Kind == LightKind::Directional || light.Position[a] < bounds[2 * a] ||
      light.Position[a] > bounds[2 * a + 1];
  };
  int secondAxis = order[1];
  if (!carriesAll(order[0]) && !carriesAll(order[1]))
  {
    // The light lies beyond the box along the third axis only (just outside a face of a flat
    // box, near its edge): the first two groups would leave the points against both unlit.
    // The third axis's group is the second, weighted by t's angle from the first axis in
    // their plane.
    secondAxis = order[2];
    beta = std::atan2(t3, t1);
  }
  double second = 2.0 * beta / vtkMath::Pi();
  // A light nearly along the first axis: the first group takes it whole where it carries
  // every point.
  if (second < MinimumSecondWeight && carriesAll(order[0]))
  {
    second = 0.0;
  }
  groups.push_back({ GroupOf(order[0], t[order[0]]), 1.0 - second });
  if (second > 0.0)
  {
    groups.push_back({ GroupOf(secondAxis, t[secondAxis]), second });
  }
  return groups;
}

std::vector<PropagationTask> TasksForLight(
  const LightState& light, int sign, const double bounds[6])
{
  std::vector<PropagationTask> tasks;
  const auto r = light.Radiance();
  if (!light.On || (r[0] == 0.0 && r[1] == 0.0 && r[2] == 0.0))
  {
    return tasks;
  }
  const bool inside = IsLightInside(light, bounds);
  const auto groups = AssignPropagationGroups(light, bounds);
  const bool pair = !inside && light.Kind != LightKind::Directional && groups.size() == 2;
  for (size_t g = 0; g < groups.size(); ++g)
  {
    PropagationTask task;
    task.Light = light;
    task.Group = groups[g].Group;
    task.Weight = groups[g].Weight;
    task.Sign = sign;
    task.Inside = inside;
    if (pair)
    {
      task.OtherGroup = groups[1 - g].Group;
      task.OtherWeight = groups[1 - g].Weight;
    }
    tasks.push_back(task);
  }
  return tasks;
}

int CountSweeps(const std::vector<PropagationTask>& tasks, bool coherent)
{
  if (!coherent)
  {
    return static_cast<int>(tasks.size());
  }
  std::set<int> groups;
  for (const auto& t : tasks)
  {
    groups.insert(t.Group);
  }
  return static_cast<int>(groups.size());
}

double EstimatePropagationCost(const std::vector<PropagationTask>& tasks, bool coherent)
{
  std::vector<PropagationTask> remaining;
  double cost = 0.0;
  for (const auto& sweep : PlanSweeps(tasks, coherent, 0, remaining))
  {
    cost += PropagationCost::Sweep;
    std::vector<RaySource> sources;
    for (const auto& task : sweep)
    {
      const RaySource source = SourceOf(task);
      if (std::find(sources.begin(), sources.end(), source) == sources.end())
      {
        sources.push_back(source);
        cost += source.Directional ? PropagationCost::DirectionalRays : PropagationCost::PointRays;
      }
      cost += PropagationCost::Deposit + (task.Recorded ? PropagationCost::RecordedDeposit : 0.0);
    }
  }
  return cost;
}

std::vector<std::vector<PropagationTask>> PlanSweeps(const std::vector<PropagationTask>& tasks,
  bool coherent, int maxSweeps, std::vector<PropagationTask>& remaining)
{
  remaining.clear();
  // Sweeps in group order, so the two directions of an axis run one after the other.
  std::vector<std::vector<PropagationTask>> sweeps;
  for (int g = 0; g < NumberOfPropagationGroups; ++g)
  {
    std::vector<PropagationTask> inGroup;
    for (const auto& t : tasks)
    {
      if (t.Group == g)
      {
        inGroup.push_back(t);
      }
    }
    if (inGroup.empty())
    {
      continue;
    }
    if (coherent)
    {
      sweeps.push_back(inGroup);
    }
    else
    {
      for (const auto& t : inGroup)
      {
        sweeps.push_back({ t });
      }
    }
  }
  const int planned = maxSweeps > 0 ? std::min<int>(maxSweeps, static_cast<int>(sweeps.size()))
                                    : static_cast<int>(sweeps.size());
  for (size_t i = planned; i < sweeps.size(); ++i)
  {
    remaining.insert(remaining.end(), sweeps[i].begin(), sweeps[i].end());
  }
  sweeps.resize(planned);
  return sweeps;
}

bool PropagateTasks(const ClassifiedVolume& volume, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, bool coherent, int maxSweeps,
  FixedPointIllumination& illumination, std::vector<PropagationTask>& remaining,
  PropagationStatistics& statistics, const ProgressCallback& progress, const EmptyBlocks* empty,
  bool rowKernels, const SweepShare& share)
{
  const auto sweeps = PlanSweeps(tasks, coherent, maxSweeps, remaining);
  const std::vector<int> process = AssignSweeps(sweeps, share.Processes);
  std::vector<size_t> mine;
  for (size_t i = 0; i < sweeps.size(); ++i)
  {
    statistics.Sweeps += 1;
    statistics.LightSweeps += static_cast<long long>(sweeps[i].size());
    if (process[i] == share.Process)
    {
      mine.push_back(i);
    }
  }
  for (size_t m = 0; m < mine.size(); ++m)
  {
    const auto& sweep = sweeps[mine[m]];
    auto sweepProgress = [&](double f)
    { return !progress || progress((m + f) / static_cast<double>(mine.size())); };
    if (!Sweep(volume, empty, rowKernels, target, sweep[0].Group, sweep, illumination, statistics,
          sweepProgress))
    {
      return false;
    }
  }
  return true;
}

std::vector<int> AssignSweeps(
  const std::vector<std::vector<PropagationTask>>& sweeps, int processes)
{
  std::vector<double> cost(sweeps.size(), SweepShare::SweepCost);
  for (size_t i = 0; i < sweeps.size(); ++i)
  {
    for (const auto& task : sweeps[i])
    {
      cost[i] += task.Light.Kind == LightKind::Directional ? 1.0 : SweepShare::PointTaskCost;
    }
  }
  std::vector<size_t> order(sweeps.size());
  for (size_t i = 0; i < order.size(); ++i)
  {
    order[i] = i;
  }
  std::stable_sort(
    order.begin(), order.end(), [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  std::vector<double> load(std::max(processes, 1), 0.0);
  std::vector<int> process(sweeps.size(), 0);
  for (size_t i : order)
  {
    const auto least = std::min_element(load.begin(), load.end());
    process[i] = static_cast<int>(least - load.begin());
    *least += cost[i];
  }
  return process;
}
}
