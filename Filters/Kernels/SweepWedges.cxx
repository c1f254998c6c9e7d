#include "PropagationSweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{
namespace propagation
{
namespace
{
// Margin of a wedge's cone of rays (ConeOfWedge), in spacings along C. Measured at an anchor
// slice, whose rays lie 1 / AnchorSpread spacings apart: a point reads the rays within two
// of where its own ray crosses the slice (4/3 spacings), and so does each ray of the next
// anchor, whose own crossing lies nearer the light's row than the ray by the ratio
// r <= 1 / AnchorSpread of the two anchors' distances from the light. So the rays a wedge
// needs at an anchor lie within u of it, u <= r u + 4/3, u <= 4 spacings. Followed to
// the next anchor they spread from the light by less than AnchorSpread (6 spacings), and
// the material along them is read there: 6 spacings, and one more for rounding.
constexpr double ConeMargin = 7.0;

// Distance along the sweep (axes) from the light to slice k of grid g: positive in front of
// it.
inline double FromLight(const GridGeometry& g, const SweepAxes& axes, const double light[3], int k)
{
  return axes.Sign * (g.Origin[axes.Axis] + k * g.Spacing[axes.Axis] - light[axes.Axis]);
}
}

// The rows first[k] to last[k] along C of slice k of grid g that a wedge of the rays of a
// light at `light` holds in a sweep (axes): in front of the light, the rows whose ratio
// (row - light) / (distance from the light) lies in [Low, High), so that wedges sharing a
// bound split the rows; elsewhere the Index-th of Count equal parts.
void WedgeRowsOf(const GridGeometry& g, const SweepAxes& axes, const double light[3],
  const SweepWedge& wedge, std::vector<int>& first, std::vector<int>& last)
{
  const int c = axes.C, n = g.Dimensions[c], na = g.Dimensions[axes.Axis];
  first.resize(na);
  last.resize(na);
  for (int k = 0; k < na; ++k)
  {
    const double from = FromLight(g, axes, light, k);
    if (!AnchoredStep::IsInFront(from, g.Spacing[axes.Axis]))
    {
      first[k] = static_cast<int>(static_cast<long long>(n) * wedge.Index / wedge.Count);
      last[k] = static_cast<int>(static_cast<long long>(n) * (wedge.Index + 1) / wedge.Count) - 1;
      continue;
    }
    // The first row whose ratio is at least u.
    auto row = [&](double u)
    {
      if (std::isinf(u))
      {
        return u < 0.0 ? 0 : n;
      }
      const double x = std::ceil((light[c] + u * from - g.Origin[c]) / g.Spacing[c]);
      return static_cast<int>(std::min<double>(n, std::max(0.0, x)));
    };
    first[k] = row(wedge.Low);
    last[k] = row(wedge.High) - 1;
  }
}

// The rays of a point or spot source at `light` that a wedge needs in a sweep (axes) of the
// grid g, as an interval [low[k], high[k]] along C per slice k (low > high where the slice is
// not in front of the light): the wedge there, widened by the margin. A ray keeps its ratio,
// so the wedge's points cross any earlier slice within the wedge there. The rays of an
// anchor are chosen at the anchor (ConeRows) and followed to the next.
void ConeOfWedge(const GridGeometry& g, const SweepAxes& axes, const double light[3],
  const SweepWedge& wedge, std::vector<double>& low, std::vector<double>& high)
{
  const int c = axes.C, n = g.Dimensions[axes.Axis];
  low.assign(n, 1.0);
  high.assign(n, 0.0);
  const double margin = ConeMargin * g.Spacing[c];
  for (int k = 0; k < n; ++k)
  {
    const double from = FromLight(g, axes, light, k);
    if (AnchoredStep::IsInFront(from, g.Spacing[axes.Axis]))
    {
      low[k] = light[c] + wedge.Low * from - margin;
      high[k] = light[c] + wedge.High * from + margin;
    }
  }
}
}

using namespace propagation;

std::vector<std::vector<PropagationTask>> TasksByLight(
  const std::vector<PropagationTask>& sweep, std::vector<PropagationTask>& directional)
{
  directional.clear();
  std::vector<std::vector<PropagationTask>> byLight;
  std::vector<RaySource> sources;
  for (const auto& task : sweep)
  {
    const RaySource source = SourceOf(task);
    if (source.Directional)
    {
      directional.push_back(task);
      continue;
    }
    const size_t at = std::find(sources.begin(), sources.end(), source) - sources.begin();
    if (at == sources.size())
    {
      sources.push_back(source);
      byLight.emplace_back();
    }
    byLight[at].push_back(task);
  }
  return byLight;
}

std::vector<SweepWedge> SplitIntoWedges(
  const GridGeometry& target, const std::vector<PropagationTask>& tasks, int count)
{
  std::vector<SweepWedge> wedges(std::max(1, count));
  for (size_t m = 0; m < wedges.size(); ++m)
  {
    wedges[m].Index = static_cast<int>(m);
    wedges[m].Count = static_cast<int>(wedges.size());
  }
  if (tasks.empty())
  {
    return wedges;
  }
  // The ratios of the points in front of the light, split into parts of as many points. (The
  // work a point costs varies: weighing it by an estimate of its samples, entries from a side
  // face included, balanced the work no better in a measured run and held more of the volume.)
  const SweepAxes axes(tasks[0].Group);
  const RaySource source = SourceOf(tasks[0]);
  const int c = axes.C;
  std::vector<double> ratios;
  for (int k = 0; k < target.Dimensions[axes.Axis]; ++k)
  {
    const double from = FromLight(target, axes, source.Position, k);
    if (AnchoredStep::IsInFront(from, target.Spacing[axes.Axis]))
    {
      for (int i = 0; i < target.Dimensions[c]; ++i)
      {
        ratios.push_back((target.Origin[c] + i * target.Spacing[c] - source.Position[c]) / from);
      }
    }
  }
  std::sort(ratios.begin(), ratios.end());
  for (size_t m = 1; m < wedges.size() && !ratios.empty(); ++m)
  {
    wedges[m - 1].High = wedges[m].Low = ratios[ratios.size() * m / wedges.size()];
  }
  return wedges;
}

void WedgeRows(const GridGeometry& target, const std::vector<PropagationTask>& tasks,
  const SweepWedge& wedge, std::vector<int>& first, std::vector<int>& last)
{
  first.clear();
  last.clear();
  if (!tasks.empty())
  {
    WedgeRowsOf(target, SweepAxes(tasks[0].Group), SourceOf(tasks[0]).Position, wedge, first, last);
  }
}

void WedgeOfData(const GridGeometry& data, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepWedge& wedge, std::vector<int>& first,
  std::vector<int>& last)
{
  first.clear();
  last.clear();
  if (tasks.empty())
  {
    return;
  }
  const SweepAxes axes(tasks[0].Group);
  const RaySource source = SourceOf(tasks[0]);
  const double* light = source.Position;
  const int a = axes.Axis, c = axes.C, na = data.Dimensions[a], n = data.Dimensions[c];
  first.resize(na);
  last.resize(na);
  // The rays followed lie within the cone margin of the wedge at their anchor (ConeRows) and
  // spread from the light by less than AnchorSpread until the next anchor; a sample between
  // two slices reads a cell's corners on both and a point beyond along C: the wedge at a
  // slice and at its neighbours (a ray's coordinate along C is linear between slices),
  // widened by the margin spread, a cell and one more point for rounding. At or behind the
  // light the wedge is the light's coordinate.
  // Beyond the margin, a path that ClipToBox keeps within a face's tolerance outside the box
  // (a light just before the first face) runs up to 1 / MinimumAlong times that across C.
  double bounds[6];
  target.GetBounds(bounds);
  const double margin = AnchorSpread * ConeMargin * target.Spacing[c] + data.Spacing[c] +
    FaceTolerance(bounds, a) / MinimumAlong;
  for (int k = 0; k < na; ++k)
  {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (int j = std::max(0, k - 1); j <= std::min(na - 1, k + 1); ++j)
    {
      const double from = std::max(0.0, FromLight(data, axes, light, j));
      low = std::min(low, from > 0.0 ? light[c] + wedge.Low * from : light[c]);
      high = std::max(high, from > 0.0 ? light[c] + wedge.High * from : light[c]);
    }
    const double lo = std::floor((low - margin - data.Origin[c]) / data.Spacing[c]) - 1.0;
    const double hi = std::ceil((high + margin - data.Origin[c]) / data.Spacing[c]) + 1.0;
    first[k] = static_cast<int>(std::min<double>(n - 1, std::max(0.0, lo)));
    last[k] = static_cast<int>(std::min<double>(n - 1, std::max(0.0, hi)));
  }
}

void PropagateSweepWedge(const WedgeVolume& volume, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepWedge& wedge, FixedPointIllumination& units,
  PropagationStatistics& statistics, const EmptyBlocks* empty,
  const std::function<void(double)>& progress)
{
  if (tasks.empty())
  {
    return;
  }
  SweepSpan span;
  span.Wedge = &wedge;
  span.WedgeMaterial = &volume;
  Sweep(
    volume.Volume, empty, true, target, tasks[0].Group, tasks, units, statistics,
    [&progress](double f)
    {
      if (progress)
      {
        progress(f);
      }
      return true; // the other wedges' processes wait on this one
    },
    span);
}
}
