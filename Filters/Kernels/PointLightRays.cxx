#include "PropagationSweep.h"

#include "SliceInterpolation.h"

#include "vtkMath.h"

#include <algorithm>
#include <cmath>

namespace volillum
{
namespace propagation
{
namespace
{
// Whether coordinate x along axis a lies on one of the box's faces across a: within twice
// the tolerance ClipToBox gives points on a face, as it puts the ends it clips that far out
// (give or take their rounding).
inline bool OnFaceAcross(const double bounds[6], int a, double x)
{
  const double tolerance = 2.0 * FaceTolerance(bounds, a);
  return std::abs(x - bounds[2 * a]) <= tolerance || std::abs(x - bounds[2 * a + 1]) <= tolerance;
}

// Points whose rays entered the box across a side face fewer than this many slices before
// them integrate their paths inside the box themselves, as the points whose rays entered
// beyond the rays beside the box do (RaysBeside), instead of reading those rays. Measured on
// the fidelity scenes: the point light of the slab (its shadow's edge on a face) has a
// material RMS of 0.43 % reading the rays everywhere, 0.08 % with 12 slices (0.07 %
// integrating every such path); the cost of a point light (placed as volillum-benchmark's
// oblique lights, a synthetic 256^3 volume) does not change measurably from 0 to 12 slices.
constexpr double EntryReach = 12.0;

// How far back from a point at coordinate `atAxis` on the sweep axis, as a part of its way
// from the light, EnteredJustBefore looks for a side face its ray crossed: back to the
// anchor slice (its ray crosses it at the part `ratio` of that way from the light), at most
// EntryReach slices. The same for every point of a slice.
inline double EntryLimit(const SweepContext& s, const double light[3], double atAxis, double ratio)
{
  return std::min(1.0 - ratio, EntryReach * s.Spacing[s.Axis] / std::abs(atAxis - light[s.Axis]));
}

// Whether the ray to point p crosses a face across B or C on the light's side within the
// part `limit` (EntryLimit) of its way from p to the light.
inline bool EnteredWithin(
  const SweepContext& s, const double light[3], const double p[3], double limit)
{
  for (const int c : { s.B, s.C })
  {
    const double low = s.Bounds[2 * c], high = s.Bounds[2 * c + 1];
    if ((light[c] > high && high - p[c] < limit * (light[c] - p[c])) ||
      (light[c] < low && p[c] - low < limit * (p[c] - light[c])))
    {
      return true;
    }
  }
  return false;
}

// Whether point p (inside the box), whose ray crosses the anchor slice at the part `ratio`
// of its way from the light, entered the box across a side face after the anchor and fewer
// than EntryReach slices before p.
inline bool EnteredJustBefore(
  const SweepContext& s, const double light[3], const double p[3], double ratio)
{
  return EnteredWithin(s, light, p, EntryLimit(s, light, p[s.Axis], ratio));
}

// Transmittance of the ray from a point or spot source to point p (out), the unit direction
// the light travels there (d) and the factor an inside light's group gives the point; rays
// holds the light along the anchored rays at the previous slice. The light read from them
// still has to be attenuated over the point's last step, from the previous slice: that is
// left to the caller, the step's length stored in lastStep (0 when nothing is left). A ray
// that entered the box across a side face after the anchor slice, beyond the rays beside the
// box or just before p (EnteredJustBefore), is integrated from there; across C, by the
// caller: the length of its path inside the box is stored in entry (else 0).
void TransmittanceAtPoint(const SweepContext& s, const SweepSource& sweep, const float* rays,
  const double p[3], float* out, double d[3], double& groupFactor, double& lastStep, double& entry)
{
  const RaySource& source = sweep.Source;
  std::fill_n(out, s.Channels, 1.0f);
  groupFactor = 1.0;
  lastStep = 0.0;
  entry = 0.0;
  const int a = s.Axis;
  for (int i = 0; i < 3; ++i)
  {
    d[i] = p[i] - source.Position[i];
  }
  const double distance = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (distance < 1e-12)
  {
    // The point is the light: every group of an inside light shares it.
    d[0] = d[1] = 0.0;
    d[2] = 1.0;
    groupFactor = source.Inside ? 1.0 / NumberOfPropagationGroups : 1.0;
    return;
  }
  const double inverse = 1.0 / distance;
  d[0] *= inverse;
  d[1] *= inverse;
  d[2] *= inverse;
  const double along = s.Sign * d[a];
  if (source.Inside)
  {
    if (along <= 0.0)
    {
      groupFactor = 0.0;
      return;
    }
    groupFactor = d[a] * d[a];
  }
  if (along <= MinimumAlong)
  {
    // The light makes no progress along the axis: this group does not carry it.
    return;
  }
  if (sweep.Anchor < 0)
  {
    SegmentTransmittance(s, p, d, distance, out);
    return;
  }
  // Where the point's ray crosses the anchor slice, in its cells.
  const double ratio =
    (SliceCoordinate(s, sweep.Anchor) - source.Position[a]) / (p[a] - source.Position[a]);
  double crossing[3];
  for (int i = 0; i < 3; ++i)
  {
    crossing[i] = source.Position[i] + ratio * (p[i] - source.Position[i]);
  }
  SlicePoint at;
  if (!Locate(AnchorSpread * (crossing[s.B] - sweep.RayOriginB) / s.Spacing[s.B],
        AnchorSpread * (crossing[s.C] - sweep.RayOriginC) / s.Spacing[s.C], sweep.RaysB,
        sweep.RaysC, at) ||
    EnteredJustBefore(s, source.Position, p, ratio))
  {
    // The ray entered the box through a side face after the anchor slice.
    const double remaining = (1.0 - ratio) * distance;
    double from, to;
    // A point inside the box (from 0) whose path starts on a face across C. A path that
    // starts on a face across B as well (a corner, or a row in the plane of a face across
    // C) ends a tolerance outside the grid along B, which keeps it out of the row runs.
    if (ClipToBox(s.Bounds, p, d, remaining, from, to) && from == 0.0 &&
      OnFaceAcross(s.Bounds, s.C, p[s.C] - to * d[s.C]))
    {
      entry = to;
      return;
    }
    SegmentTransmittance(s, p, d, remaining, out);
    return;
  }
  MonotoneBicubic(
    rays, s.Channels, sweep.RaysB, sweep.RaysC, at, out, sweep.RayFirst, sweep.RayRows);
  lastStep = s.Spacing[a] / along;
}

// Most columns MonotoneBicubicAlongRow combines at once.
constexpr int MaximumColumns = 2 * MaximumDivergingRays + 4;

// MonotoneBicubic (one channel) of a slice buffer (nb x nc pixels; rows from firstRow on,
// `rows` of them) at `count` points of a row, point i at (u[i], v) in pixels, u increasing,
// all inside the slice. They share their weights along v, so the four rows the taps read
// are combined once per column and each point interpolates those columns along u, clamped
// to the range of its four surrounding pixels as MonotoneBicubic: the same values up to the
// order of the sums.
void MonotoneBicubicAlongRow(const float* base, int nb, int nc, int firstRow, int rows,
  const double* u, double v, int count, float* out)
{
  auto cell = [nb](double x) { return std::min(static_cast<int>(x), std::max(nb - 2, 0)); };
  const int from = std::max(cell(u[0]) - 1, 0);
  const int to = std::min(cell(u[count - 1]) + 2, nb - 1);
  SlicePoint at;
  if (nb < 4 || nc < 4 || to - from + 1 > MaximumColumns)
  {
    for (int i = 0; i < count; ++i)
    {
      Locate(u[i], v, nb, nc, at);
      MonotoneBicubic(base, 1, nb, nc, at, out + i, firstRow, rows);
    }
    return;
  }
  Locate(u[0], v, nb, nc, at);
  rows = rows > 0 ? rows : nc - firstRow;
  float wv[4];
  CubicWeights(at.FV, wv);
  const float* row[4];
  for (int m = 0; m < 4; ++m)
  {
    const int iv = std::min(std::max(at.V - 1 + m, 0), nc - 1) - firstRow;
    row[m] = base + static_cast<long long>(nb) * std::min(std::max(iv, 0), rows - 1);
  }
  float column[MaximumColumns], low[MaximumColumns], high[MaximumColumns];
  for (int x = from; x <= to; ++x)
  {
    column[x - from] =
      wv[0] * row[0][x] + wv[1] * row[1][x] + wv[2] * row[2][x] + wv[3] * row[3][x];
    low[x - from] = std::min(row[1][x], row[2][x]);
    high[x - from] = std::max(row[1][x], row[2][x]);
  }
  for (int i = 0; i < count; ++i)
  {
    const int iu = cell(u[i]);
    float wu[4];
    CubicWeights(static_cast<float>(u[i] - iu), wu);
    float sum = 0.0f;
    for (int m = 0; m < 4; ++m)
    {
      sum += wu[m] * column[std::min(std::max(iu - 1 + m, 0), nb - 1) - from];
    }
    const int c = iu - from;
    out[i] = std::min(std::max(sum, std::min(low[c], low[c + 1])), std::max(high[c], high[c + 1]));
  }
}

// Whether TransmittanceAlongRow reads a row's light from the rays a run of points at a time.
inline bool ReadsRaysAlongRow(const SweepContext& s, const SweepSource& sweep)
{
  return s.RowKernels && s.Channels == 1 && sweep.Anchor >= 0;
}

// TransmittanceAtPoint at the points first to first + count - 1 (at most
// MaximumDivergingRays) of a row of a slice (`row`: point i at its NearEnd(i)), their last
// steps integrated as a row (DivergingRowSegments), and so are the paths of the rays that
// entered the box across C: those of a row's points inside the box all enter the same face
// (the one between the row and the light along C) at the same fraction of their way from
// the light, the fraction that brings them to the face's coordinate along C, so their
// samples line up as their last steps' do. Without chromatic attenuation, where the rays
// are anchored, the points' rays cross the anchor slice at positions affine along the row:
// the points whose rays cross it among the anchored rays read them a run at a time
// (MonotoneBicubicAlongRow) and integrate their last steps as one (LightRowTransmittance).
void TransmittanceAlongRow(const SweepContext& s, const SweepSource& sweep, const float* rays,
  const LightRow& row, int first, int count, float* out, double* direction, double* groupFactor)
{
  const int a = s.Axis;
  const double* light = sweep.Source.Position;
  double p[3 * MaximumDivergingRays], distance[MaximumDivergingRays];
  double lastStep[MaximumDivergingRays], entry[MaximumDivergingRays];
  bool inRun[MaximumDivergingRays];
  // Where the points' rays cross the anchor slice, in rays: u[i] along B for point i, v
  // along C (computed as TransmittanceAtPoint does, which the points left out use).
  double u[MaximumDivergingRays], ratio = 0.0, v = -1.0;
  const bool runs = ReadsRaysAlongRow(s, sweep);
  if (runs)
  {
    ratio = (SliceCoordinate(s, sweep.Anchor) - light[a]) / (row.Near[a] - light[a]);
    v = AnchorSpread * (light[s.C] + ratio * (row.Near[s.C] - light[s.C]) - sweep.RayOriginC) /
      s.Spacing[s.C];
  }
  const bool crossesAnchor = runs && ratio > 0.0 && v >= 0.0 && v <= sweep.RaysC - 1;
  // Per point: its position, offset from the light (along the sweep axis and C, the row's),
  // distance from it, direction, group factor and crossing. The first loop, over contiguous
  // values only, is vectorised (square roots and divisions two or more at a time, with GCC and
  // Clang given -fno-math-errno); the
  // second spreads them over the points' coordinates (axes known only at run time).
  const double offsetA = row.Near[a] - light[a], offsetC = row.Near[s.C] - light[s.C];
  const double across = offsetA * offsetA + offsetC * offsetC;
  const bool inside = sweep.Source.Inside;
  double coordinateB[MaximumDivergingRays], offsetB[MaximumDivergingRays];
  double inverse[MaximumDivergingRays];
  for (int i = 0; i < count; ++i)
  {
    coordinateB[i] = row.Near[s.B] + (first + i) * row.StepB; // (NearEnd)
    offsetB[i] = coordinateB[i] - light[s.B];
    distance[i] = std::sqrt(offsetB[i] * offsetB[i] + across);
    u[i] = AnchorSpread * (light[s.B] + ratio * offsetB[i] - sweep.RayOriginB) / s.Spacing[s.B];
    inverse[i] = 1.0 / distance[i];
  }
  for (int i = 0; i < count; ++i)
  {
    double* q = p + 3 * i;
    double* d = direction + 3 * i;
    std::copy_n(row.Near, 3, q);
    q[s.B] = coordinateB[i];
    d[a] = offsetA * inverse[i];
    d[s.B] = offsetB[i] * inverse[i];
    d[s.C] = offsetC * inverse[i];
    groupFactor[i] = inside ? d[a] * d[a] : 1.0;
  }
  // The points whose rays cross the anchor slice among the rays, toward the sweep's
  // direction, read them a run at a time; the others one by one.
  const double along = s.Sign * offsetA;
  const double limit = crossesAnchor ? EntryLimit(s, light, row.Near[a], ratio) : 0.0;
  bool left = false, entries = false;
  for (int i = 0; i < count; ++i)
  {
    inRun[i] = crossesAnchor && u[i] >= 0.0 && u[i] <= sweep.RaysB - 1 && distance[i] >= 1e-12 &&
      along > MinimumAlong * distance[i] && !EnteredWithin(s, light, p + 3 * i, limit);
    if (inRun[i])
    {
      lastStep[i] = entry[i] = 0.0;
      continue;
    }
    TransmittanceAtPoint(s, sweep, rays, p + 3 * i, out + s.Channels * i, direction + 3 * i,
      groupFactor[i], lastStep[i], entry[i]);
    left = left || lastStep[i] > 0.0;
    entries = entries || entry[i] > 0.0;
  }
  if (left)
  {
    DivergingRowSegments(s, p, direction, lastStep, count, out);
  }
  if (entries)
  {
    DivergingRowSegments(s, p, direction, entry, count, out);
  }
  LightRow steps = row;
  steps.Fraction = s.Spacing[a] / (s.Sign * (row.Near[a] - light[a]));
  for (int r = 0; r < count;)
  {
    int end = r;
    while (end < count && inRun[end])
    {
      ++end;
    }
    if (end > r)
    {
      MonotoneBicubicAlongRow(
        rays, sweep.RaysB, sweep.RaysC, sweep.RayFirst, sweep.RayRows, u + r, v, end - r, out + r);
      LightRowTransmittance(s, steps, first + r, end - r, distance + r, out + r);
    }
    r = end + 1;
  }
}

// Position of ray (i, j) of a point or spot source where it leaves anchor slice k.
inline void AnchorPoint(
  const SweepContext& s, const SweepSource& sweep, int k, int i, int j, double p[3])
{
  p[s.Axis] = SliceCoordinate(s, k);
  p[s.B] = sweep.RayOriginB + i * (s.Spacing[s.B] / AnchorSpread);
  p[s.C] = sweep.RayOriginC + j * (s.Spacing[s.C] / AnchorSpread);
}
}

// The rows [first, last] of a point or spot source's rays from anchor slice k that a band
// computes (SweepSource::ConeLow and ConeHigh at k); all when the sweep is not in bands.
void ConeRows(const SweepContext& s, const SweepSource& sweep, int k, int& first, int& last)
{
  first = 0;
  last = sweep.RaysC - 1;
  if (!sweep.ConeLow.empty())
  {
    const double scale = AnchorSpread / s.Spacing[s.C];
    first = static_cast<int>(std::max(0.0,
      std::min<double>(sweep.RaysC, std::ceil((sweep.ConeLow[k] - sweep.RayOriginC) * scale))));
    last = static_cast<int>(std::min<double>(
      sweep.RaysC - 1, std::max(-1.0, std::floor((sweep.ConeHigh[k] - sweep.RayOriginC) * scale))));
  }
}

namespace
{
// The rays [first, last) of row j of a point or spot source's rays that may cross the box
// over a step from slice k - Sign to slice k (step.Anchor false): the others lie beyond one
// side of it at both ends of the step, by more than a margin far above the rounding of
// their positions (1000 face tolerances, 10^-6 of the box's extent: for lights within 10^9 extents
// of the box, as ClipToBox's tolerance assumes), so SegmentTransmittance would leave them
// unchanged. A ray's coordinate along B or C is the light's plus the anchor point's offset from it
// scaled by the slice's distance from the light, so it is affine in the ray's index along B and the
// same for the whole row along C.
void RaysCrossingBox(const SweepContext& s, const SweepSource& sweep, const AnchoredStep& step,
  int k, int j, int& first, int& last)
{
  first = 0;
  last = 0;
  const double* light = sweep.Source.Position;
  const double scales[2] = { step.Scale,
    (SliceCoordinate(s, k - s.Sign) - light[s.Axis]) /
      (SliceCoordinate(s, sweep.Anchor) - light[s.Axis]) };
  double anchor[3];
  AnchorPoint(s, sweep, sweep.Anchor, 0, j, anchor);
  double low[3], high[3];
  for (int a = 0; a < 3; ++a)
  {
    const double margin = 1000.0 * FaceTolerance(s.Bounds, a);
    low[a] = s.Bounds[2 * a] - margin;
    high[a] = s.Bounds[2 * a + 1] + margin;
  }
  const double c0 = light[s.C] + scales[0] * (anchor[s.C] - light[s.C]);
  const double c1 = light[s.C] + scales[1] * (anchor[s.C] - light[s.C]);
  if (std::max(c0, c1) < low[s.C] || std::min(c0, c1) > high[s.C])
  {
    return; // the whole row lies beyond one face across C
  }
  // Per scale, the (fractional) ray index at which the coordinate along B reaches x.
  auto index = [&](double scale, double x)
  {
    const double slope = scale * s.Spacing[s.B] / AnchorSpread;
    return (x - light[s.B] - scale * (anchor[s.B] - light[s.B])) / slope;
  };
  const double below = std::min(index(scales[0], low[s.B]), index(scales[1], low[s.B]));
  const double above = std::max(index(scales[0], high[s.B]), index(scales[1], high[s.B]));
  if (!std::isfinite(below) || !std::isfinite(above))
  {
    last = sweep.RaysB; // keep them all
    return;
  }
  first = static_cast<int>(std::min<double>(sweep.RaysB, std::max(0.0, std::floor(below) - 1)));
  last = static_cast<int>(std::min<double>(sweep.RaysB, std::max(0.0, std::ceil(above) + 2)));
  last = std::max(first, last);
}
}

// The rays [first, last) of row j of a point or spot source's rays leaving an anchor whose
// paths from the light may have met the box: the others leave it beside the box on the
// light's side (RaysBeside), beyond a face the light is beyond too, so their whole paths
// lie beyond it and they carry the light unattenuated.
void RaysMeetingBox(const SweepContext& s, const SweepSource& sweep, int j, int& first, int& last)
{
  first = 0;
  last = sweep.RaysB;
  const double* light = sweep.Source.Position;
  // Whether coordinate x along axis c and the light lie beyond the same face across c.
  auto beside = [&](int c, double x)
  {
    const double tolerance = FaceTolerance(s.Bounds, c);
    const double low = s.Bounds[2 * c] - tolerance, high = s.Bounds[2 * c + 1] + tolerance;
    return (x < low && light[c] < low) || (x > high && light[c] > high);
  };
  const double spacing = s.Spacing[s.B] / AnchorSpread;
  if (beside(s.C, sweep.RayOriginC + j * (s.Spacing[s.C] / AnchorSpread)))
  {
    last = 0;
    return;
  }
  while (first < last && beside(s.B, sweep.RayOriginB + first * spacing))
  {
    ++first;
  }
  while (last > first && beside(s.B, sweep.RayOriginB + (last - 1) * spacing))
  {
    --last;
  }
}

// Rows [begin, end) of a point or spot source's rays at slice k (see AnchoredStep): an
// anchor's rays get their light in `next` from the rays reaching the previous slice,
// `rays`; otherwise the rays in `rays` are attenuated over the step to slice k.
void AdvanceAnchoredRays(const SweepContext& s, SweepSource& sweep, const AnchoredStep& step, int k,
  int begin, int end, float* rays, float* next)
{
  if (!step.InFront)
  {
    return;
  }
  const double* light = sweep.Source.Position;
  double p[3 * MaximumDivergingRays], d[3 * MaximumDivergingRays], length[MaximumDivergingRays];
  const bool grey = s.RowKernels && s.Channels == 1;
  int first, last;
  ConeRows(s, sweep, step.Anchor ? k : sweep.Anchor, first, last);
  for (int j = std::max(begin, first); j < std::min(end, last + 1); ++j)
  {
    const long long row = static_cast<long long>(j - sweep.RayFirst) * sweep.RaysB;
    double* norms = sweep.Norms.data() + row;
    if (!step.Anchor && sweep.RowAnchor[j] != sweep.Anchor)
    {
      for (int i = 0; i < sweep.RaysB; ++i)
      {
        double offset[3];
        AnchorPoint(s, sweep, sweep.Anchor, i, j, offset);
        for (int c = 0; c < 3; ++c)
        {
          offset[c] -= light[c];
        }
        norms[i] = vtkMath::Norm(offset);
      }
      sweep.RowAnchor[j] = sweep.Anchor;
    }
    // The rays that stay beyond the box are left out; the others keep the runs they have
    // in the row's chunks of MaximumDivergingRays rays (the rays left out break runs).
    int crossing = 0, beyond = sweep.RaysB;
    // The row's rays: an anchor's points at slice k, or (without chromatic attenuation) the
    // rays' steps to slice k, each a row at once.
    LightRow rayRow;
    std::copy_n(light, 3, rayRow.Light);
    if (step.Anchor)
    {
      RaysMeetingBox(s, sweep, j, crossing, beyond);
      float* leaving = next + s.Channels * row;
      std::fill(leaving, leaving + s.Channels * crossing, 1.0f);
      std::fill(leaving + s.Channels * beyond, leaving + s.Channels * sweep.RaysB, 1.0f);
      AnchorPoint(s, sweep, k, 0, j, rayRow.Near);
      rayRow.StepB = s.Spacing[s.B] / AnchorSpread;
    }
    else
    {
      RaysCrossingBox(s, sweep, step, k, j, crossing, beyond);
      AnchorPoint(s, sweep, sweep.Anchor, 0, j, rayRow.Near);
      for (int c = 0; c < 3; ++c)
      {
        rayRow.Near[c] = light[c] + step.Scale * (rayRow.Near[c] - light[c]);
      }
      rayRow.StepB = step.Scale * s.Spacing[s.B] / AnchorSpread;
      rayRow.Fraction = s.Spacing[s.Axis] / (s.Sign * (SliceCoordinate(s, k) - light[s.Axis]));
    }
    for (int chunk = crossing - crossing % MaximumDivergingRays; chunk < beyond;
         chunk += MaximumDivergingRays)
    {
      const int i0 = std::max(chunk, crossing);
      const int size = std::min(chunk + MaximumDivergingRays, beyond) - i0;
      if (size <= 0)
      {
        continue;
      }
      const long long firstRay = row + i0;
      if (step.Anchor)
      {
        // The rays leave slice k: their light is read from the rays at slice k - 1.
        double factors[MaximumDivergingRays];
        TransmittanceAlongRow(
          s, sweep, rays, rayRow, i0, size, next + s.Channels * firstRay, d, factors);
        continue;
      }
      // The rays through the anchor's points, at slice k, over their step from slice k - 1.
      float* out = rays + s.Channels * firstRay;
      if (grey)
      {
        for (int i = 0; i < size; ++i)
        {
          length[i] = step.Scale * norms[i0 + i];
        }
        LightRowTransmittance(s, rayRow, i0, size, length, out);
        continue;
      }
      for (int i = 0; i < size; ++i)
      {
        double offset[3];
        AnchorPoint(s, sweep, sweep.Anchor, i0 + i, j, offset);
        for (int c = 0; c < 3; ++c)
        {
          offset[c] -= light[c];
          p[3 * i + c] = light[c] + step.Scale * offset[c];
          d[3 * i + c] = offset[c] / norms[i0 + i];
        }
        length[i] = s.Spacing[s.Axis] / (s.Sign * d[3 * i + s.Axis]);
      }
      DivergingRowSegments(s, p, d, length, size, out);
    }
  }
}

// Transmittance of a source that follows no ray lattice along row ic of slice k into out
// (3 floats a pixel), with the direction and group factor at each pixel of a point or spot
// source.
void RowTransmittance(const SweepContext& s, const SweepSource& sweep, const float* rays, int k,
  int ic, float* out, double* direction, double* groupFactor)
{
  const int nb = s.N[s.B];
  if (sweep.Source.Directional)
  {
    // A directional light that makes no progress along the axis enters at every point.
    std::fill(out, out + s.Channels * nb, 1.0f);
    return;
  }
  LightRow points;
  std::copy_n(sweep.Source.Position, 3, points.Light);
  points.Near[s.Axis] = SliceCoordinate(s, k);
  points.Near[s.B] = s.Origin[s.B];
  points.Near[s.C] = s.Origin[s.C] + ic * s.Spacing[s.C];
  points.StepB = s.Spacing[s.B];
  for (int first = 0; first < nb; first += MaximumDivergingRays)
  {
    const int size = std::min(MaximumDivergingRays, nb - first);
    TransmittanceAlongRow(s, sweep, rays, points, first, size, out + s.Channels * first,
      direction + 3 * first, groupFactor + first);
  }
}
}
}
