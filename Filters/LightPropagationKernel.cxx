#include "LightPropagationKernel.h"

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

// Rounds half away from zero, so that -x rounds to exactly minus what x rounds to: a light
// state removed later cancels to the last unit.
inline std::int64_t RoundToFixed(double x)
{
  // Light sums stay far below this (MaximumRadiance); the clamp only keeps a NaN or an
  // overflowing product from becoming an undefined conversion.
  constexpr double limit = 4.0e18;
  if (!(std::abs(x) < limit))
  {
    return std::isnan(x) ? 0 : static_cast<std::int64_t>(std::copysign(limit, x));
  }
  return static_cast<std::int64_t>(x >= 0.0 ? x + 0.5 : x - 0.5);
}

// Smallest progress along the sweep axis per unit of path a ray must make for a group to
// carry it.
constexpr double MinimumAlong = 1e-6;

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
template <int Channels>
inline void Bilinear(
  const float* base, long long strideU, long long strideV, const SlicePoint& at, float* out)
{
  const float* q = base + at.U * strideU + at.V * strideV;
  for (int ch = 0; ch < Channels; ++ch)
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

// Bicubic (Catmull-Rom) interpolation of a 3-channel slice buffer (nb x nc pixels) at `at`,
// limited to the range of the four surrounding pixels so that it adds no new extremes.
inline void MonotoneBicubic(const float* base, int nb, int nc, const SlicePoint& at, float* out)
{
  if (nb < 4 || nc < 4)
  {
    Bilinear<3>(base, nb > 1 ? 3 : 0, nc > 1 ? 3LL * nb : 0, at, out);
    return;
  }
  float wu[4], wv[4];
  CubicWeights(at.FU, wu);
  CubicWeights(at.FV, wv);
  int iu[4], iv[4];
  for (int m = 0; m < 4; ++m)
  {
    iu[m] = std::min(std::max(at.U - 1 + m, 0), nb - 1);
    iv[m] = std::min(std::max(at.V - 1 + m, 0), nc - 1);
  }
  for (int ch = 0; ch < 3; ++ch)
  {
    float sum = 0.0f;
    for (int mv = 0; mv < 4; ++mv)
    {
      const float* row = base + 3LL * nb * iv[mv] + ch;
      sum += wv[mv] *
        (wu[0] * row[3 * iu[0]] + wu[1] * row[3 * iu[1]] + wu[2] * row[3 * iu[2]] +
          wu[3] * row[3 * iu[3]]);
    }
    const float a = base[3LL * nb * iv[1] + 3 * iu[1] + ch];
    const float b = base[3LL * nb * iv[1] + 3 * iu[2] + ch];
    const float c = base[3LL * nb * iv[2] + 3 * iu[1] + ch];
    const float d = base[3LL * nb * iv[2] + 3 * iu[2] + ch];
    out[ch] = std::min(std::max(sum, std::min(std::min(a, b), std::min(c, d))),
      std::max(std::max(a, b), std::max(c, d)));
  }
}

// Trilinear samples of the four optical properties of a classified volume, positions
// clamped onto the grid (ClassifiedVolume::Sample inlined for the sweep's inner loop).
struct VolumeSampler
{
  const float* Properties;
  int Last[3];
  double Origin[3], Inverse[3];
  long long Stride[3];

  explicit VolumeSampler(const ClassifiedVolume& v)
    : Properties(v.Properties.data())
  {
    const auto& g = v.Geometry;
    for (int a = 0; a < 3; ++a)
    {
      this->Last[a] = g.Dimensions[a] - 1;
      this->Origin[a] = g.Origin[a];
      this->Inverse[a] = 1.0 / g.Spacing[a];
    }
    this->Stride[0] = g.Dimensions[0] > 1 ? 4 : 0;
    this->Stride[1] = g.Dimensions[1] > 1 ? 4LL * g.Dimensions[0] : 0;
    this->Stride[2] = g.Dimensions[2] > 1 ? 4LL * g.Dimensions[0] * g.Dimensions[1] : 0;
  }

  inline void operator()(const double p[3], float out[4]) const
  {
    long long offset = 0;
    float f[3];
    for (int a = 0; a < 3; ++a)
    {
      const double u = std::min(std::max((p[a] - this->Origin[a]) * this->Inverse[a], 0.0),
        static_cast<double>(this->Last[a]));
      const int i = std::min(static_cast<int>(u), std::max(this->Last[a] - 1, 0));
      f[a] = static_cast<float>(u - i);
      offset += i * this->Stride[a];
    }
    const float* q = this->Properties + offset;
    const long long dx = this->Stride[0], dy = this->Stride[1], dz = this->Stride[2];
    for (int c = 0; c < 4; ++c)
    {
      const float c00 = q[c] + f[0] * (q[dx + c] - q[c]);
      const float c10 = q[dy + c] + f[0] * (q[dy + dx + c] - q[dy + c]);
      const float c01 = q[dz + c] + f[0] * (q[dz + dx + c] - q[dz + c]);
      const float c11 = q[dz + dy + c] + f[0] * (q[dz + dy + dx + c] - q[dz + dy + c]);
      const float c0 = c00 + f[1] * (c10 - c00);
      const float c1 = c01 + f[1] * (c11 - c01);
      out[c] = c0 + f[2] * (c1 - c0);
    }
  }
};

// One sweep over the illumination grid (N, Stride, Origin, Spacing, Bounds) along Axis
// toward Sign; light is attenuated through the full-resolution volume the Sampler reads.
struct SweepContext
{
  VolumeSampler Sampler;
  double SegmentStep; // longest midpoint step: the volume's smallest spacing
  int Axis, Sign, B, C;
  int N[3];
  long long Stride[3];
  double Origin[3], Spacing[3];
  double Bounds[6];
};

// A ray source as one sweep uses it; for a directional light everything that does not
// depend on the point is worked out once.
struct SweepSource
{
  RaySource Source;
  bool Enters = false;  // directional: light does not progress along the axis
  double Step = 0.0;    // directional: path length between slices
  double OffsetU = 0.0; // directional: offset to the previous slice, in cells
  double OffsetV = 0.0;

  SweepSource(const RaySource& source, const SweepContext& s)
    : Source(source)
  {
    if (!source.Directional)
    {
      return;
    }
    const double along = s.Sign * source.Travel[s.Axis];
    this->Enters = along <= MinimumAlong;
    if (!this->Enters)
    {
      this->Step = s.Spacing[s.Axis] / along;
      this->OffsetU = source.Travel[s.B] * this->Step / s.Spacing[s.B];
      this->OffsetV = source.Travel[s.C] * this->Step / s.Spacing[s.C];
    }
  }
};

// Chromatic transmittance (multiplied into out) of the segment from p back along -d over
// `length`, integrated through the full-resolution classification with the midpoint rule and
// steps of at most its smallest spacing (read at full resolution, stored at the illumination
// grid's: thin material between two coarse slices still casts its shadow). Halving the step
// changes the material error of the fidelity tests by less than 0.1 %: the error left is the
// interpolation of the light between slices.
void SegmentTransmittance(
  const SweepContext& s, const double p[3], const double d[3], double length, float out[3])
{
  const int n = std::max(1, static_cast<int>(std::ceil(length / s.SegmentStep - 1e-9)));
  const double h = length / n;
  float props[4];
  for (int m = 0; m < n; ++m)
  {
    const double back = (m + 0.5) * h;
    const double q[3] = { p[0] - back * d[0], p[1] - back * d[1], p[2] - back * d[2] };
    s.Sampler(q, props);
    const float a = 1.0f - std::exp(-props[0] * static_cast<float>(h));
    for (int ch = 0; ch < 3; ++ch)
    {
      out[ch] *= 1.0f - a * props[1 + ch];
    }
  }
}

// Light that entered the box through a side face after the previous slice: out is the
// transmittance of the part of the step inside the box.
void EnteredThroughSide(
  const SweepContext& s, const double p[3], const double d[3], double step, float out[3])
{
  out[0] = out[1] = out[2] = 1.0f;
  const double back[3] = { -d[0], -d[1], -d[2] };
  const double inside = std::min(step, DistanceToBoxExit(p, back, s.Bounds));
  if (inside > 0.0)
  {
    SegmentTransmittance(s, p, d, inside, out);
  }
}

// Transmittance of the ray from a source to point p of slice t (out), the unit direction the
// light travels there (d) and the factor an inside light's group gives the point.
void TransmittanceAtPoint(const SweepContext& s, const SweepSource& sweep, const float* readBuffer,
  int t, int ib, int ic, const double p[3], float out[3], double d[3], double& groupFactor)
{
  const RaySource& source = sweep.Source;
  out[0] = out[1] = out[2] = 1.0f;
  groupFactor = 1.0;
  const int a = s.Axis;
  double step, u, v;
  if (source.Directional)
  {
    d[0] = source.Travel[0];
    d[1] = source.Travel[1];
    d[2] = source.Travel[2];
    if (t == 0 || sweep.Enters)
    {
      return;
    }
    step = sweep.Step;
    u = ib - sweep.OffsetU;
    v = ic - sweep.OffsetV;
  }
  else
  {
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
    if (source.Inside)
    {
      if (s.Sign * (p[a] - source.Position[a]) <= 0.0)
      {
        groupFactor = 0.0;
        return;
      }
      groupFactor = d[a] * d[a];
      if (s.Sign * (p[a] - s.Sign * s.Spacing[a] - source.Position[a]) <= 0.0)
      {
        // The light lies between the previous slice and this point: attenuate over the
        // short path from the light.
        SegmentTransmittance(s, p, d, distance, out);
        return;
      }
    }
    const double along = s.Sign * d[a];
    if (t == 0 || along <= MinimumAlong)
    {
      // Light enters the box at the first slice, or makes no progress along the axis.
      return;
    }
    step = s.Spacing[a] / along;
    u = ib - d[s.B] * step / s.Spacing[s.B];
    v = ic - d[s.C] * step / s.Spacing[s.C];
  }
  const int nb = s.N[s.B];
  const int nc = s.N[s.C];
  SlicePoint at;
  if (!Locate(u, v, nb, nc, at))
  {
    EnteredThroughSide(s, p, d, step, out);
    return;
  }
  MonotoneBicubic(readBuffer, nb, nc, at, out);
  SegmentTransmittance(s, p, d, step, out);
}

// Transmittance of one source along row ic of slice t into out (3 floats a pixel), with
// the direction and group factor at each pixel. A directional source has the same offset
// to the previous slice at every pixel, so its row is a fixed-weight stencil.
void RowTransmittance(const SweepContext& s, const SweepSource& sweep, const float* readBuffer,
  int t, int k, int ic, float* out, double* direction, double* groupFactor)
{
  const int nb = s.N[s.B];
  const int nc = s.N[s.C];
  const RaySource& source = sweep.Source;
  if (!source.Directional)
  {
    double p[3];
    p[s.Axis] = s.Origin[s.Axis] + k * s.Spacing[s.Axis];
    p[s.C] = s.Origin[s.C] + ic * s.Spacing[s.C];
    for (int ib = 0; ib < nb; ++ib)
    {
      p[s.B] = s.Origin[s.B] + ib * s.Spacing[s.B];
      TransmittanceAtPoint(
        s, sweep, readBuffer, t, ib, ic, p, out + 3 * ib, direction + 3 * ib, groupFactor[ib]);
    }
    return;
  }
  for (int ib = 0; ib < nb; ++ib)
  {
    direction[3 * ib] = source.Travel[0];
    direction[3 * ib + 1] = source.Travel[1];
    direction[3 * ib + 2] = source.Travel[2];
    groupFactor[ib] = 1.0;
  }
  if (t == 0 || sweep.Enters)
  {
    // Light enters the box here (first slice, or no progress along the axis).
    std::fill(out, out + 3 * nb, 1.0f);
    return;
  }
  const double v = ic - sweep.OffsetV;
  const bool rowInside = v >= 0.0 && v <= nc - 1;
  SlicePoint at;
  if (rowInside)
  {
    at.V = std::min(static_cast<int>(v), std::max(nc - 2, 0));
    at.FV = nc > 1 ? static_cast<float>(v - at.V) : 0.0f;
  }
  double p[3];
  p[s.Axis] = s.Origin[s.Axis] + k * s.Spacing[s.Axis];
  p[s.C] = s.Origin[s.C] + ic * s.Spacing[s.C];
  for (int ib = 0; ib < nb; ++ib)
  {
    const double u = ib - sweep.OffsetU;
    float* o = out + 3 * ib;
    p[s.B] = s.Origin[s.B] + ib * s.Spacing[s.B];
    if (!rowInside || u < 0.0 || u > nb - 1)
    {
      EnteredThroughSide(s, p, source.Travel, sweep.Step, o);
      continue;
    }
    at.U = std::min(static_cast<int>(u), std::max(nb - 2, 0));
    at.FU = nb > 1 ? static_cast<float>(u - at.U) : 0.0f;
    MonotoneBicubic(readBuffer, nb, nc, at, o);
    SegmentTransmittance(s, p, source.Travel, sweep.Step, o);
  }
}

// One sweep of the tasks (all in the same group) through the grid.
bool Sweep(const ClassifiedVolume& volume, const GridGeometry& g, int group,
  const std::vector<PropagationTask>& tasks, FixedPointIllumination& illumination,
  PropagationStatistics& statistics, const std::function<bool(double)>& progress)
{
  const auto& sp = volume.Geometry.Spacing;
  SweepContext s{ VolumeSampler(volume), std::min(sp[0], std::min(sp[1], sp[2])), group / 2,
    group % 2 == 0 ? 1 : -1, (group / 2 + 1) % 3, (group / 2 + 2) % 3,
    { g.Dimensions[0], g.Dimensions[1], g.Dimensions[2] },
    { 1, g.Dimensions[0], static_cast<long long>(g.Dimensions[0]) * g.Dimensions[1] },
    { g.Origin[0], g.Origin[1], g.Origin[2] }, { g.Spacing[0], g.Spacing[1], g.Spacing[2] }, {} };
  g.GetBounds(s.Bounds);
  const int na = s.N[s.Axis];
  const int nb = s.N[s.B];
  const int nc = s.N[s.C];
  const size_t sliceValues = 3 * static_cast<size_t>(nb) * nc;

  std::vector<RaySource> sources;
  std::vector<SweepSource> prepared;
  std::vector<Deposit> deposits;
  for (const auto& task : tasks)
  {
    const RaySource source = SourceOf(task);
    auto found = std::find(sources.begin(), sources.end(), source);
    Deposit deposit;
    deposit.Source = static_cast<size_t>(found - sources.begin());
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
      deposit.Scaled[ch] = r[ch] * task.Weight * task.Sign * FixedPointIllumination::Scale;
    }
    deposits.push_back(deposit);
  }
  const size_t count = sources.size();
  std::vector<std::vector<float>> read(count, std::vector<float>(sliceValues, 1.0f));
  std::vector<std::vector<float>> write(count, std::vector<float>(sliceValues, 1.0f));
  statistics.PeakBufferBytes =
    std::max(statistics.PeakBufferBytes, 2 * count * sliceValues * sizeof(float));
  std::int64_t* values = illumination.Values.data();
  const int progressEvery = std::max(1, na / 16);

  for (int t = 0; t < na; ++t)
  {
    const int k = s.Sign > 0 ? t : na - 1 - t;
    vtkSMPTools::For(0, nc,
      [&](int begin, int end)
      {
        // Per row and source: the light's direction and group factor at each pixel (only
        // point and spot sources vary along the row).
        std::vector<double> direction(3 * static_cast<size_t>(nb) * count);
        std::vector<double> groupFactor(static_cast<size_t>(nb) * count, 1.0);
        for (int ic = begin; ic < end; ++ic)
        {
          const size_t row = 3 * static_cast<size_t>(ic) * nb;
          for (size_t j = 0; j < count; ++j)
          {
            RowTransmittance(s, prepared[j], read[j].data(), t, k, ic, write[j].data() + row,
              direction.data() + 3 * nb * j, groupFactor.data() + nb * j);
          }
          for (int ib = 0; ib < nb; ++ib)
          {
            std::int64_t sum[3] = { 0, 0, 0 };
            for (const Deposit& deposit : deposits)
            {
              const size_t j = deposit.Source;
              const double* d = direction.data() + 3 * (nb * j + ib);
              double factor = groupFactor[nb * j + ib];
              if (deposit.OtherAxis >= 0)
              {
                // Two groups: where the other cannot carry the ray, this one (the sweep's)
                // takes it all; where this one cannot, the other does.
                if (s.Sign * d[s.Axis] <= MinimumAlong)
                {
                  continue;
                }
                if (deposit.OtherSign * d[deposit.OtherAxis] <= MinimumAlong)
                {
                  factor *= deposit.Whole;
                }
              }
              if (deposit.Spot && factor != 0.0)
              {
                const double cosine =
                  d[0] * deposit.Axis[0] + d[1] * deposit.Axis[1] + d[2] * deposit.Axis[2];
                factor *= cosine < deposit.CosCone
                  ? 0.0
                  : std::pow(std::max(cosine, 0.0), deposit.Exponent);
              }
              if (factor == 0.0)
              {
                continue;
              }
              const float* tj = write[j].data() + row + 3 * ib;
              for (int ch = 0; ch < 3; ++ch)
              {
                sum[ch] += RoundToFixed(deposit.Scaled[ch] * factor * tj[ch]);
              }
            }
            const long long index = k * s.Stride[s.Axis] + ib * s.Stride[s.B] + ic * s.Stride[s.C];
            for (int ch = 0; ch < 3; ++ch)
            {
              values[3 * index + ch] += sum[ch];
            }
          }
        }
      });
    std::swap(read, write);
    if ((t + 1) % progressEvery == 0 && progress && !progress(static_cast<double>(t + 1) / na))
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

void FixedPointIllumination::ToFloat(float* rgb) const
{
  const std::int64_t* v = this->Values.data();
  vtkSMPTools::For(0, static_cast<long long>(this->Values.size()),
    [&](long long b, long long e)
    {
      for (long long i = b; i < e; ++i)
      {
        rgb[i] = static_cast<float>(static_cast<double>(v[i]) / Scale);
      }
    });
}

bool PropagateTasks(const ClassifiedVolume& volume, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, bool coherent, int maxSweeps,
  FixedPointIllumination& illumination, std::vector<PropagationTask>& remaining,
  PropagationStatistics& statistics, const ProgressCallback& progress)
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
  for (size_t i = 0; i < sweeps.size(); ++i)
  {
    if (static_cast<int>(i) >= planned)
    {
      remaining.insert(remaining.end(), sweeps[i].begin(), sweeps[i].end());
      continue;
    }
    auto sweepProgress = [&](double f) { return !progress || progress((i + f) / planned); };
    if (!Sweep(
          volume, target, sweeps[i][0].Group, sweeps[i], illumination, statistics, sweepProgress))
    {
      return false;
    }
    statistics.Sweeps += 1;
    statistics.LightSweeps += static_cast<long long>(sweeps[i].size());
  }
  return true;
}

}
