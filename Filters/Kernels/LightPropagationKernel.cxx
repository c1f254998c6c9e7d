#include "LightPropagationKernel.h"

#include "ParallelSteps.h"

#include "vtkMath.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace volillum
{

namespace
{
// The group that sweeps along axis toward the sign of component.
int GroupOf(int axis, double component)
{
  return 2 * axis + (component >= 0.0 ? 0 : 1);
}

// Where light of one geometry (kind, position or direction) comes from. Lights that share
// a geometry share the transmittance of their rays, so a sweep propagates each geometry
// once, whatever the lights' colours, intensities, weights and spot cones.
struct RaySource
{
  bool Directional;
  bool Inside;
  double Travel[3]; // directional: the direction light travels
  double Position[3];

  bool operator==(const RaySource& o) const
  {
    return this->Directional == o.Directional && this->Inside == o.Inside &&
      std::equal(this->Travel, this->Travel + 3, o.Travel) &&
      std::equal(this->Position, this->Position + 3, o.Position);
  }
};

// A deposit's fixed-point units: x rounded half away from zero, so that -x rounds to exactly
// minus what x rounds to (a light state removed later cancels to the last unit). Deposits
// stay below 2^31 units (every total an update may show is at most 2^30 units,
// FixedPointIllumination::Holds), so 32 bits hold them; a NaN
// or an overflowing product gives 0 instead of an undefined conversion. Branch-free, so that
// a row of deposits vectorises.
inline std::int32_t DepositUnits(double x)
{
  const double rounded = x >= 0.0 ? x + 0.5 : x - 0.5;
  return static_cast<std::int32_t>(std::abs(rounded) < 2147483647.0 ? rounded : 0.0);
}

// Smallest progress along the sweep axis per unit of path a ray must make for a group to
// carry it.
constexpr double MinimumAlong = 1e-6;

// Slices a sweep along x deposits into a buffer before adding them to the illumination
// (SweepSlices::Flush): the units of 4 points along x are 48 bytes, mostly one cache line.
// The buffer holds 4 / nx of the illumination's units (0.2 bytes a point for nx = 256); 8
// slices measured no faster.
constexpr int DepositSlices = 4;

// How many rows ahead SweepSlices::Flush and CopySlab ask for the cache lines they will
// use: theirs lie rows apart, which the hardware prefetchers do not follow.
constexpr int RowsAhead = 16;

// Asks for the cache line at p ahead of a read (Write 0: read once, not kept in the caches
// closest to the core) or of a write (1: kept in the outer caches until written); nothing
// where the compiler cannot.
template <int Write>
inline void Prefetch(const void* p)
{
#if defined(__GNUC__)
  __builtin_prefetch(p, Write, Write);
#else
  (void)p;
#endif
}

// One task as the sweep deposits it.
struct Deposit
{
  size_t Source;
  bool Spot;
  int OtherAxis = -1, OtherSign = 1; // the other group of a two-group point or spot light
  double Whole = 1.0;                // (weight + other weight) / weight
  double Axis[3];                    // spot cone axis
  double CosCone;
  double Exponent;
  double Scaled[3]; // radiance x weight x sign x fixed-point scale
  bool Recorded = false;
  bool Uniform = false; // a directional source: group and spot factors 1 at every pixel
};

RaySource SourceOf(const PropagationTask& task)
{
  RaySource r;
  const LightState& l = task.Light;
  r.Directional = l.Kind == LightKind::Directional;
  r.Inside = task.Inside;
  const auto d = l.Direction();
  for (int a = 0; a < 3; ++a)
  {
    r.Travel[a] = r.Directional ? d[a] : 0.0;
    r.Position[a] = r.Directional ? 0.0 : l.Position[a];
  }
  return r;
}

// Position in a slice (width nb, height nc) as the cell (iu, iv) and the fractions in it.
struct SlicePoint
{
  int U, V;
  float FU, FV;
};

// Where (u, v) falls, or false when outside the slice.
inline bool Locate(double u, double v, int nb, int nc, SlicePoint& at)
{
  if (u < 0.0 || v < 0.0 || u > nb - 1 || v > nc - 1)
  {
    return false;
  }
  at.U = std::min(static_cast<int>(u), std::max(nb - 2, 0));
  at.V = std::min(static_cast<int>(v), std::max(nc - 2, 0));
  at.FU = nb > 1 ? static_cast<float>(u - at.U) : 0.0f;
  at.FV = nc > 1 ? static_cast<float>(v - at.V) : 0.0f;
  return true;
}

// Bilinear interpolation of interleaved channels; strides in values (0 along a flat axis).
inline void Bilinear(const float* base, int channels, long long strideU, long long strideV,
  const SlicePoint& at, float* out)
{
  const float* q = base + at.U * strideU + at.V * strideV;
  for (int ch = 0; ch < channels; ++ch)
  {
    const float a = q[ch] + at.FU * (q[strideU + ch] - q[ch]);
    const float b = q[strideV + ch] + at.FU * (q[strideV + strideU + ch] - q[strideV + ch]);
    out[ch] = a + at.FV * (b - a);
  }
}

// Catmull-Rom weights for the fraction f between the second and third of four samples.
inline void CubicWeights(float f, float w[4])
{
  const float f2 = f * f;
  const float f3 = f2 * f;
  w[0] = 0.5f * (-f3 + 2.0f * f2 - f);
  w[1] = 0.5f * (3.0f * f3 - 5.0f * f2 + 2.0f);
  w[2] = 0.5f * (-3.0f * f3 + 4.0f * f2 + f);
  w[3] = 0.5f * (f3 - f2);
}

// An interpolated value limited to the range of the four values around it (no new extremes).
inline float ClampToSurrounding(float sum, float a, float b, float c, float d)
{
  return std::min(std::max(sum, std::min(std::min(a, b), std::min(c, d))),
    std::max(std::max(a, b), std::max(c, d)));
}

// Bicubic (Catmull-Rom) interpolation of a slice buffer (nb x nc pixels, `channels` values
// each) at `at`, limited to the range of the four surrounding pixels so that it adds no new
// extremes. The buffer may hold only `rows` rows from firstRow on (base: that row; 0: those
// up to the last), those the taps read; a tap beyond them reads the nearest row held.
inline void MonotoneBicubic(const float* base, int channels, int nb, int nc, const SlicePoint& at,
  float* out, int firstRow = 0, int rows = 0)
{
  rows = rows > 0 ? rows : nc - firstRow;
  const long long rowValues = 1LL * channels * nb;
  if (nb < 4 || nc < 4)
  {
    // (clamped to the rows held as the taps below are)
    SlicePoint local = at;
    local.V = std::min(std::max(at.V - firstRow, 0), std::max(rows - 2, 0));
    Bilinear(base, channels, nb > 1 ? channels : 0, nc > 1 && rows > 1 ? rowValues : 0, local, out);
    return;
  }
  float wu[4], wv[4];
  CubicWeights(at.FU, wu);
  CubicWeights(at.FV, wv);
  int iu[4], iv[4];
  for (int m = 0; m < 4; ++m)
  {
    iu[m] = std::min(std::max(at.U - 1 + m, 0), nb - 1);
    iv[m] = std::min(std::max(at.V - 1 + m, 0), nc - 1) - firstRow;
    iv[m] = std::min(std::max(iv[m], 0), rows - 1);
  }
  for (int ch = 0; ch < channels; ++ch)
  {
    float sum = 0.0f;
    for (int mv = 0; mv < 4; ++mv)
    {
      const float* row = base + rowValues * iv[mv] + ch;
      sum += wv[mv] *
        (wu[0] * row[channels * iu[0]] + wu[1] * row[channels * iu[1]] +
          wu[2] * row[channels * iu[2]] + wu[3] * row[channels * iu[3]]);
    }
    const float a = base[rowValues * iv[1] + channels * iu[1] + ch];
    const float b = base[rowValues * iv[1] + channels * iu[2] + ch];
    const float c = base[rowValues * iv[2] + channels * iu[1] + ch];
    const float d = base[rowValues * iv[2] + channels * iu[2] + ch];
    out[ch] = ClampToSurrounding(sum, a, b, c, d);
  }
}

// MonotoneBicubic for the pixels [first, last] of a row whose positions in the slice buffer
// (width x height pixels, `channels` values each) share their fractions (fu, fv): pixel i
// lies in cell (i + shiftU, v) and all its taps inside the buffer (1 <= first + shiftU,
// last + shiftU + 2 < width, 1 <= v, v + 2 < height). The weights are computed once, and the
// row is one flat loop the compiler vectorises; the same values as MonotoneBicubic.
template <int Channels>
void MonotoneBicubicRow(const float* base, int width, int shiftU, int v, float fu, float fv,
  int first, int last, float* out)
{
  float wu[4], wv[4];
  CubicWeights(fu, wu);
  CubicWeights(fv, wv);
  const float u0 = wu[0], u1 = wu[1], u2 = wu[2], u3 = wu[3];
  const float v0 = wv[0], v1 = wv[1], v2 = wv[2], v3 = wv[3];
  const long long rowValues = 1LL * Channels * width;
  // Tap (mu, mv) of value x of the row (x = Channels x pixel + channel) is r_mv[x + mu C].
  const float* r0 = base + rowValues * (v - 1) + Channels * (shiftU - 1);
  const float* r1 = r0 + rowValues;
  const float* r2 = r1 + rowValues;
  const float* r3 = r2 + rowValues;
  constexpr int C = Channels;
  for (int x = C * first; x < C * (last + 1); ++x)
  {
    float sum = 0.0f;
    sum += v0 * (u0 * r0[x] + u1 * r0[x + C] + u2 * r0[x + 2 * C] + u3 * r0[x + 3 * C]);
    sum += v1 * (u0 * r1[x] + u1 * r1[x + C] + u2 * r1[x + 2 * C] + u3 * r1[x + 3 * C]);
    sum += v2 * (u0 * r2[x] + u1 * r2[x + C] + u2 * r2[x + 2 * C] + u3 * r2[x + 3 * C]);
    sum += v3 * (u0 * r3[x] + u1 * r3[x + C] + u2 * r3[x + 2 * C] + u3 * r3[x + 3 * C]);
    const float a = r1[x + C], b = r1[x + 2 * C];
    const float c = r2[x + C], d = r2[x + 2 * C];
    out[x] = ClampToSurrounding(sum, a, b, c, d);
  }
}

// Grey extinction at points Low to High along x of the volume's grid: point (i, j, k) at
// Values + (i - Low) Stride[0] + j Stride[1] + k Stride[2] (Layout).
struct ExtinctionSlab
{
  const PackedValue* Values = nullptr;
  FieldLayout Layout;
  int Low = 0, High = -1;

  // The whole volume's extinction (grey: one value a point).
  static ExtinctionSlab Entire(const ClassifiedVolume& volume)
  {
    ExtinctionSlab entire;
    entire.Values = volume.Properties.data();
    entire.Layout = FieldLayout(volume.Geometry, 1);
    entire.High = volume.Geometry.Dimensions[0] - 1;
    return entire;
  }
  // Whether it holds the points of a cell whose first point along x is i.
  bool HoldsCell(int i) const { return this->Low <= i && i + 1 <= this->High; }
  // The first value of a cell it holds.
  const PackedValue* Cell(const int index[3]) const
  {
    return this->Values + (this->Layout.Offset(index) - this->Low * this->Layout.Stride[0]);
  }
};

// One sweep over the illumination grid (N, Stride, Origin, Spacing, Bounds) along Axis
// toward Sign; light is attenuated through the full-resolution Volume, whose Empty blocks
// (when given) are skipped.
struct SweepContext
{
  const ClassifiedVolume& Volume;
  const EmptyBlocks* Empty;
  double SegmentStep; // longest midpoint step: the volume's smallest spacing
  int Axis, Sign, B, C;
  int N[3];
  long long Stride[3];
  double Origin[3], Spacing[3];
  double Bounds[6];
  // The layout of the units the sweep deposits into: point (i, j, k) of the grid at
  // 3 ((i, j, k) - UnitFirst) . UnitStride: the whole grid (Stride, UnitFirst 0), or the
  // rows of a band (SweepBand).
  long long UnitStride[3];
  int UnitFirst[3];
  // Whether rows of segments may share their samples' cells (RowSegments for directional
  // sources, DivergingRowSegments for point and spot sources); false integrates every segment
  // on its own.
  bool RowKernels;
  // Values of light per ray or pixel: 3 (RGB) with chromatic attenuation; else 1, as every
  // channel keeps the same transmittance.
  int Channels;
  // Sweeps along x with a directional source, row kernels and no chromatic attenuation: a
  // copy of the volume's extinction at the points along x the current chunk of slices
  // reaches, rows along y contiguous (SweepSlices::SlabFor and CopySlab), read by the grey
  // row kernel; none (Low > High) otherwise.
  ExtinctionSlab Slab;
  // A sweep over a wedge (PropagateSweepWedge): the material it holds (Volume then gives only
  // the grid and the classification's channels and scales), and per slice k the first row of
  // its units (UnitSliceFirst) and where they start (UnitSliceBase, in points). Null and
  // empty otherwise.
  const WedgeVolume* Wedge = nullptr;
  std::vector<int> UnitSliceFirst;
  std::vector<long long> UnitSliceBase;
};

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

// A ray source as one sweep uses it; for a directional light everything that does not
// depend on the point is worked out once.
//
// A directional light's rays are parallel, so they are followed exactly: a lattice of rays
// one cell apart crosses every slice, and a ray moves from one slice to the next by the
// same offset as every other. The lattice is the grid shifted by the fraction of the
// accumulated offset, so a ray's predecessor is a whole number of cells away and is read
// without interpolation. A grid point interpolates the previous slice's lattice once, where
// its own ray crosses it, and integrates its last step itself (RowFromLattice). Reading the
// previous slice's grid values by interpolation instead would blur a shadow edge a little
// at every slice.
struct SweepSource
{
  RaySource Source;
  bool Enters = false;  // directional: light does not progress along the axis
  double Step = 0.0;    // directional: path length between slices
  double OffsetU = 0.0; // directional: how far a ray moves from one slice to the next, in cells
  double OffsetV = 0.0;

  SweepSource(const RaySource& source, const SweepContext& s)
    : SweepSource(source, s.Axis, s.Sign, s.B, s.C, s.Spacing)
  {
  }
  // The source in a sweep along `axis` toward `sign` of a grid of `spacing`, its rows along
  // b, ordered along c.
  SweepSource(const RaySource& source, int axis, int sign, int b, int c, const double spacing[3])
    : Source(source)
  {
    if (!source.Directional)
    {
      return;
    }
    const double along = sign * source.Travel[axis];
    this->Enters = along <= MinimumAlong;
    if (!this->Enters)
    {
      this->Step = spacing[axis] / along;
      this->OffsetU = source.Travel[b] * this->Step / spacing[b];
      this->OffsetV = source.Travel[c] * this->Step / spacing[c];
    }
  }

  /// Whether the source's light is carried by a ray lattice (see above).
  bool FollowsRays() const { return this->Source.Directional && !this->Enters; }

  /// Point and spot sources: the slice (index along the axis) that anchors the rays
  /// followed, -1 while there is none, and the number of rays along each slice axis.
  int Anchor = -1;
  int RaysB = 0, RaysC = 0;
  /// Point and spot sources: the rows of rays the buffers (and Norms) hold, RayRows from
  /// RayFirst on: every row, or those of a band's cone at any anchor (ConeRows).
  int RayFirst = 0, RayRows = 0;
  /// Point and spot sources: each ray's distance from the light to its anchor point, which
  /// gives its direction at every slice until the anchor moves, so computed once per anchor
  /// (a square root a ray and slice cost more than a fifth of the ray's step): row j of rays
  /// holds those of anchor RowAnchor[j] (-1: none yet).
  std::vector<double> Norms;
  std::vector<int> RowAnchor;
  /// Point and spot sources swept over a wedge (SweepWedge): per slice k, the interval
  /// [ConeLow[k], ConeHigh[k]] along C of the rays the wedge needs there (ConeOfWedge);
  /// empty: every ray.
  std::vector<double> ConeLow, ConeHigh;
};

// Where the ray lattice of a directional source crosses slice t: lattice ray (i, j) lies
// at (i - 1 + FractionU, j - 1 + FractionV) in the slice's cells (one ray beyond each side,
// so every point of the slice has a ray on either side), and came from lattice ray
// (i - ShiftU, j - ShiftV) of slice t - 1.
struct LatticePhase
{
  double FractionU, FractionV;
  int ShiftU, ShiftV;

  LatticePhase(const SweepSource& sweep, int t)
  {
    const double u = t * sweep.OffsetU;
    const double v = t * sweep.OffsetV;
    const double previousU = std::floor((t - 1) * sweep.OffsetU);
    const double previousV = std::floor((t - 1) * sweep.OffsetV);
    this->FractionU = u - std::floor(u);
    this->FractionV = v - std::floor(v);
    this->ShiftU = static_cast<int>(std::floor(u) - previousU);
    this->ShiftV = static_cast<int>(std::floor(v) - previousV);
  }
};

// How far from a face of the box (bounds) across axis a a point still counts as on it: the
// geometric tolerance of the box's extent.
inline double FaceTolerance(const double bounds[6], int a)
{
  return GeometricTolerance * (bounds[2 * a + 1] - bounds[2 * a] + 1.0);
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

// Whether coordinate x along axis a lies on one of the box's faces across a: within twice
// the tolerance ClipToBox gives points on a face, as it puts the ends it clips that far out
// (give or take their rounding).
inline bool OnFaceAcross(const double bounds[6], int a, double x)
{
  const double tolerance = 2.0 * FaceTolerance(bounds, a);
  return std::abs(x - bounds[2 * a]) <= tolerance || std::abs(x - bounds[2 * a + 1]) <= tolerance;
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

// Number of midpoint steps of a segment of the given length.
inline int SegmentSteps(const SweepContext& s, double length)
{
  return std::max(1, static_cast<int>(std::ceil(length / s.SegmentStep - GeometricTolerance)));
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

// AddRowDepths for rays a fractional number of cells apart along axis B: ray i samples the
// cell `cell` except along B, where it lies at grid coordinate u0 + i ratio (never below 0
// nor at the last point). q: the cell's first point with index 0 along B. Adjacent: dx is 1
// (TrilinearInPackedCell).
template <int B, bool Adjacent>
void AddFractionalRowDepths(const PackedValue* q, long long strideB, long long dx, long long dy,
  long long dz, const TrilinearCell& cell, double u0, double ratio, float h, int count,
  float* depth)
{
  for (int i = 0; i < count; ++i)
  {
    const double u = u0 + i * ratio;
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
  int count, float* depth)
{
  if (dx == 1)
  {
    AddFractionalRowDepths<B, true>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth);
  }
  else
  {
    AddFractionalRowDepths<B, false>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth);
  }
}

// AddFractionalRowDepths along axis b (0, 1 or 2).
void AddFractionalRowDepthsAlong(int b, const PackedValue* q, long long strideB, long long dx,
  long long dy, long long dz, const TrilinearCell& cell, double u0, double ratio, float h,
  int count, float* depth)
{
  if (b == 0)
  {
    AddFractionalRowDepthsAlong<0>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth);
  }
  else if (b == 1)
  {
    AddFractionalRowDepthsAlong<1>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth);
  }
  else
  {
    AddFractionalRowDepthsAlong<2>(q, strideB, dx, dy, dz, cell, u0, ratio, h, count, depth);
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

// SegmentTransmittance for `count` parallel segments (direction d, length) whose near ends
// lie `spacing` apart along the slice axis B, ray i at p + i spacing e_B (out: Channels
// values a ray). The samples of the rays wholly inside the volume share their cells and
// fractions along the two other axes: the cells are found once for the row and only the
// position along B moves from ray to ray (the row kernel). When the rays lie a whole number
// of the volume's cells apart along B (the illumination grid at the data's resolution), the
// fractions along B are shared too, and without chromatic attenuation the whole row is
// summed at once (GreyRowTransmittance). Other rays are integrated one by one. All give the
// same cells up to the rounding of the positions.
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

// Most rays DivergingRowSegments takes at once.
constexpr int MaximumDivergingRays = 256;

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

// A point or spot light's rays diverge, so no lattice keeps them a whole number of cells
// apart. They are followed exactly from an anchor slice instead: rays leave the anchor
// AnchorSpread times closer together than its points, are attenuated slice by slice
// (AdvanceAnchoredRays), and the light reaching a point is interpolated from them where
// the point's own ray crosses the previous slice, then attenuated over its last step. Once
// the rays have spread to a cell apart, the anchor moves to the current slice (its rays
// take the light computed there the same way): the light is interpolated once per anchor
// instead of once per slice, and rays are never farther apart than the grid's points.
// Until a slice in front of the light anchors the rays, light is integrated all the way
// from the light (inside the box only). Measured on the fidelity scenes (material RMS of
// point and spot lights at scale 1 and 0.5): a spread of 1.25 leaves up to 11.9 %, 1.5 up
// to 10.0 % and 2 up to 9.7 %, at 1.6x, 2.2x and 4x the rays (re-anchoring at every
// slice on the grid's points, the former method, up to 20 %).
constexpr double AnchorSpread = 1.5;

// Axis coordinate of slice k of the sweep.
inline double SliceCoordinate(const SweepContext& s, int k)
{
  return s.Origin[s.Axis] + k * s.Spacing[s.Axis];
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

// What slice k does to a point or spot source's rays once its points are lit: nothing
// (InFront false: the slice is not in front of the light), anchor the rays there (Anchor:
// their light is computed from the rays reaching the previous slice) or attenuate the rays
// over the step to it (their position there is the anchor's scaled by Scale from the light).
struct AnchoredStep
{
  bool InFront = false;
  bool Anchor = false;
  double Scale = 1.0;

  AnchoredStep(const SweepContext& s, const SweepSource& sweep, int k)
  {
    const int a = s.Axis;
    const double light = sweep.Source.Position[a];
    const double from = s.Sign * (SliceCoordinate(s, k) - light);
    this->InFront = IsInFront(from, s.Spacing[a]);
    if (!this->InFront)
    {
      return;
    }
    this->Anchor = sweep.Anchor < 0 ||
      from >= AnchorSpread * s.Sign * (SliceCoordinate(s, sweep.Anchor) - light);
    if (!this->Anchor)
    {
      this->Scale = (SliceCoordinate(s, k) - light) / (SliceCoordinate(s, sweep.Anchor) - light);
    }
  }

  // Whether a slice `from` away from the light along the sweep (spacing apart) is in front
  // of it.
  static bool IsInFront(double from, double spacing) { return from > GeometricTolerance * spacing; }
};

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

// Row j of a directional source's ray lattice at slice t (out: 3 floats a ray), from the
// lattice of slice t - 1 (previous: its rows from firstRow on, those the row reads); rays
// without a predecessor entered through a side face.
void LatticeRow(const SweepContext& s, const SweepSource& sweep, const LatticePhase& phase,
  const float* previous, int firstRow, int t, int k, int j, float* out)
{
  const int width = s.N[s.B] + 1;
  const int height = s.N[s.C] + 1;
  const int channels = s.Channels;
  if (t == 0)
  {
    std::fill(out, out + channels * width, 1.0f);
    return;
  }
  // Rays [first, last) have a predecessor, ray i - ShiftU of row j - ShiftV of the previous
  // lattice; the others entered through a side face after the previous slice. Rays beside
  // the box carry light unattenuated (SegmentTransmittance integrates inside the box only);
  // points on its faces interpolate between them and the rays inside.
  const int from = j - phase.ShiftV;
  int first = 0, last = 0;
  if (from >= 0 && from < height)
  {
    first = std::min(std::max(phase.ShiftU, 0), width);
    last = std::max(std::min(width + phase.ShiftU, width), first);
  }
  std::fill(out, out + channels * first, 1.0f);
  if (first < last)
  {
    const long long offset =
      channels * (static_cast<long long>(from - firstRow) * width - phase.ShiftU);
    std::copy(previous + (offset + channels * first), previous + (offset + channels * last),
      out + channels * first);
  }
  std::fill(out + channels * last, out + channels * width, 1.0f);
  // Every ray is attenuated over its step back to the previous slice.
  double p[3];
  p[s.Axis] = SliceCoordinate(s, k);
  p[s.B] = s.Origin[s.B] + (phase.FractionU - 1) * s.Spacing[s.B];
  p[s.C] = s.Origin[s.C] + (j - 1 + phase.FractionV) * s.Spacing[s.C];
  RowSegments(s, p, s.Spacing[s.B], width, sweep.Source.Travel, sweep.Step, out);
}

// Light of a directional source along row ic of slice t (out: 3 floats a pixel): the ray
// lattice of slice t - 1 (previous: its rows from firstRow on, those the row reads)
// interpolated where the point's ray crosses that slice, attenuated over the point's own
// last step (material just before a point shades it exactly, as in the reference).
void RowFromLattice(const SweepContext& s, const SweepSource& sweep, const LatticePhase& phase,
  const float* previous, int firstRow, int t, int k, int ic, float* out)
{
  const int nb = s.N[s.B];
  const int nc = s.N[s.C];
  const double* d = sweep.Source.Travel;
  const int channels = s.Channels;
  std::fill(out, out + channels * nb, 1.0f);
  if (t == 0)
  {
    return;
  }
  // The pixels [first, last] of the row whose ray crossed the previous slice inside it;
  // the others entered through a side face after it.
  const double v = ic - sweep.OffsetV;
  int first = 0, last = nb - 1;
  if (v < 0.0 || v > nc - 1)
  {
    first = nb;
  }
  while (first < nb && first - sweep.OffsetU < 0.0)
  {
    ++first;
  }
  while (last >= first && last - sweep.OffsetU > nb - 1)
  {
    --last;
  }
  // In the lattice of slice t - 1, ray (i, j) lies at (i - 1 + f, j - 1 + g) where
  // f + OffsetU = FractionU + ShiftU (and so for v): pixel ib at (ib + shiftU, V) with the
  // same fractions all along the row. Where all of a pixel's taps lie inside the lattice
  // ([inner, outer]) the row is interpolated at once.
  const double latticeU = 1 - phase.FractionU - phase.ShiftU;
  const double latticeV = ic + 1 - phase.FractionV - phase.ShiftV;
  SlicePoint at;
  int inner = last + 1, outer = last;
  if (first <= last && nb >= 3 && nc >= 3 &&
    Locate(first + latticeU, latticeV, nb + 1, nc + 1, at) && at.V >= 1 && at.V + 2 <= nc)
  {
    const int shiftU = at.U - first;
    inner = std::max(first, 1 - shiftU);
    outer = std::min(last, nb - 2 - shiftU);
    if (inner <= outer)
    {
      if (channels == 1)
      {
        MonotoneBicubicRow<1>(
          previous, nb + 1, shiftU, at.V - firstRow, at.FU, at.FV, inner, outer, out);
      }
      else
      {
        MonotoneBicubicRow<3>(
          previous, nb + 1, shiftU, at.V - firstRow, at.FU, at.FV, inner, outer, out);
      }
    }
  }
  for (int ib = first; ib <= last; ++ib)
  {
    if (ib < inner || ib > outer)
    {
      Locate(ib + latticeU, latticeV, nb + 1, nc + 1, at);
      MonotoneBicubic(previous, channels, nb + 1, nc + 1, at, out + channels * ib, firstRow);
    }
  }
  // Each point's own last step: material just before it shades it exactly.
  double p[3];
  p[s.Axis] = SliceCoordinate(s, k);
  p[s.B] = s.Origin[s.B];
  p[s.C] = s.Origin[s.C] + ic * s.Spacing[s.C];
  RowSegments(s, p, s.Spacing[s.B], nb, d, sweep.Step, out);
}

// A group's sweep axis, direction, and the axes its rows run along (B) and are ordered
// along (C, SweepRowAxis). Rows run along x (B = x) in sweeps along y and z, so that their
// volume reads and deposits are contiguous; sweeps along x run their rows along y.
struct SweepAxes
{
  int Axis, Sign, B, C;
  explicit SweepAxes(int group)
    : Axis(group / 2)
    , Sign(group % 2 == 0 ? 1 : -1)
    , B(group / 2 == 0 ? 1 : 0)
    , C(group / 2 == 2 ? 1 : 2)
  {
  }
};

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

// The geometry of a sweep of the grid g in a group (SweepAxes), and whether row kernels
// apply.
SweepContext MakeSweepContext(const ClassifiedVolume& volume, const EmptyBlocks* empty,
  bool rowKernels, const GridGeometry& g, int group)
{
  const auto& sp = volume.Geometry.Spacing;
  const SweepAxes axes(group);
  SweepContext s{ volume, empty, std::min(sp[0], std::min(sp[1], sp[2])), axes.Axis, axes.Sign,
    axes.B, axes.C, { g.Dimensions[0], g.Dimensions[1], g.Dimensions[2] },
    { 1, g.Dimensions[0], static_cast<long long>(g.Dimensions[0]) * g.Dimensions[1] },
    { g.Origin[0], g.Origin[1], g.Origin[2] }, { g.Spacing[0], g.Spacing[1], g.Spacing[2] }, {},
    { 1, g.Dimensions[0], static_cast<long long>(g.Dimensions[0]) * g.Dimensions[1] }, { 0, 0, 0 },
    false, volume.IsChromatic() ? 3 : 1 };
  g.GetBounds(s.Bounds);
  // Row kernels take a ray inside the volume's grid to be inside the box: along the rows
  // the two must coincide; across them the volume may be a band of the box (SweepBand).
  double volumeBounds[6];
  volume.Geometry.GetBounds(volumeBounds);
  s.RowKernels = rowKernels;
  for (int a = 0; a < 3; ++a)
  {
    const double tolerance = FaceTolerance(s.Bounds, a);
    const double low = volumeBounds[2 * a] - s.Bounds[2 * a];
    const double high = s.Bounds[2 * a + 1] - volumeBounds[2 * a + 1];
    s.RowKernels = s.RowKernels &&
      (a != s.B ? low >= -tolerance && high >= -tolerance
                : std::abs(low) <= tolerance && std::abs(high) <= tolerance);
  }
  return s;
}

// The distinct ray sources of the tasks (prepared for the sweep) and each task's deposit,
// its radiance in fixed-point units.
void PrepareDeposits(const SweepContext& s, const std::vector<PropagationTask>& tasks, double scale,
  std::vector<SweepSource>& prepared, std::vector<Deposit>& deposits)
{
  std::vector<RaySource> sources;
  for (const auto& task : tasks)
  {
    const RaySource source = SourceOf(task);
    auto found = std::find(sources.begin(), sources.end(), source);
    Deposit deposit;
    deposit.Source = static_cast<size_t>(found - sources.begin());
    deposit.Recorded = task.Recorded;
    deposit.Uniform = source.Directional;
    if (found == sources.end())
    {
      sources.push_back(source);
      prepared.emplace_back(source, s);
    }
    const LightState& l = task.Light;
    deposit.Spot = l.Kind == LightKind::Spot;
    if (task.OtherGroup >= 0 && task.Weight > 0.0)
    {
      deposit.OtherAxis = task.OtherGroup / 2;
      deposit.OtherSign = task.OtherGroup % 2 == 0 ? 1 : -1;
      deposit.Whole = (task.Weight + task.OtherWeight) / task.Weight;
    }
    const auto axis = l.Direction();
    std::copy(axis.begin(), axis.end(), deposit.Axis);
    deposit.CosCone = std::cos(vtkMath::RadiansFromDegrees(l.ConeAngle));
    deposit.Exponent = l.Exponent;
    const auto r = l.Radiance();
    for (int ch = 0; ch < 3; ++ch)
    {
      deposit.Scaled[ch] = r[ch] * task.Weight * task.Sign * scale;
    }
    deposits.push_back(deposit);
  }
}

// The read and write slice buffers of each source of a sweep (s); returns the bytes of
// every buffer of the sweep, the threads' row buffers included.
size_t AllocateSliceBuffers(const SweepContext& s, std::vector<SweepSource>& prepared,
  int latticeRows, std::vector<std::vector<float>>& read, std::vector<std::vector<float>>& write)
{
  const int channels = s.Channels, nb = s.N[s.B], nc = s.N[s.C];
  const size_t count = prepared.size();
  // Slice buffers: a ray lattice (one ray more than points along each slice axis; the
  // latticeRows rows a band reads) for a directional source; the rays from the anchor and
  // those of the next anchor for a point or spot source (a band's: the rows of its cone).
  const size_t latticeValues = channels * static_cast<size_t>(nb + 1) * latticeRows;
  size_t bufferBytes = 0;
  for (SweepSource& sweep : prepared)
  {
    size_t size = sweep.FollowsRays() ? latticeValues : 0;
    if (!sweep.Source.Directional)
    {
      // The rays leaving an anchor, AnchorSpread times denser than its points.
      sweep.RaysB = static_cast<int>(std::ceil((nb - 1) * AnchorSpread)) + 1;
      sweep.RaysC = static_cast<int>(std::ceil((nc - 1) * AnchorSpread)) + 1;
      int first = 0, last = sweep.RaysC - 1;
      if (!sweep.ConeLow.empty())
      {
        // A wedge's: the rows of its cone at any anchor, which hold the taps of its reads
        // (ConeMargin).
        int low = sweep.RaysC - 1, high = -1;
        for (int k = 0; k < s.N[s.Axis]; ++k)
        {
          int f, l;
          ConeRows(s, sweep, k, f, l);
          if (f <= l)
          {
            low = std::min(low, f);
            high = std::max(high, l);
          }
        }
        first = low;
        last = std::max(high, low);
      }
      sweep.RayFirst = first;
      sweep.RayRows = last - first + 1;
      const size_t rays = static_cast<size_t>(sweep.RaysB) * sweep.RayRows;
      size = channels * rays;
      sweep.Norms.assign(rays, 0.0);
      sweep.RowAnchor.assign(sweep.RaysC, -1);
      bufferBytes += rays * sizeof(double) + sweep.RaysC * sizeof(int);
    }
    read.emplace_back(size, 1.0f);
    write.emplace_back(size, 1.0f);
    bufferBytes += 2 * size * sizeof(float);
  }
  // Each thread's row buffers: light per pixel and source, direction and group factor too
  // with a point or spot source (SweepSlices::NewScratch), and a deposit's factors per pixel.
  const bool directions = std::any_of(prepared.begin(), prepared.end(),
    [](const SweepSource& sweep) { return !sweep.Source.Directional; });
  bufferBytes += static_cast<size_t>(vtkSMPTools::GetEstimatedNumberOfThreads()) * nb *
    (count * (channels * sizeof(float) + (directions ? 4 * sizeof(double) : 0)) + sizeof(double));
  return bufferBytes;
}

// A point or spot deposit's factor at a pixel whose ray has direction d and group factor
// `group`: 0 where the other group of a pair carries the ray, the whole pair's weight where
// only this one can, and the spot's cone and falloff.
double DepositFactor(const SweepContext& s, const Deposit& deposit, const double* d, double group)
{
  double factor = group;
  if (deposit.OtherAxis >= 0)
  {
    // Two groups: where the other cannot carry the ray, this one (the sweep's) takes it all;
    // where this one cannot, the other does.
    if (s.Sign * d[s.Axis] <= MinimumAlong)
    {
      return 0.0;
    }
    if (deposit.OtherSign * d[deposit.OtherAxis] <= MinimumAlong)
    {
      factor *= deposit.Whole;
    }
  }
  if (deposit.Spot && factor != 0.0)
  {
    const double cosine = d[0] * deposit.Axis[0] + d[1] * deposit.Axis[1] + d[2] * deposit.Axis[2];
    factor *= cosine < deposit.CosCone ? 0.0 : std::pow(std::max(cosine, 0.0), deposit.Exponent);
  }
  return factor;
}

// Adds to units (3 a pixel) the units of scaled x factor x light for a row of nb pixels
// (light: Channels values a pixel; factors: one a pixel, or nullptr where every factor is
// 1), modulo 2^32 (see FixedPointIllumination).
template <int Channels>
void AddDepositUnits(
  const double scaled[3], const double* factors, const float* light, int nb, std::uint32_t* units)
{
  for (int ib = 0; ib < nb; ++ib)
  {
    for (int ch = 0; ch < 3; ++ch)
    {
      const double product = factors ? scaled[ch] * factors[ib] : scaled[ch];
      units[3 * ib + ch] += static_cast<std::uint32_t>(
        DepositUnits(product * light[Channels * ib + (Channels == 3 ? ch : 0)]));
    }
  }
}

// Adds the deposits of a row of nb pixels to its fixed-point units (values, 3 a pixel): per
// deposit and pixel, radiance x group factor x spot factor x light, rounded; the recorded
// deposits also to `recorded` (when given, same layout). factors: room for nb values.
void DepositRow(const SweepContext& s, const std::vector<Deposit>& deposits, const float* light,
  const double* direction, const double* groupFactor, int nb, std::uint32_t* values,
  std::uint32_t* recorded, double* factors)
{
  for (const Deposit& deposit : deposits)
  {
    const size_t j = deposit.Source;
    if (!deposit.Uniform)
    {
      for (int ib = 0; ib < nb; ++ib)
      {
        factors[ib] =
          DepositFactor(s, deposit, direction + 3 * (nb * j + ib), groupFactor[nb * j + ib]);
      }
    }
    const double* f = deposit.Uniform ? nullptr : factors;
    const float* t = light + s.Channels * nb * j;
    for (std::uint32_t* units : { values, deposit.Recorded ? recorded : nullptr })
    {
      if (units && s.Channels == 1)
      {
        AddDepositUnits<1>(deposit.Scaled, f, t, nb, units);
      }
      else if (units)
      {
        AddDepositUnits<3>(deposit.Scaled, f, t, nb, units);
      }
    }
  }
}

// The rows of a sweep one call runs: all, or a band's (SweepBand), whose units hold only its
// rows and whose ray lattices (its rows and the halo either side) get their neighbouring
// rows from `Exchange` after every slice.
struct SweepSpan
{
  bool Banded = false;
  SweepBand Band;
  LatticeExchange Exchange;
  // Or a wedge's (PropagateSweepWedge): per slice its own rows (WedgeRows), reading the
  // material it holds (WedgeMaterial).
  const SweepWedge* Wedge = nullptr;
  const WedgeVolume* WedgeMaterial = nullptr;
};

// The work of one sweep's slices, shared by the threads of the sweep. Slice t (index k
// along the axis) takes these steps: its rows (Row: a directional source's lattice row and
// the points' deposits, which read the previous slice's buffers only), each point or spot
// source's rays (Advance), and its end (End: buffer swaps and anchors, one thread).
struct SweepSlices
{
  const SweepContext& S;
  std::vector<SweepSource> Prepared;
  std::vector<Deposit> Deposits;
  std::vector<std::vector<float>> Read, Write;
  std::vector<size_t> Anchored; // the point and spot sources
  // The rows this sweep computes (all, or a band's): lattice and deposit rows FirstRow to
  // FirstRow + Rows - 1, of which the first DepositRows are the grid's (a lattice has a row
  // more than the grid). The lattices hold the rows from LatticeFirst on, those the sweep's
  // rows read (a band's and the halo the exchange fills either side).
  int FirstRow = 0, Rows = 0, DepositRows = 0, LatticeFirst = 0;
  // A wedge's rows per slice k (it has no lattices): SliceFirst[k] to SliceLast[k].
  std::vector<int> SliceFirst, SliceLast;
  int ChunkFirst = 0; // the first slice t of the chunk being swept
  std::uint32_t* Values = nullptr;
  std::uint32_t* Recorded = nullptr; // when a task is recorded
  // A sweep along x, whose rows run along y, deposits BufferSlices slices at a time into
  // slice-major buffers (the units of the chunk's slice t at slot t - ChunkFirst, its deposit
  // rows only) and then adds them to the illumination point by point along x (Flush): a
  // point's deposits of those slices then share cache lines instead of taking one line
  // each. 0: deposits go straight to the illumination. A band (chunks of one slice) buffers
  // one slice.
  int BufferSlices = 0;
  std::vector<std::uint32_t> Buffer, BufferRecorded;
  // A sweep along x with a directional source and without chromatic attenuation copies the
  // extinction its next slices reach into SlabValues (rows along y contiguous), so that the
  // lattice's row kernel reads the volume as it does in other sweeps (CopySlab).
  std::vector<PackedValue> SlabValues;

  // A thread's row buffers, per source: the light reaching each pixel, its direction and
  // group factor (point and spot sources only); and a deposit's factors (DepositRow).
  struct Scratch
  {
    std::vector<float> Light;
    std::vector<double> Direction, GroupFactor, Factors;
  };

  // The sweep (s) of the tasks of a group through the grid g, over the rows `span` gives.
  SweepSlices(const SweepContext& s, const GridGeometry& g, int group,
    const std::vector<PropagationTask>& tasks, FixedPointIllumination& illumination,
    PropagationStatistics& statistics, const SweepSpan& span)
    : S(s)
    , Values(illumination.Values.data())
  {
    PrepareDeposits(s, tasks, illumination.Scale, this->Prepared, this->Deposits);
    const int nc = s.N[s.C];
    const bool banded = span.Banded;
    const int firstRow = banded ? span.Band.First : 0;
    const int lastRow = banded ? span.Band.Last : nc - 1;
    int latticeLast = nc;
    if (banded)
    {
      // The lattice rows beyond its own that a band reads either side.
      const int halo = span.Band.Halo <= 0 ? LatticeHalo(g, tasks) : span.Band.Halo;
      this->LatticeFirst = std::max(0, firstRow - halo);
      latticeLast = std::min(nc, lastRow + halo); // (the last band's: up to the extra row nc)
    }
    if (span.Wedge)
    {
      WedgeRowsOf(g, SweepAxes(group), this->Prepared[0].Source.Position, *span.Wedge,
        this->SliceFirst, this->SliceLast);
      for (SweepSource& sweep : this->Prepared)
      {
        ConeOfWedge(
          g, SweepAxes(group), sweep.Source.Position, *span.Wedge, sweep.ConeLow, sweep.ConeHigh);
      }
    }
    size_t bytes = AllocateSliceBuffers(
      s, this->Prepared, latticeLast - this->LatticeFirst + 1, this->Read, this->Write);
    bool lattices = false;
    for (size_t j = 0; j < this->Prepared.size(); ++j)
    {
      lattices = lattices || this->Prepared[j].FollowsRays();
      if (!this->Prepared[j].Source.Directional)
      {
        this->Anchored.push_back(j);
      }
    }
    this->FirstRow = firstRow;
    this->DepositRows = lastRow - firstRow + 1;
    this->Rows = this->DepositRows + (lattices && lastRow == s.N[s.C] - 1 ? 1 : 0);
    if (illumination.Recorded.size() == illumination.Values.size() &&
      std::any_of(tasks.begin(), tasks.end(), [](const PropagationTask& t) { return t.Recorded; }))
    {
      this->Recorded = illumination.Recorded.data();
    }
    if (s.UnitStride[s.B] != 1)
    {
      this->BufferSlices = banded ? 1 : std::min(DepositSlices, s.N[s.Axis]);
      const size_t size =
        3 * static_cast<size_t>(this->BufferSlices) * s.N[s.B] * this->DepositRows;
      this->Buffer.assign(size, 0);
      if (this->Recorded)
      {
        this->BufferRecorded.assign(size, 0);
      }
      bytes += (this->Buffer.size() + this->BufferRecorded.size()) * sizeof(std::uint32_t);
    }
    const GridGeometry& v = s.Volume.Geometry;
    if (s.Axis == 0 && lattices && s.RowKernels && !s.Volume.IsChromatic())
    {
      // The points along x from the slice before a chunk to its last (BufferSlices
      // spacings), those of their cells' far corners and one more either side for rounding:
      // SlabFor leaves a chunk that needs more (rounding) to the volume.
      const double cells = this->BufferSlices * s.Spacing[0] / v.Spacing[0];
      const size_t points = std::min<size_t>(
        static_cast<size_t>(std::ceil(cells)) + 4, static_cast<size_t>(v.Dimensions[0]));
      this->SlabValues.resize(points * v.Dimensions[1] * v.Dimensions[2]);
      bytes += this->SlabValues.size() * sizeof(PackedValue);
    }
    statistics.PeakBufferBytes = std::max(statistics.PeakBufferBytes, bytes);
  }

  // The slab for slices [first, first + count) (see SweepContext::Slab): the points along x
  // from the one before the previous slice to the one after the last, when they fit.
  ExtinctionSlab SlabFor(int first, int count) const
  {
    const SweepContext& s = this->S;
    const GridGeometry& v = s.Volume.Geometry;
    ExtinctionSlab slab;
    if (this->SlabValues.empty())
    {
      return slab;
    }
    const int a = std::max(0, first - 1), b = first + count - 1;
    const double x0 = SliceCoordinate(s, this->Slice(a)), x1 = SliceCoordinate(s, this->Slice(b));
    const double low = (std::min(x0, x1) - v.Origin[0]) / v.Spacing[0];
    const double high = (std::max(x0, x1) - v.Origin[0]) / v.Spacing[0];
    slab.Low = std::max(0, static_cast<int>(std::floor(low)) - 1);
    slab.High = std::min(v.Dimensions[0] - 1, static_cast<int>(std::ceil(high)) + 1);
    const long long planes = static_cast<long long>(v.Dimensions[1]) * v.Dimensions[2];
    if ((slab.High - slab.Low + 1) * planes > static_cast<long long>(this->SlabValues.size()))
    {
      return ExtinctionSlab();
    }
    slab.Values = this->SlabValues.data();
    slab.Layout = FieldLayout(v, { planes, 1, v.Dimensions[1] });
    return slab;
  }

  // Copies row z (along y) of the volume's extinction into the slab s.Slab describes.
  void CopySlab(int z)
  {
    const SweepContext& s = this->S;
    const GridGeometry& v = s.Volume.Geometry;
    const ExtinctionSlab& slab = s.Slab;
    const long long nx = v.Dimensions[0], ny = v.Dimensions[1];
    const PackedValue* in = s.Volume.Properties.data() + nx * ny * z;
    PackedValue* out = this->SlabValues.data() + ny * z;
    for (long long y = 0; y < ny; ++y)
    {
      if (y + RowsAhead < ny)
      {
        Prefetch<0>(in + nx * (y + RowsAhead) + slab.Low);
        Prefetch<0>(in + nx * (y + RowsAhead) + slab.High);
      }
      for (int x = slab.Low; x <= slab.High; ++x)
      {
        out[(x - slab.Low) * slab.Layout.Stride[0] + y] = in[nx * y + x];
      }
    }
  }

  int StepsPerSlice() const { return static_cast<int>(this->Anchored.size()) + 2; }

  // The rows slice t computes: FirstRowAt(t) on, RowsAt(t) of them.
  int FirstRowAt(int t) const
  {
    return this->SliceFirst.empty() ? this->FirstRow : this->SliceFirst[this->Slice(t)];
  }
  int RowsAt(int t) const
  {
    const int k = this->Slice(t);
    return this->SliceFirst.empty() ? this->Rows : this->SliceLast[k] - this->SliceFirst[k] + 1;
  }

  int Slice(int t) const { return this->S.Sign > 0 ? t : this->S.N[this->S.Axis] - 1 - t; }

  // The units of point (0, 0, k) (3 a point).
  long long SliceStart(int k) const
  {
    return 3 * (k - this->S.UnitFirst[this->S.Axis]) * this->S.UnitStride[this->S.Axis];
  }

  // The units of the first point of row ic of slice k.
  long long RowStart(int k, int ic) const
  {
    const SweepContext& s = this->S;
    if (!s.UnitSliceBase.empty())
    {
      return 3 * (s.UnitSliceBase[k] + (ic - s.UnitSliceFirst[k]) * s.UnitStride[s.C]);
    }
    return this->SliceStart(k) + 3 * (ic - s.UnitFirst[s.C]) * s.UnitStride[s.C];
  }

  // Directions and group factors are kept only with a point or spot source (a directional
  // source's deposits are uniform along a row).
  Scratch NewScratch() const
  {
    const size_t pixels = static_cast<size_t>(this->S.N[this->S.B]) * this->Prepared.size();
    const size_t directions = this->Anchored.empty() ? 0 : pixels;
    return { std::vector<float>(this->S.Channels * pixels), std::vector<double>(3 * directions),
      std::vector<double>(directions, 1.0), std::vector<double>(this->S.N[this->S.B]) };
  }

  // Row ic of slice t: the lattice rows, then (ic inside the slice) the row's deposits.
  void Row(int t, int ic, Scratch& scratch)
  {
    const SweepContext& s = this->S;
    const int k = this->Slice(t);
    const int nb = s.N[s.B];
    for (size_t j = 0; j < this->Prepared.size(); ++j)
    {
      if (this->Prepared[j].FollowsRays())
      {
        LatticeRow(s, this->Prepared[j], LatticePhase(this->Prepared[j], t), this->Read[j].data(),
          this->LatticeFirst, t, k, ic,
          this->Write[j].data() +
            s.Channels * static_cast<size_t>(ic - this->LatticeFirst) * (nb + 1));
      }
    }
    if (ic == s.N[s.C])
    {
      return; // the lattices' extra row
    }
    for (size_t j = 0; j < this->Prepared.size(); ++j)
    {
      float* light = scratch.Light.data() + s.Channels * nb * j;
      double* direction =
        scratch.Direction.empty() ? nullptr : scratch.Direction.data() + 3 * nb * j;
      double* groupFactor =
        scratch.GroupFactor.empty() ? nullptr : scratch.GroupFactor.data() + nb * j;
      if (this->Prepared[j].FollowsRays())
      {
        RowFromLattice(s, this->Prepared[j], LatticePhase(this->Prepared[j], t),
          this->Read[j].data(), this->LatticeFirst, t, k, ic, light);
      }
      else
      {
        RowTransmittance(
          s, this->Prepared[j], this->Read[j].data(), k, ic, light, direction, groupFactor);
      }
    }
    // The row's units: contiguous in the illumination when rows run along x, else in the
    // deposit buffers.
    long long start = this->RowStart(k, ic);
    std::uint32_t* values = this->Values;
    std::uint32_t* recorded = this->Recorded;
    if (this->BufferSlices > 0)
    {
      const int slot = t - this->ChunkFirst;
      start = 3 * (static_cast<long long>(slot) * this->DepositRows + ic - this->FirstRow) * nb;
      values = this->Buffer.data();
      recorded = this->Recorded ? this->BufferRecorded.data() : nullptr;
    }
    DepositRow(s, this->Deposits, scratch.Light.data(), scratch.Direction.data(),
      scratch.GroupFactor.data(), nb, values + start, recorded ? recorded + start : nullptr,
      scratch.Factors.data());
  }

  // Adds the buffered units of row ic of slices [first, first + count) (the chunk) to the
  // illumination, and clears them.
  void Flush(int first, int count, int ic)
  {
    const SweepContext& s = this->S;
    const int nb = s.N[s.B];
    const size_t perSlice = 3 * static_cast<size_t>(nb) * this->DepositRows;
    auto add = [&](std::uint32_t* buffer, std::uint32_t* out)
    {
      for (int ib = 0; ib < nb; ++ib)
      {
        std::uint32_t* in = buffer + 3 * (static_cast<size_t>(ic - this->FirstRow) * nb + ib);
        const long long row =
          3 * (ib * s.UnitStride[s.B] + (ic - s.UnitFirst[s.C]) * s.UnitStride[s.C]);
        if (ib + RowsAhead < nb)
        {
          // The units of a pixel lie rows apart: ask for those of a later one meanwhile.
          const long long ahead = row + 3 * RowsAhead * s.UnitStride[s.B];
          Prefetch<1>(out + ahead + this->SliceStart(this->Slice(first)));
          Prefetch<1>(out + ahead + this->SliceStart(this->Slice(first + count - 1)));
        }
        for (int m = 0; m < count; ++m, in += perSlice)
        {
          std::uint32_t* o = out + row + this->SliceStart(this->Slice(first + m));
          for (int ch = 0; ch < 3; ++ch)
          {
            o[ch] += in[ch]; // modulo 2^32, as DepositRow
            in[ch] = 0;
          }
        }
      }
    };
    add(this->Buffer.data(), this->Values);
    if (this->Recorded)
    {
      add(this->BufferRecorded.data(), this->Recorded);
    }
  }

  // Rows [begin, end) of the rays of point or spot source j at slice t.
  void Advance(size_t j, int t, int begin, int end)
  {
    const int k = this->Slice(t);
    AdvanceAnchoredRays(this->S, this->Prepared[j], AnchoredStep(this->S, this->Prepared[j], k), k,
      begin, end, this->Read[j].data(), this->Write[j].data());
  }

  // After slice t: a directional source's lattice is the next slice's previous one; a
  // point or spot source anchored there now reads its rays from the slice.
  void End(int t)
  {
    for (size_t j = 0; j < this->Prepared.size(); ++j)
    {
      SweepSource& sweep = this->Prepared[j];
      const bool anchor =
        !sweep.Source.Directional && AnchoredStep(this->S, sweep, this->Slice(t)).Anchor;
      if (anchor)
      {
        sweep.Anchor = this->Slice(t);
      }
      if (anchor || sweep.FollowsRays())
      {
        std::swap(this->Read[j], this->Write[j]);
      }
    }
  }
};

// One sweep of the tasks (all in the same group) through the grid, or over the rows `span`
// gives: its slices' steps run by one team of threads per chunk of slices (ForSteps),
// progress reported between chunks from this thread.
bool Sweep(const ClassifiedVolume& volume, const EmptyBlocks* empty, bool rowKernels,
  const GridGeometry& g, int group, const std::vector<PropagationTask>& tasks,
  FixedPointIllumination& illumination, PropagationStatistics& statistics,
  const std::function<bool(double)>& progress, const SweepSpan& span = SweepSpan())
{
  // The slab (SweepContext::Slab) changes from chunk to chunk: the threads read it after the
  // step that copies it.
  SweepContext s = MakeSweepContext(volume, empty, rowKernels, g, group);
  const int na = s.N[s.Axis];
  if (span.Banded)
  {
    const int firstRow = span.Band.First, lastRow = span.Band.Last;
    const long long rows[3] = { s.C == 0 ? lastRow - firstRow + 1 : s.N[0],
      s.C == 1 ? lastRow - firstRow + 1 : s.N[1], 0 };
    s.UnitStride[1] = rows[0];
    s.UnitStride[2] = rows[0] * rows[1];
    s.UnitFirst[s.C] = firstRow;
  }
  if (span.Wedge)
  {
    // Per slice its rows, one after the other, each row's points in the grid's order.
    std::vector<int> first, last;
    WedgeRowsOf(g, SweepAxes(group), SourceOf(tasks[0]).Position, *span.Wedge, first, last);
    s.Wedge = span.WedgeMaterial;
    s.UnitStride[s.B] = 1;
    s.UnitStride[s.C] = s.N[s.B];
    s.UnitSliceFirst = first;
    s.UnitSliceBase.resize(first.size());
    long long base = 0;
    for (size_t k = 0; k < first.size(); ++k)
    {
      s.UnitSliceBase[k] = base;
      base += static_cast<long long>(s.N[s.B]) * (last[k] - first[k] + 1);
    }
  }
  SweepSlices slices(s, g, group, tasks, illumination, statistics, span);
  std::vector<float*> lattices; // a band's, for the exchange
  for (size_t j = 0; j < slices.Prepared.size(); ++j)
  {
    if (slices.Prepared[j].FollowsRays())
    {
      lattices.push_back(nullptr);
    }
  }
  const int perSlice = slices.StepsPerSlice();
  // A chunk of buffered slices ends with their flush, a step of a row each; one with a slab
  // starts by copying it, a step of a row along y each.
  // A band's lattices are completed by the exchange after every slice.
  const int chunk = span.Banded ? 1
    : slices.BufferSlices > 0   ? slices.BufferSlices
                                : std::max(1, na / 16);
  const int flush = slices.BufferSlices > 0 ? 1 : 0;
  for (int first = 0; first < na; first += chunk)
  {
    const int count = std::min(chunk, na - first);
    slices.ChunkFirst = first;
    s.Slab = slices.SlabFor(first, count);
    const int copy = s.Slab.Low <= s.Slab.High ? 1 : 0;
    ForSteps(
      copy + count * perSlice + flush,
      [&](int step) -> long long
      {
        if (step < copy)
        {
          return volume.Geometry.Dimensions[2];
        }
        step -= copy;
        if (step == count * perSlice)
        {
          return slices.DepositRows;
        }
        const int part = step % perSlice;
        return part == 0         ? slices.RowsAt(first + step / perSlice)
          : part == perSlice - 1 ? 1
                                 : slices.Prepared[slices.Anchored[part - 1]].RaysC;
      },
      [&]() -> StepWork
      {
        return [&, scratch = slices.NewScratch()](int step, long long begin, long long end) mutable
        {
          if (step < copy)
          {
            for (long long z = begin; z < end; ++z)
            {
              slices.CopySlab(static_cast<int>(z));
            }
            return;
          }
          step -= copy;
          const int t = first + step / perSlice;
          const int part = step % perSlice;
          if (step == count * perSlice)
          {
            for (long long ic = begin; ic < end; ++ic)
            {
              slices.Flush(first, count, slices.FirstRow + static_cast<int>(ic));
            }
          }
          else if (part == 0)
          {
            for (long long ic = begin; ic < end; ++ic)
            {
              slices.Row(t, slices.FirstRowAt(t) + static_cast<int>(ic), scratch);
            }
          }
          else if (part == perSlice - 1)
          {
            slices.End(t);
          }
          else
          {
            slices.Advance(
              slices.Anchored[part - 1], t, static_cast<int>(begin), static_cast<int>(end));
          }
        };
      });
    if (span.Banded && first + count < na)
    {
      for (size_t j = 0, m = 0; j < slices.Prepared.size(); ++j)
      {
        if (slices.Prepared[j].FollowsRays())
        {
          lattices[m++] = slices.Read[j].data();
        }
      }
      span.Exchange(lattices, s.Channels * static_cast<size_t>(s.N[s.B] + 1), slices.LatticeFirst);
    }
    if (progress && !progress(static_cast<double>(first + count) / na))
    {
      return false;
    }
  }
  return true;
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
  const double beta = (t1 - t3 > 0.0) ? std::atan2(t2 - t3, t1 - t3) : vtkMath::Pi() / 4.0;
  const double second = 2.0 * beta / vtkMath::Pi();
  groups.push_back({ GroupOf(order[0], t[order[0]]), 1.0 - second });
  if (second > 0.0)
  {
    groups.push_back({ GroupOf(order[1], t[order[1]]), second });
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

double FixedPointIllumination::ScaleFor(double bound)
{
  if (!(bound > 0.0) || !std::isfinite(bound))
  {
    return 1.0; // no light: any scale holds the zeros
  }
  int exponent;
  std::frexp(bound, &exponent); // bound < 2^exponent
  return std::ldexp(1.0, 28 - exponent);
}

bool FixedPointIllumination::Holds(double largest, double final) const
{
  const double units = largest * this->Scale;
  return std::isfinite(units) && units <= std::ldexp(1.0, 30) &&
    final * this->Scale >= std::ldexp(1.0, 20);
}

void FixedPointIllumination::ToFloat(
  const std::uint32_t* units, size_t count, double scale, float* rgb)
{
  const double unit = 1.0 / scale;
  vtkSMPTools::For(0, static_cast<long long>(count),
    [&](long long b, long long e)
    {
      for (long long i = b; i < e; ++i)
      {
        rgb[i] = static_cast<float>(static_cast<std::int32_t>(units[i]) * unit);
      }
    });
}

void FixedPointIllumination::SubtractRecord()
{
  std::uint32_t* v = this->Values.data();
  const std::uint32_t* r = this->Recorded.data();
  vtkSMPTools::For(0, static_cast<long long>(std::min(this->Values.size(), this->Recorded.size())),
    [&](long long b, long long e)
    {
      for (long long i = b; i < e; ++i)
      {
        v[i] -= r[i]; // modulo 2^32, as the record was added
      }
    });
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
