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

// Transmittance of the ray from a point or spot source to point p (out), the unit direction
// the light travels there (d) and the factor an inside light's group gives the point; rays
// holds the light along the anchored rays at the previous slice. The light read from them
// still has to be attenuated over the point's last step, from the previous slice: that is
// left to the caller, the step's length stored in lastStep (0 when nothing is left). A ray
// that entered the box across C after the anchor slice is integrated from there, also by
// the caller: the length of its path inside the box is stored in entry (else 0).
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
  if (!Locate(AnchorSpread * (crossing[s.B] - s.Origin[s.B]) / s.Spacing[s.B],
        AnchorSpread * (crossing[s.C] - s.Origin[s.C]) / s.Spacing[s.C], sweep.RaysB, sweep.RaysC,
        at))
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

// TransmittanceAtPoint at `count` points equally spaced along axis B of a slice (p: 3 values
// a point, at most MaximumDivergingRays), their last steps integrated as a row
// (DivergingRowSegments), and so are the paths of the rays that entered the box across C:
// those of a row's points inside the box all enter the same face (the one between the row
// and the light along C) at the same fraction of their way from the light, the fraction
// that brings them to the face's coordinate along C, so their samples line up as their
// last steps' do.
void TransmittanceAlongRow(const SweepContext& s, const SweepSource& sweep, const float* rays,
  const double* p, int count, float* out, double* direction, double* groupFactor)
{
  double lastStep[MaximumDivergingRays], entry[MaximumDivergingRays];
  bool entries = false;
  for (int i = 0; i < count; ++i)
  {
    TransmittanceAtPoint(s, sweep, rays, p + 3 * i, out + s.Channels * i, direction + 3 * i,
      groupFactor[i], lastStep[i], entry[i]);
    entries = entries || entry[i] > 0.0;
  }
  DivergingRowSegments(s, p, direction, lastStep, count, out);
  if (entries)
  {
    DivergingRowSegments(s, p, direction, entry, count, out);
  }
}

// Position of ray (i, j) of a point or spot source where it leaves anchor slice k.
inline void AnchorPoint(const SweepContext& s, int k, int i, int j, double p[3])
{
  p[s.Axis] = SliceCoordinate(s, k);
  p[s.B] = s.Origin[s.B] + i * s.Spacing[s.B] / AnchorSpread;
  p[s.C] = s.Origin[s.C] + j * s.Spacing[s.C] / AnchorSpread;
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
    first = static_cast<int>(std::max(
      0.0, std::min<double>(sweep.RaysC, std::ceil((sweep.ConeLow[k] - s.Origin[s.C]) * scale))));
    last = static_cast<int>(std::min<double>(
      sweep.RaysC - 1, std::max(-1.0, std::floor((sweep.ConeHigh[k] - s.Origin[s.C]) * scale))));
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
  AnchorPoint(s, sweep.Anchor, 0, j, anchor);
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
        AnchorPoint(s, sweep.Anchor, i, j, offset);
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
    if (!step.Anchor)
    {
      RaysCrossingBox(s, sweep, step, k, j, crossing, beyond);
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
        for (int i = 0; i < size; ++i)
        {
          AnchorPoint(s, k, i0 + i, j, p + 3 * i);
        }
        double factors[MaximumDivergingRays];
        TransmittanceAlongRow(s, sweep, rays, p, size, next + s.Channels * firstRay, d, factors);
        continue;
      }
      // The rays through the anchor's points, at slice k, over their step from slice k - 1.
      for (int i = 0; i < size; ++i)
      {
        double offset[3];
        AnchorPoint(s, sweep.Anchor, i0 + i, j, offset);
        for (int c = 0; c < 3; ++c)
        {
          offset[c] -= light[c];
          p[3 * i + c] = light[c] + step.Scale * offset[c];
          d[3 * i + c] = offset[c] / norms[i0 + i];
        }
        length[i] = s.Spacing[s.Axis] / (s.Sign * d[3 * i + s.Axis]);
      }
      DivergingRowSegments(s, p, d, length, size, rays + s.Channels * firstRay);
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
  double p[3 * MaximumDivergingRays];
  for (int first = 0; first < nb; first += MaximumDivergingRays)
  {
    const int size = std::min(MaximumDivergingRays, nb - first);
    for (int i = 0; i < size; ++i)
    {
      p[3 * i + s.Axis] = SliceCoordinate(s, k);
      p[3 * i + s.B] = s.Origin[s.B] + (first + i) * s.Spacing[s.B];
      p[3 * i + s.C] = s.Origin[s.C] + ic * s.Spacing[s.C];
    }
    TransmittanceAlongRow(s, sweep, rays, p, size, out + s.Channels * first, direction + 3 * first,
      groupFactor + first);
  }
}
}
}
