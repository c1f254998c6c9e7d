#include "PropagationSweep.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

using namespace propagation;

int SweepRowAxis(int group)
{
  return SweepAxes(group).C;
}

int LatticeHalo(const GridGeometry& target, const std::vector<PropagationTask>& tasks)
{
  double offset = 0.0;
  for (const auto& task : tasks)
  {
    const SweepAxes a(task.Group);
    const SweepSource sweep(SourceOf(task), a.Axis, a.Sign, a.B, a.C, target.Spacing.data());
    if (sweep.FollowsRays())
    {
      offset = std::max(offset, std::abs(sweep.OffsetV));
    }
  }
  // The lattice rows a point's bicubic read takes (two either side of its ray's crossing)
  // and those a lattice row's predecessor lies away, with one for rounding.
  return static_cast<int>(std::ceil(offset)) + 3;
}

void BandOfData(const GridGeometry& data, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepBand& band, int halo, int& first, int& last)
{
  if (tasks.empty())
  {
    first = 0;
    last = -1;
    return;
  }
  const SweepAxes axes(tasks[0].Group);
  const int c = axes.C;
  // The lattice rows a band computes lie up to a row before its first point; their segments
  // and its points' move fewer rows across than the halo less its three rows for the reads.
  const int reach = halo - 1;
  double low = target.Origin[c] + (band.First - reach) * target.Spacing[c];
  double high = target.Origin[c] + (band.Last + reach) * target.Spacing[c];
  // One point more either side for rounding.
  const int n = data.Dimensions[c];
  first = static_cast<int>(std::max(0.0, std::floor((low - data.Origin[c]) / data.Spacing[c]) - 1));
  last =
    static_cast<int>(std::min(n - 1.0, std::ceil((high - data.Origin[c]) / data.Spacing[c]) + 1));
}

void PropagateSweepBand(const ClassifiedVolume& volume, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepBand& band, FixedPointIllumination& units,
  const LatticeExchange& exchange, PropagationStatistics& statistics, const EmptyBlocks* empty,
  const std::function<void(double)>& progress)
{
  if (tasks.empty())
  {
    return;
  }
  SweepSpan span;
  span.Banded = true;
  span.Band = band;
  span.Exchange = exchange;
  Sweep(
    volume, empty, true, target, tasks[0].Group, tasks, units, statistics,
    [&progress](double f)
    {
      if (progress)
      {
        progress(f);
      }
      return true; // the other bands wait on this one
    },
    span);
}
}
