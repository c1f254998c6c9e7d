#include "FilteredShadowsKernel.h"

#include "vtkMath.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

namespace
{
// Store a point's transmittance in a per-light array, when there is one.
void Record(float* out, long long id, const double* transmittance, int channels)
{
  if (out)
  {
    for (int c = 0; c < channels; ++c)
    {
      out[channels * id + c] = static_cast<float>(transmittance[c]);
    }
  }
}

// Shadow rays are integrated through the full-resolution data over their first
// NearSegmentCells table cells toward the light and read from the table beyond: the optical
// depth next to a sample changes fastest across rays (a sample inside a thin structure or at
// its edge), and a table cell is one to four data cells wide. Measured (material RMS at
// FilterWidth 0, engine, directional light, default tables, patch one cell wide): 16.6 %
// without, 9.9 % with 1 cell, 7.6 % with 2, 5.9 % with 4, 4.9 % with 8; with the patch one
// data spacing wide, chest CT: 10.77 % with 4 cells, 10.11 % with 6, 9.19 % with 8 (the
// whole update 0-25 % slower than with 4).
constexpr double NearSegmentCells = 8.0;
}

void GroupShadowLights(const std::vector<LightState>& lights, std::vector<SatFrame>& frames,
  std::vector<ShadowLookup>& lookups, std::vector<SphericalLookup>& sphericalLookups)
{
  for (size_t index = 0; index < lights.size(); ++index)
  {
    const auto& light = lights[index];
    if (!light.On)
    {
      continue;
    }
    if (light.Kind != LightKind::Directional)
    {
      sphericalLookups.push_back({ index, sphericalLookups.size(), light });
      continue;
    }
    // The table is read toward the light, against the direction light travels.
    const auto travel = light.Direction();
    const double toward[3] = { -travel[0], -travel[1], -travel[2] };
    ShadowLookup lookup{ index, frames.size(), -1, 0, light.Radiance(),
      { toward[0], toward[1], toward[2] }, DirectionalConeSpread(light.Radius) };
    for (size_t f = 0; f < frames.size() && lookup.Axis < 0; ++f)
    {
      lookup.Axis = AxisOfDirection(frames[f], toward, lookup.Sign);
      lookup.Table = f;
    }
    if (lookup.Axis < 0)
    {
      frames.push_back(FrameForDirection(toward));
      lookup.Table = frames.size() - 1;
      lookup.Axis = AxisOfDirection(frames.back(), toward, lookup.Sign);
    }
    lookups.push_back(lookup);
  }
}

double NearSegmentLength(double cell, double patch)
{
  return NearSegmentCells * cell * std::min(std::max(2.0 - 2.0 * patch / cell, 0.0), 1.0);
}

namespace
{
// One row of points along the target's x axis and its working memory, reused row to row.
// Sum, Near, Far and FullDepth hold 3 values a point; Table holds one channel after another
// (as FilteredOpticalDepths writes them).
struct ShadingRow
{
  explicit ShadingRow(int count)
    : X(count)
    , Sum(3 * static_cast<size_t>(count))
    , Near(3 * static_cast<size_t>(count))
    , Length(count)
    , Far(3 * static_cast<size_t>(count))
    , Table(3 * static_cast<size_t>(count))
    , FullX(count)
    , FullDepth(3 * static_cast<size_t>(count))
    , Full(count)
  {
  }

  long long First = 0; // id of the row's first point
  double Y = 0.0, Z = 0.0;
  std::vector<double> X, Sum, Near, Length, Far, Table, FullX, FullDepth;
  std::vector<double> Line; // the table collapsed onto the row (CartesianSAT)
  std::vector<int> Full;
};

// The optical depths (Near) and lengths (Length) of the near segments of a row's shadow rays
// toward a directional light: rays whose near segment has its full length share their
// samples' cells along y and z (RowSegmentOpticalDepths); rays cut short by the box are
// integrated alone.
void DirectionalNearSegments(const PointShading& shading, const ShadowLookup& l, ShadingRow& row)
{
  const int count = static_cast<int>(row.X.size());
  const double* toward = l.Toward.data();
  int full = 0;
  for (int i = 0; i < count; ++i)
  {
    const double p[3] = { row.X[i], row.Y, row.Z };
    row.Length[i] = std::min(shading.NearLength, DistanceToBoxExit(p, toward, shading.Bounds));
    if (row.Length[i] == shading.NearLength)
    {
      row.FullX[full] = row.X[i];
      row.Full[full++] = i;
      continue;
    }
    SegmentOpticalDepth(
      shading.Volume, p, toward, row.Length[i], shading.Channels, &row.Near[3 * i], shading.Empty);
  }
  RowSegmentOpticalDepths(shading.Volume, row.FullX.data(), full, row.Y, row.Z, toward,
    shading.NearLength, shading.Channels, row.FullDepth.data(), shading.Empty);
  for (int f = 0; f < full; ++f)
  {
    std::copy_n(&row.FullDepth[3 * f], 3, &row.Near[3 * row.Full[f]]);
  }
}

// Add a directional light's share to the row's sums.
void ShadeDirectional(const PointShading& shading, const ShadowLookup& l, ShadingRow& row)
{
  const int count = static_cast<int>(row.X.size());
  const int channels = shading.Channels;
  const auto& table = shading.Tables[l.Table];
  const bool near = shading.Empty && shading.NearLength > 0.0;
  if (near)
  {
    DirectionalNearSegments(shading, l, row);
  }
  // The table takes over where the near segment ends.
  for (int i = 0; i < count; ++i)
  {
    const double reach = near ? std::max(row.Length[i], 0.0) : 0.0;
    row.Far[3 * i] = row.X[i] + reach * l.Toward[0];
    row.Far[3 * i + 1] = row.Y + reach * l.Toward[1];
    row.Far[3 * i + 2] = row.Z + reach * l.Toward[2];
  }
  for (int c = 0; c < channels; ++c)
  {
    double* tau = &row.Table[static_cast<size_t>(c) * count];
    if (l.Spread > 0.0)
    {
      // A light of finite size: a cone from each point (the box kernel's).
      for (int i = 0; i < count; ++i)
      {
        const double start = near ? std::max(row.Length[i], 0.0) : 0.0;
        tau[i] = table.ConeFilteredOpticalDepth(
          c, &row.Far[3 * i], l.Axis, l.Sign, shading.HalfWidth, start, l.Spread);
      }
      continue;
    }
    if (shading.Gaussian.empty())
    {
      table.FilteredOpticalDepths(
        c, row.Far.data(), count, l.Axis, l.Sign, shading.HalfWidth, tau, row.Line);
      continue;
    }
    for (int i = 0; i < count; ++i)
    {
      tau[i] = table.KernelFilteredOpticalDepth(
        c, &row.Far[3 * i], l.Axis, l.Sign, shading.HalfWidth, shading.Gaussian);
    }
  }
  for (int i = 0; i < count; ++i)
  {
    double transmittance[3] = { 1.0, 1.0, 1.0 };
    for (int c = 0; c < channels; ++c)
    {
      const double tau = (near ? row.Near[3 * i + c] : 0.0) + row.Table[c * count + i];
      transmittance[c] = std::exp(-std::max(tau, 0.0));
    }
    for (int c = 0; c < 3; ++c)
    {
      row.Sum[3 * i + c] += l.Radiance[c] * transmittance[channels == 3 ? c : 0];
    }
    Record(shading.Transmittances[l.Index], row.First + i, transmittance, channels);
  }
}

// The near part of the shadow ray from p toward the light (unit direction toward, clipped
// to the box and to `reach`): its optical depth per channel, integrated through the data, and
// in far the point where the table takes over. Without empty blocks (soft shadows: no near
// segment) the table gives the whole ray from p.
void NearSegment(const PointShading& shading, const double p[3], const double toward[3],
  double reach, double depth[3], double far[3])
{
  depth[0] = depth[1] = depth[2] = 0.0;
  std::copy_n(p, 3, far);
  if (!shading.Empty)
  {
    return;
  }
  const double length = std::min(reach, DistanceToBoxExit(p, toward, shading.Bounds));
  SegmentOpticalDepth(shading.Volume, p, toward, length, shading.Channels, depth, shading.Empty);
  for (int a = 0; a < 3; ++a)
  {
    far[a] = p[a] + std::max(length, 0.0) * toward[a];
  }
}

// Add a point or spot light's share at point id (at p) to sum.
void ShadeSpherical(const PointShading& shading, const SphericalLookup& l, long long id,
  const double p[3], double* sum)
{
  const auto incidence = ComputeIncidence(l.Light, p);
  const double cone = incidence.ConeFactor;
  if (cone == 0.0 && !shading.Transmittances[l.Index])
  {
    return;
  }
  const int channels = shading.Channels;
  const auto& table = shading.SphericalTables[l.Table];
  const auto radiance = l.Light.Radiance();
  double near[3], far[3];
  NearSegment(shading, p, incidence.ToLight.data(),
    std::min(shading.SphericalNear[l.Table], incidence.Distance), near, far);
  // A light of finite size: a cone from p toward its disc (DiscSquareRatio), starting where
  // the near segment ends.
  const double spread = DiscSquareRatio * l.Light.Radius / std::max(incidence.Distance, 1e-12);
  const double start = spread > 0.0 ? std::sqrt(vtkMath::Distance2BetweenPoints(p, far)) : 0.0;
  double transmittance[3] = { 1.0, 1.0, 1.0 };
  for (int c = 0; c < channels; ++c)
  {
    const double tau = spread > 0.0
      ? table.ConeFilteredOpticalDepth(c, far, shading.Patch, start, spread)
      : table.FilteredOpticalDepth(c, far, shading.Patch);
    transmittance[c] = std::exp(-std::max(near[c] + tau, 0.0));
  }
  for (int c = 0; c < 3; ++c)
  {
    sum[c] += cone * radiance[c] * transmittance[channels == 3 ? c : 0];
  }
  Record(shading.Transmittances[l.Index], id, transmittance, channels);
}

// Light reaching the points of row (j, k) of the target from every light that is on.
void ShadeRow(const PointShading& shading, const GridGeometry& target, long long j, long long k,
  ShadingRow& row, float* rgb)
{
  const int count = static_cast<int>(row.X.size());
  row.First = count * (j + target.Dimensions[1] * k);
  double p[3];
  target.PointPosition(0, j, k, p);
  row.Y = p[1];
  row.Z = p[2];
  for (int i = 0; i < count; ++i)
  {
    row.X[i] = target.Origin[0] + i * target.Spacing[0]; // PointPosition's x
  }
  std::fill(row.Sum.begin(), row.Sum.end(), 0.0);
  for (const auto& l : shading.Lookups)
  {
    ShadeDirectional(shading, l, row);
  }
  for (int i = 0; i < count && !shading.SphericalLookups.empty(); ++i)
  {
    const double q[3] = { row.X[i], row.Y, row.Z };
    for (const auto& l : shading.SphericalLookups)
    {
      ShadeSpherical(shading, l, row.First + i, q, &row.Sum[3 * i]);
    }
  }
  float* out = rgb + 3 * row.First;
  for (size_t v = 0; v < row.Sum.size(); ++v)
  {
    out[v] = static_cast<float>(row.Sum[v]);
  }
}
}

bool ShadePoints(const PointShading& shading, const GridGeometry& target, float* rgb,
  const ProgressCallback& progress)
{
  const int nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  const long long rows = ny * target.Dimensions[2];
  const long long chunk = std::max(1LL, rows / 20);
  for (long long first = 0; first < rows; first += chunk)
  {
    const long long last = std::min(rows, first + chunk);
    vtkSMPTools::For(first, last,
      [&](long long begin, long long end)
      {
        ShadingRow row(nx);
        for (long long r = begin; r < end; ++r)
        {
          ShadeRow(shading, target, r % ny, r / ny, row, rgb);
        }
      });
    if (progress && !progress(static_cast<double>(last) / rows))
    {
      return false;
    }
  }
  return true;
}

}
