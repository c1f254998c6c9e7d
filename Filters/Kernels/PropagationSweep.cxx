#include "PropagationSweep.h"

#include "ParallelSteps.h"
#include "SliceInterpolation.h"

#include <algorithm>
#include <cmath>

namespace volillum
{
namespace propagation
{
namespace
{
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

// A point or spot deposit's factor at a pixel whose ray has direction d and group factor
// `group`: 0 where the other group of a pair carries the ray, the whole pair's weight where
// only this one can (neither happens where both carry every point: Carried), and the spot's
// cone and falloff.
double DepositFactor(const SweepContext& s, const Deposit& deposit, const double* d, double group)
{
  double factor = group;
  if (deposit.OtherAxis >= 0 && !deposit.Carried)
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
    // (pow(x, 1) is x: the default exponent skips the power, a fifth of a spot light's cost)
    const double falloff = deposit.Exponent == 1.0
      ? std::max(cosine, 0.0)
      : std::pow(std::max(cosine, 0.0), deposit.Exponent);
    factor *= cosine < deposit.CosCone ? 0.0 : falloff;
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

  // A chunk of slices [First, First + Count) as one team of threads runs it (ForSteps): the
  // copy of its slab when it has one (Copy steps, 0 or 1), StepsPerSlice steps a slice, and
  // the flush of its buffered slices when they are buffered (one step).
  struct Chunk
  {
    int First, Count, Copy;
  };

  // The items of step `step` of a chunk: the slab's rows along y, a slice's rows, a point or
  // spot source's rows of rays, one for a slice's end, the deposit rows for the flush.
  long long ChunkStepItems(const Chunk& chunk, int step) const
  {
    const int perSlice = this->StepsPerSlice();
    if (step < chunk.Copy)
    {
      return this->S.Volume.Geometry.Dimensions[2];
    }
    step -= chunk.Copy;
    if (step == chunk.Count * perSlice)
    {
      return this->DepositRows;
    }
    const int part = step % perSlice;
    return part == 0         ? this->RowsAt(chunk.First + step / perSlice)
      : part == perSlice - 1 ? 1
                             : this->Prepared[this->Anchored[part - 1]].RaysC;
  }

  // Items [begin, end) of step `step` of a chunk, with a thread's row buffers.
  void RunChunkStep(const Chunk& chunk, int step, long long begin, long long end, Scratch& scratch)
  {
    if (step < chunk.Copy)
    {
      for (long long z = begin; z < end; ++z)
      {
        this->CopySlab(static_cast<int>(z));
      }
      return;
    }
    step -= chunk.Copy;
    const int perSlice = this->StepsPerSlice();
    const int t = chunk.First + step / perSlice;
    const int part = step % perSlice;
    if (step == chunk.Count * perSlice)
    {
      for (long long ic = begin; ic < end; ++ic)
      {
        this->Flush(chunk.First, chunk.Count, this->FirstRow + static_cast<int>(ic));
      }
    }
    else if (part == 0)
    {
      for (long long ic = begin; ic < end; ++ic)
      {
        this->Row(t, this->FirstRowAt(t) + static_cast<int>(ic), scratch);
      }
    }
    else if (part == perSlice - 1)
    {
      this->End(t);
    }
    else
    {
      this->Advance(this->Anchored[part - 1], t, static_cast<int>(begin), static_cast<int>(end));
    }
  }

  // After a slice of a band's sweep: its ray lattices' rows beyond the band's own, from the
  // bands that compute them (SweepSpan::Exchange).
  void ExchangeLattices(const LatticeExchange& exchange)
  {
    std::vector<float*> lattices;
    for (size_t j = 0; j < this->Prepared.size(); ++j)
    {
      if (this->Prepared[j].FollowsRays())
      {
        lattices.push_back(this->Read[j].data());
      }
    }
    exchange(lattices, this->S.Channels * static_cast<size_t>(this->S.N[this->S.B] + 1),
      this->LatticeFirst);
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
}

// One sweep of the tasks (all in the same group) through the grid, or over the rows `span`
// gives: its slices' steps run by one team of threads per chunk of slices (ForSteps),
// progress reported between chunks from this thread.
bool Sweep(const ClassifiedVolume& volume, const EmptyBlocks* empty, bool rowKernels,
  const GridGeometry& g, int group, const std::vector<PropagationTask>& tasks,
  FixedPointIllumination& illumination, PropagationStatistics& statistics,
  const std::function<bool(double)>& progress, const SweepSpan& span)
{
  // The slab (SweepContext::Slab) changes from chunk to chunk: the threads read it after the
  // step that copies it.
  SweepContext s = MakeSweepContext(volume, empty, rowKernels, g, group);
  const int na = s.N[s.Axis];
  if (span.Banded)
  {
    SetBandUnits(span.Band, s);
  }
  if (span.Wedge)
  {
    SetWedgeUnits(g, group, tasks, span, s);
  }
  SweepSlices slices(s, g, group, tasks, illumination, statistics, span);
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
    const SweepSlices::Chunk c{ first, count, s.Slab.Low <= s.Slab.High ? 1 : 0 };
    ForSteps(
      c.Copy + count * slices.StepsPerSlice() + flush,
      [&](int step) -> long long { return slices.ChunkStepItems(c, step); },
      [&]() -> StepWork
      {
        return [&, scratch = slices.NewScratch()](int step, long long begin, long long end) mutable
        { slices.RunChunkStep(c, step, begin, end, scratch); };
      });
    if (span.Banded && first + count < na)
    {
      slices.ExchangeLattices(span.Exchange);
    }
    if (progress && !progress(static_cast<double>(first + count) / na))
    {
      return false;
    }
  }
  return true;
}
}
}
