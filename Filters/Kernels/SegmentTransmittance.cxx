#include "PropagationSweep.h"

#include <algorithm>
#include <cmath>

namespace volillum
{
namespace propagation
{
namespace
{
// The first value of the cell whose first point has the given indices in the material a
// sweep reads, the offsets from it to the cell's next corners along x, y and z (corner) and
// from a point to the next along the sweep's axis B (strideB): the volume's, or a wedge's,
// whose slices along the sweep's axis hold rows from their own first one on (so the offset
// to the next slice depends on the slice and the row).
inline const PackedValue* CellValues(
  const SweepContext& s, const int index[3], long long corner[3], long long* strideB = nullptr)
{
  const ClassifiedVolume& v = s.Volume;
  if (!s.Wedge)
  {
    const FieldLayout layout(v.Geometry, v.Channels);
    std::copy_n(layout.Corner, 3, corner);
    if (strideB)
    {
      *strideB = layout.Stride[s.B];
    }
    return v.Properties.data() + layout.Offset(index);
  }
  if (strideB)
  {
    *strideB = v.Channels;
  }
  const WedgeVolume& w = *s.Wedge;
  const auto& n = v.Geometry.Dimensions;
  const long long channels = v.Channels, nb = n[s.B];
  const int a = index[s.Axis], c = index[s.C];
  corner[s.B] = n[s.B] > 1 ? channels : 0;
  corner[s.C] = n[s.C] > 1 ? channels * nb : 0;
  corner[s.Axis] =
    n[s.Axis] > 1 ? channels * (w.Base[a + 1] - w.Base[a] - nb * (w.First[a + 1] - w.First[a])) : 0;
  return w.Volume.Properties.data() + channels * (w.Base[a] + nb * (c - w.First[a]) + index[s.B]);
}

// One midpoint sample (in `cell`, step length h given as ClassifiedVolume::ScaledStep) of a
// segment: without chromatic attenuation every channel keeps exp(-sigma h), so the optical
// depth is summed (depth) and applied once per segment (ApplyDepth); with it, out is
// multiplied per channel.
inline void AttenuateBySample(
  const SweepContext& s, const TrilinearCell& cell, float h, float& depth, float out[3])
{
  if (s.Empty && s.Empty->ContainsCell(cell.Index))
  {
    return;
  }
  const ClassifiedVolume& v = s.Volume;
  long long d[3];
  const PackedValue* q = CellValues(s, cell.Index, d);
  const float* f = cell.Fraction;
  auto channel = [&](int c)
  {
    return d[0] == 1 ? TrilinearInPackedCell(q + c, d[1], d[2], f[0], f[1], f[2])
                     : TrilinearInCell(q + c, d[0], d[1], d[2], f[0], f[1], f[2]);
  };
  const float sigma = channel(0);
  if (!(sigma > 0.0f))
  {
    return;
  }
  if (!v.IsChromatic())
  {
    depth += sigma * h;
    return;
  }
  const float a = 1.0f - std::exp(-sigma * h);
  for (int ch = 0; ch < 3; ++ch)
  {
    out[ch] *= 1.0f - a * channel(1 + ch) * v.Scale[1 + ch];
  }
}

inline void ApplyDepth(int channels, float depth, float* out)
{
  if (depth > 0.0f)
  {
    const float t = std::exp(-depth);
    for (int ch = 0; ch < channels; ++ch)
    {
      out[ch] *= t;
    }
  }
}

// Number of midpoint steps of a segment of the given length: the ceiling of its length in
// units of SegmentStep (less GeometricTolerance), at least 1. The ceiling is the truncation,
// plus 1 above it (the same as std::ceil for every count an int holds), which GCC and Clang
// vectorise in a loop over rays where std::ceil is a call or a branch without SSE4.1.
inline int SegmentSteps(const SweepContext& s, double length)
{
  const double x = length / s.SegmentStep - GeometricTolerance;
  const int truncated = static_cast<int>(x);
  return std::max(1, truncated + (x > truncated ? 1 : 0));
}
}

// The part [from, to] of the segment from p back along -d over `length` that lies inside
// the box (bounds); false when none does. Light is attenuated inside the volume only.
bool ClipToBox(const double bounds[6], const double p[3], const double d[3], double length,
  double& from, double& to)
{
  from = 0.0;
  to = length;
  for (int a = 0; a < 3; ++a)
  {
    // Points on a face (the grid's outer points) count as inside, whatever the rounding.
    const double tolerance = FaceTolerance(bounds, a);
    const double low = bounds[2 * a] - tolerance;
    const double high = bounds[2 * a + 1] + tolerance;
    if (d[a] == 0.0)
    {
      if (p[a] < low || p[a] > high)
      {
        return false;
      }
      continue;
    }
    const double first = (p[a] - high) / d[a];
    const double second = (p[a] - low) / d[a];
    from = std::max(from, std::min(first, second));
    to = std::min(to, std::max(first, second));
  }
  return to > from;
}

// Chromatic transmittance (multiplied into out) of the segment from p back along -d over
// `length`, integrated through the full-resolution classification with the midpoint rule and
// steps of at most its smallest spacing (read at full resolution, stored at the illumination
// grid's: thin material between two coarse slices still casts its shadow). Only the part
// inside the box attenuates. Halving the step changes the material error of the fidelity
// tests by less than 0.1 %: the error left is the interpolation of the light.
void SegmentTransmittance(
  const SweepContext& s, const double p[3], const double d[3], double length, float* out)
{
  double from, to;
  if (!ClipToBox(s.Bounds, p, d, length, from, to))
  {
    return;
  }
  const int n = SegmentSteps(s, to - from);
  const double h = (to - from) / n;
  // Steps in the volume's grid coordinates, from the far end of the part inside.
  const GridGeometry& g = s.Volume.Geometry;
  double first[3], step[3];
  for (int a = 0; a < 3; ++a)
  {
    first[a] = (p[a] - (from + 0.5 * h) * d[a] - g.Origin[a]) / g.Spacing[a];
    step[a] = -h * d[a] / g.Spacing[a];
  }
  const float hf = s.Volume.ScaledStep(h);
  float depth = 0.0f;
  for (int m = 0; m < n; ++m)
  {
    const double u[3] = { first[0] + m * step[0], first[1] + m * step[1], first[2] + m * step[2] };
    AttenuateBySample(s, CellAt(g, u), hf, depth, out);
  }
  ApplyDepth(s.Channels, depth, out);
}

namespace
{
// Most steps of a segment that RowSegments integrates as part of a row.
constexpr int MaximumRowSteps = 64;

// Adds h x sigma (sigma unpacked and interpolated at the fractions fx, fy, fz of the cells
// whose first points are q + i step, corner offsets dx, dy, dz; h a ScaledStep) to depth[i]
// for the `count` rays of a row: AttenuateBySample's sum without its branches (the
// extinction is 0 in an empty block and never negative, so the sums are the same), a loop
// the compiler vectorises.
inline void AddRowDepths(const PackedValue* q, long long step, long long dx, long long dy,
  long long dz, float fx, float fy, float fz, float h, int count, float* depth)
{
  for (int i = 0; i < count; ++i)
  {
    const float sigma = TrilinearInCell(q + i * step, dx, dy, dz, fx, fy, fz);
    depth[i] += (sigma > 0.0f ? sigma : 0.0f) * h;
  }
}

// AddRowDepths for rays a fractional number of cells apart along axis B: ray i (depth[i])
// samples the cell `cell` except along B, where it lies at grid coordinate
// u0 + (first + i) ratio (never below 0 nor at the last point). q: the cell's first point
// with index 0 along B. Adjacent: dx is 1 (TrilinearInPackedCell).
template <int B, bool Adjacent>
void AddFractionalRowDepths(const PackedValue* q, long long strideB, long long dx, long long dy,
  long long dz, const TrilinearCell& cell, double u0, double ratio, float h, int count,
  float* depth, int first)
{
  for (int i = 0; i < count; ++i)
  {
    const double u = u0 + (first + i) * ratio;
    const int index = static_cast<int>(u);
    const float f = static_cast<float>(u - index);
    const float fx = B == 0 ? f : cell.Fraction[0];
    const float fy = B == 1 ? f : cell.Fraction[1];
    const float fz = B == 2 ? f : cell.Fraction[2];
    const PackedValue* r = q + index * strideB;
    const float sigma = Adjacent ? TrilinearInPackedCell(r, dy, dz, fx, fy, fz)
                                 : TrilinearInCell(r, dx, dy, dz, fx, fy, fz);
    depth[i] += (sigma > 0.0f ? sigma : 0.0f) * h;
  }
}

// AddFractionalRowDepths along axis B, for adjacent values along x or not.
template <int B>
void AddFractionalRowDepthsAlong(const PackedValue* q, long long strideB, long long dx,
  long long dy, long long dz, const TrilinearCell& cell, double u0, double ratio, float h,
  int count, float* depth, int first)
{
  if (dx == 1)
  {
    AddFractionalRowDepths<B, true>(
      q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth, first);
  }
  else
  {
    AddFractionalRowDepths<B, false>(
      q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth, first);
  }
}

// AddFractionalRowDepths along axis b (0, 1 or 2); rays first to first + count - 1.
void AddFractionalRowDepthsAlong(int b, const PackedValue* q, long long strideB, long long dx,
  long long dy, long long dz, const TrilinearCell& cell, double u0, double ratio, float h,
  int count, float* depth, int first = 0)
{
  if (b == 0)
  {
    AddFractionalRowDepthsAlong<0>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth, first);
  }
  else if (b == 1)
  {
    AddFractionalRowDepthsAlong<1>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth, first);
  }
  else
  {
    AddFractionalRowDepthsAlong<2>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth, first);
  }
}

// Whether the cells first to last (first <= last) along B of the row through cell all lie
// in empty blocks (SweepContext Empty, given): their extinction is 0, so a row kernel
// leaves them out with the same sums, without reading empty space.
bool RowCellsEmpty(const SweepContext& s, const int cell[3], int first, int last)
{
  return s.Empty->ContainsCells(s.B, cell, first, last);
}

// AddFractionalRowDepthsAlong(s.B, ...) for rays [0, count) whose positions along B
// increase (ratio > 0), left out when their cells all lie in empty blocks.
void AddFractionalRowDepthsOutsideEmpty(const SweepContext& s, const PackedValue* q,
  long long strideB, long long dx, long long dy, long long dz, const TrilinearCell& cell, double u0,
  double ratio, float h, int count, float* depth)
{
  // The cells along B of the first and last rays, as AddFractionalRowDepths finds them.
  if (s.Empty && ratio > 0.0 &&
    RowCellsEmpty(s, cell.Index, static_cast<int>(u0), static_cast<int>(u0 + (count - 1) * ratio)))
  {
    return;
  }
  AddFractionalRowDepthsAlong(s.B, q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth);
}

// The row kernel without chromatic attenuation (one value a ray): the transmittance of
// `count` rays multiplied into out[i]. Ray i samples cells[m] with its position along B
// moved by i x ratio cells (alongB[m] on ray 0); shift is ratio when that is whole. The
// rays are summed sample by sample, a whole row at once.
void GreyRowTransmittance(const SweepContext& s, const TrilinearCell* cells, const double* alongB,
  int n, float h, double ratio, int shift, bool whole, int count, float* out)
{
  // The volume's values, or the slab's where it holds a sample's cell (the same values).
  const ExtinctionSlab entire = ExtinctionSlab::Entire(s.Volume);
  constexpr int Chunk = 256;
  float depth[Chunk];
  for (int begin = 0; begin < count; begin += Chunk)
  {
    const int size = std::min(Chunk, count - begin);
    std::fill_n(depth, size, 0.0f);
    for (int m = 0; m < n; ++m)
    {
      const TrilinearCell& c = cells[m];
      const ExtinctionSlab& view = s.Slab.HoldsCell(c.Index[0]) ? s.Slab : entire;
      const long long* stride = view.Layout.Stride;
      const long long dx = view.Layout.Corner[0], dy = view.Layout.Corner[1],
                      dz = view.Layout.Corner[2];
      const long long step = shift * stride[s.B];
      // The first value of ray 0's cell.
      const PackedValue* first = view.Cell(c.Index);
      if (!whole)
      {
        const PackedValue* q = first - c.Index[s.B] * stride[s.B]; // index 0 along B
        const double u0 = alongB[m] + begin * ratio;
        AddFractionalRowDepthsOutsideEmpty(
          s, q, stride[s.B], dx, dy, dz, c, u0, ratio, h, size, depth);
        continue;
      }
      const int firstCell = c.Index[s.B] + begin * shift;
      if (s.Empty && shift > 0 &&
        RowCellsEmpty(s, c.Index, firstCell, firstCell + (size - 1) * shift))
      {
        continue;
      }
      const PackedValue* q = first + begin * step;
      const float fx = c.Fraction[0], fy = c.Fraction[1], fz = c.Fraction[2];
      if (step == 1)
      {
        AddRowDepths(q, 1, dx, dy, dz, fx, fy, fz, h, size, depth);
      }
      else
      {
        AddRowDepths(q, step, dx, dy, dz, fx, fy, fz, h, size, depth);
      }
    }
    for (int i = 0; i < size; ++i)
    {
      ApplyDepth(1, depth[i], out + begin + i);
    }
  }
}
}

// SegmentTransmittance for `count` parallel segments (direction d, length) whose near ends
// lie `spacing` apart along the slice axis B, ray i at p + i spacing e_B (out: Channels
// values a ray). The samples of the rays wholly inside the volume share their cells and
// fractions along the two other axes: the cells are found once for the row and only the
// position along B moves from ray to ray (the row kernel). When the rays lie a whole number
// of the volume's cells apart along B (the illumination grid at the data's resolution), the
// fractions along B are shared too, and without chromatic attenuation the whole row is
// summed at once (GreyRowTransmittance). Other rays are integrated one by one. All give the
// same cells up to the rounding of the positions.
// Kept whole (issue 45): the per-row inner loop of a directional source's sweep (each lattice
// row and row of points); its parts share the row's sample cells (cells, alongB) and its run
// of rays inside the volume, so helpers would cost a call and a dozen arguments per row.
void RowSegments(const SweepContext& s, const double p[3], double spacing, int count,
  const double d[3], double length, float* out)
{
  const GridGeometry& g = s.Volume.Geometry;
  const double ratio = spacing / g.Spacing[s.B]; // the volume's cells from one ray to the next
  const int shift = static_cast<int>(std::lround(ratio));
  const bool whole = shift >= 1 && std::abs(ratio - shift) < GeometricTolerance;
  const int n = SegmentSteps(s, length);
  int first = 0, last = -1; // the rays wholly inside
  if (s.RowKernels && count > 1 && ratio > 0.0 && n <= MaximumRowSteps)
  {
    // Grid coordinates of both ends of ray 0's segment: rays inside the volume's grid (short
    // of its last point along B, so that every sample has a cell without clamping) are
    // inside the box, whose bounds are the volume's.
    bool inside = true;
    double low = 0.0, high = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double near = (p[a] - g.Origin[a]) / g.Spacing[a];
      const double far = (p[a] - length * d[a] - g.Origin[a]) / g.Spacing[a];
      const double lo = std::min(near, far), hi = std::max(near, far);
      if (a == s.B)
      {
        low = lo;
        high = hi;
      }
      else
      {
        inside = inside && lo >= 0.0 && hi < g.Dimensions[a] - 1;
      }
    }
    if (inside)
    {
      const double end = g.Dimensions[s.B] - 1;
      first = std::max(0, static_cast<int>(std::ceil(-low / ratio)));
      last = std::min(count - 1, static_cast<int>(std::ceil((end - high) / ratio)) - 1);
      // The divisions' rounding must not let a ray out.
      while (first <= last && low + first * ratio < 0.0)
      {
        ++first;
      }
      while (last >= first && high + last * ratio >= end)
      {
        --last;
      }
    }
  }
  TrilinearCell cells[MaximumRowSteps];
  double alongB[MaximumRowSteps]; // sample m's grid coordinate along B on ray `first`
  const double h = length / n;
  if (first <= last)
  {
    double u[3];
    for (int m = 0; m < n; ++m)
    {
      for (int a = 0; a < 3; ++a)
      {
        const double along = a == s.B ? first * spacing : 0.0;
        u[a] = (p[a] + along - (m + 0.5) * h * d[a] - g.Origin[a]) / g.Spacing[a];
      }
      cells[m] = CellAt(g, u);
      alongB[m] = u[s.B];
    }
  }
  const float hf = s.Volume.ScaledStep(h);
  const bool grey = !s.Volume.IsChromatic();
  if (grey && first <= last)
  {
    GreyRowTransmittance(
      s, cells, alongB, n, hf, ratio, shift, whole, last - first + 1, out + first);
  }
  double q[3] = { p[0], p[1], p[2] };
  for (int i = 0; i < count; ++i)
  {
    float* o = out + s.Channels * i;
    if (i < first || i > last)
    {
      q[s.B] = p[s.B] + i * spacing;
      SegmentTransmittance(s, q, d, length, o);
      continue;
    }
    if (grey)
    {
      continue;
    }
    float depth = 0.0f;
    for (int m = 0; m < n; ++m)
    {
      TrilinearCell cell = cells[m];
      if (whole)
      {
        cell.Index[s.B] += (i - first) * shift;
      }
      else
      {
        // Only the position along B moves from ray to ray.
        const double u = alongB[m] + (i - first) * ratio;
        cell.Index[s.B] = static_cast<int>(u);
        cell.Fraction[s.B] = static_cast<float>(u - cell.Index[s.B]);
      }
      AttenuateBySample(s, cell, hf, depth, o);
    }
    ApplyDepth(s.Channels, depth, o);
  }
}

// SegmentTransmittance(s, p_i, d_i, length_i, out_i) for `count` (at most
// MaximumDivergingRays) rays of a point or spot source whose near ends p_i lie equally spaced
// along axis B of a slice, at the same coordinate along C, and whose directions d_i point
// away from the light, each over the same fraction of its way back to the light (length_i
// proportional to the ray's distance from the light, as a step from the previous slice or
// a path from a face across C; 0: nothing to integrate). Such rays with the
// same number of steps place their m-th samples at the same coordinates along the sweep
// axis and along C, and along B affinely in the ray index (the ray's offset from the light
// along B is affine in it): without chromatic attenuation, a run of them inside the
// volume's grid is summed sample by sample, a run at a time (AddFractionalRowDepths), and
// the optical depth scaled by each ray's step length. Other rays are integrated one by one.
// Both give the same cells up to the rounding of the positions: a ray's result depends, by
// that rounding, on the run it belongs to (deterministic, as runs depend on the row only).
// Kept whole (issue 45): the per-row inner loop of a point or spot source's rays; its parts
// share the rays' steps and insideness and the runs' depths (arrays on the stack), so helpers
// would cost a call and those arrays per row.
void DivergingRowSegments(const SweepContext& s, const double* p, const double* d,
  const double* length, int count, float* out)
{
  const GridGeometry& g = s.Volume.Geometry;
  int steps[MaximumDivergingRays];
  bool inside[MaximumDivergingRays];
  const bool rows = s.RowKernels && !s.Volume.IsChromatic();
  // Both ends inside the grid put the whole segment inside the box: along B short of its
  // last point by more than the rounding of the interpolated positions (every sample has its
  // cell there without clamping), along the other axes up to twice the tolerance of
  // ClipToBox, which may have put an end there on a face (the samples, midpoints, lie
  // inside). Per axis, the grid coordinates [low, high] an end may take.
  double low[3], high[3];
  for (int a = 0; a < 3; ++a)
  {
    const double end = g.Dimensions[a] - 1;
    if (a == s.B)
    {
      low[a] = 0.0;
      high[a] = end - GeometricTolerance * end;
      continue;
    }
    const double tolerance = 2.0 * FaceTolerance(s.Bounds, a) / g.Spacing[a];
    low[a] = -tolerance;
    high[a] = end + tolerance;
  }
  for (int i = 0; i < count && rows; ++i)
  {
    inside[i] = length[i] > 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double near = (p[3 * i + a] - g.Origin[a]) / g.Spacing[a];
      const double far = (p[3 * i + a] - length[i] * d[3 * i + a] - g.Origin[a]) / g.Spacing[a];
      inside[i] = inside[i] && std::min(near, far) >= low[a] &&
        (a == s.B ? std::max(near, far) < high[a] : std::max(near, far) <= high[a]);
    }
    steps[i] = inside[i] ? SegmentSteps(s, length[i]) : 0;
  }
  // Grid coordinates of ray i's samples: start + m step for sample m.
  auto samples = [&](int i, double start[3], double step[3])
  {
    const double h = length[i] / steps[i];
    for (int a = 0; a < 3; ++a)
    {
      start[a] = (p[3 * i + a] - 0.5 * h * d[3 * i + a] - g.Origin[a]) / g.Spacing[a];
      step[a] = -h * d[3 * i + a] / g.Spacing[a];
    }
  };
  float depth[MaximumDivergingRays];
  for (int first = 0; first < count;)
  {
    int last = first;
    while (rows && inside[first] && last + 1 < count && inside[last + 1] &&
      steps[last + 1] == steps[first])
    {
      ++last;
    }
    if (last == first)
    {
      if (length[first] > 0.0)
      {
        SegmentTransmittance(
          s, p + 3 * first, d + 3 * first, length[first], out + s.Channels * first);
      }
      ++first;
      continue;
    }
    const int size = last - first + 1;
    std::fill_n(depth, size, 0.0f);
    double firstStart[3], firstStep[3], lastStart[3], lastStep[3];
    samples(first, firstStart, firstStep);
    samples(last, lastStart, lastStep);
    for (int m = 0; m < steps[first]; ++m)
    {
      double u[3], v[3];
      for (int a = 0; a < 3; ++a)
      {
        u[a] = firstStart[a] + m * firstStep[a];
        v[a] = lastStart[a] + m * lastStep[a];
      }
      const TrilinearCell cell = CellAt(g, u);
      long long corner[3], strideB;
      const PackedValue* q = CellValues(s, cell.Index, corner, &strideB);
      AddFractionalRowDepthsOutsideEmpty(s, q - cell.Index[s.B] * strideB, strideB, corner[0],
        corner[1], corner[2], cell, u[s.B], (v[s.B] - u[s.B]) / (size - 1), 1.0f, size, depth);
    }
    for (int i = 0; i < size; ++i)
    {
      ApplyDepth(1, s.Volume.ScaledStep(length[first + i] / steps[first]) * depth[i],
        out + s.Channels * (first + i));
    }
    first = last + 1;
  }
}
namespace
{
// Most values of the extinction along B that AddLightRowSamples keeps for a run of rays: rays
// at most two of the volume's cells apart.
constexpr int MaximumLine = 2 * MaximumDivergingRays + 2;

// Grid coordinate along axis a of the point a fraction t of the way from the light to the
// near end of ray 0 of `row`.
inline double RowCoordinate(const GridGeometry& g, const LightRow& row, double t, int a)
{
  return (row.Light[a] + t * (row.Near[a] - row.Light[a]) - g.Origin[a]) / g.Spacing[a];
}

// Adds the extinction at the samples a fraction t of the way from the light to the near ends
// of rays first to first + count - 1 of `row` (all inside the volume's grid, at most
// MaximumDivergingRays) to their depths (depth[0] for ray first). The samples share their
// coordinates along the sweep axis and C, so the extinction is interpolated along those once,
// at the points of the volume along B the rays pass (`line`), and each ray interpolates that
// along B: fewer reads than a trilinear sample a ray while rays are at most two cells apart
// (beyond, they sample their cells directly). Ray i's coordinate along B is ray 0's plus
// i times the rays' spacing, so its result does not depend on the run it is summed in.
void AddLightRowSamples(
  const SweepContext& s, const LightRow& row, double t, int first, int count, float* depth)
{
  const GridGeometry& g = s.Volume.Geometry;
  const int b = s.B;
  const double origin = RowCoordinate(g, row, t, b); // ray 0's
  const double spacing = t * row.StepB / g.Spacing[b];
  double u[3];
  for (int a = 0; a < 3; ++a)
  {
    u[a] = a == b ? origin + first * spacing : RowCoordinate(g, row, t, a);
  }
  const TrilinearCell cell = CellAt(g, u);
  const int low = cell.Index[b];
  const int high =
    std::min(static_cast<int>(origin + (first + count - 1) * spacing), g.Dimensions[b] - 2);
  if (s.Empty && RowCellsEmpty(s, cell.Index, low, high))
  {
    return;
  }
  int start[3] = { cell.Index[0], cell.Index[1], cell.Index[2] };
  start[b] = 0;
  long long corner[3], strideB;
  const PackedValue* q = CellValues(s, start, corner, &strideB);
  if (spacing > 2.0 || high - low + 2 > MaximumLine)
  {
    AddFractionalRowDepthsAlong(b, q, strideB, corner[0], corner[1], corner[2], cell, origin,
      spacing, 1.0f, count, depth, first);
    return;
  }
  const float fa = cell.Fraction[s.Axis], fc = cell.Fraction[s.C];
  const long long da = corner[s.Axis], dc = corner[s.C];
  float line[MaximumLine];
  for (int x = low; x <= high + 1; ++x)
  {
    const PackedValue* r = q + x * strideB;
    const float c0 = Unpack(r[0]) + fa * (Unpack(r[da]) - Unpack(r[0]));
    const float c1 = Unpack(r[dc]) + fa * (Unpack(r[dc + da]) - Unpack(r[dc]));
    line[x - low] = c0 + fc * (c1 - c0);
  }
  for (int i = 0; i < count; ++i)
  {
    const double v = origin + (first + i) * spacing;
    const int x = std::min(static_cast<int>(v), high) - low;
    const float f = static_cast<float>(v - (x + low));
    const float sigma = line[x] + f * (line[x + 1] - line[x]);
    depth[i] += sigma > 0.0f ? sigma : 0.0f;
  }
}

// The rays [first, last] of `row` (among first to first + count - 1) whose both ends lie
// inside the grid, as DivergingRowSegments requires of a run; none: first > last.
void RaysInsideGrid(const SweepContext& s, const LightRow& row, int& first, int& last)
{
  const GridGeometry& g = s.Volume.Geometry;
  for (const double t : { 1.0, 1.0 - row.Fraction })
  {
    for (int a = 0; a < 3; ++a)
    {
      const double end = g.Dimensions[a] - 1;
      const double origin = RowCoordinate(g, row, t, a);
      if (a != s.B)
      {
        const double tolerance = 2.0 * FaceTolerance(s.Bounds, a) / g.Spacing[a];
        if (origin < -tolerance || origin > end + tolerance)
        {
          last = first - 1;
        }
        continue;
      }
      const double spacing = t * row.StepB / g.Spacing[a];
      const double high = end - GeometricTolerance * end;
      if (!(spacing > 0.0))
      {
        last = origin >= 0.0 && origin < high ? last : first - 1;
        continue;
      }
      const double lowest = std::ceil(-origin / spacing);
      const double highest = std::ceil((high - origin) / spacing) - 1.0;
      first = static_cast<int>(std::max<double>(first, std::min<double>(lowest, last + 1)));
      last = static_cast<int>(std::min<double>(last, std::max<double>(highest, first - 1)));
      // The divisions' rounding must not let a ray out.
      while (first <= last && origin + first * spacing < 0.0)
      {
        ++first;
      }
      while (last >= first && origin + last * spacing >= high)
      {
        --last;
      }
    }
  }
}
}

// DivergingRowSegments for the rays of a row (LightRow): those inside the volume's grid
// summed a run of equal step counts at a time (AddLightRowSamples), without per-ray
// positions, directions or tests; the others integrated one by one.
void LightRowTransmittance(const SweepContext& s, const LightRow& row, int first, int count,
  const double* distance, float* out)
{
  int inFirst = first, inLast = first + count - 1;
  RaysInsideGrid(s, row, inFirst, inLast);
  for (int i = first; i < first + count; ++i)
  {
    if (i < inFirst || i > inLast)
    {
      double p[3], d[3];
      row.NearEnd(i, p, s.B);
      for (int a = 0; a < 3; ++a)
      {
        d[a] = (p[a] - row.Light[a]) / distance[i - first];
      }
      SegmentTransmittance(s, p, d, distance[i - first] * row.Fraction, out + (i - first));
    }
  }
  if (inFirst > inLast)
  {
    return;
  }
  // Runs of rays with the same number of steps, each summed sample by sample.
  int steps[MaximumDivergingRays];
  float depth[MaximumDivergingRays];
  for (int i = inFirst - first; i <= inLast - first; ++i)
  {
    steps[i] = SegmentSteps(s, distance[i] * row.Fraction);
    depth[i] = 0.0f;
  }
  for (int r = inFirst - first; r <= inLast - first;)
  {
    int end = r + 1;
    while (end <= inLast - first && steps[end] == steps[r])
    {
      ++end;
    }
    const int n = steps[r];
    for (int m = 0; m < n; ++m)
    {
      AddLightRowSamples(s, row, 1.0 - (m + 0.5) * row.Fraction / n, first + r, end - r, depth + r);
    }
    r = end;
  }
  for (int i = inFirst - first; i <= inLast - first; ++i)
  {
    ApplyDepth(1, s.Volume.ScaledStep(distance[i] * row.Fraction / steps[i]) * depth[i], out + i);
  }
}
}
}
