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

// One task as the sweep deposits it.
struct Deposit
{
  size_t Source;
  bool Spot;
  double Axis[3]; // spot cone axis
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

struct SweepContext
{
  const ClassifiedVolume& Grid;
  int Axis, Sign, B, C;
  int N[3];
  long long Stride[3];
  double Origin[3], Spacing[3];
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
    this->Enters = along <= 1e-6;
    if (!this->Enters)
    {
      this->Step = s.Spacing[s.Axis] / along;
      this->OffsetU = source.Travel[s.B] * this->Step / s.Spacing[s.B];
      this->OffsetV = source.Travel[s.C] * this->Step / s.Spacing[s.C];
    }
  }
};

// Transmittance of the ray from a source to point p of slice t (out), the unit direction the
// light travels there (d) and the factor an inside light's group gives the point.
void TransmittanceAtPoint(const SweepContext& s, const SweepSource& sweep, const float* readBuffer,
  int t, int k, int ib, int ic, const double p[3], const float* current, float out[3], double d[3],
  double& groupFactor)
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
        // short path from the light with this point's properties.
        const double alpha = StepOpacity(current[0], distance);
        for (int ch = 0; ch < 3; ++ch)
        {
          out[ch] = static_cast<float>(1.0 - alpha * current[1 + ch]);
        }
        return;
      }
    }
    const double along = s.Sign * d[a];
    if (t == 0 || along <= 1e-6)
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
    // The light entered the box through a side face after the previous slice.
    return;
  }
  float incoming[3];
  Bilinear<3>(readBuffer, nb > 1 ? 3 : 0, nc > 1 ? 3LL * nb : 0, at, incoming);
  float previous[4];
  const float* slice = s.Grid.Properties.data() + 4 * (k - s.Sign) * s.Stride[a];
  Bilinear<4>(slice, nb > 1 ? 4 * s.Stride[s.B] : 0, nc > 1 ? 4 * s.Stride[s.C] : 0, at, previous);
  const float alpha =
    1.0f - std::exp(-0.5f * (previous[0] + current[0]) * static_cast<float>(step));
  for (int ch = 0; ch < 3; ++ch)
  {
    out[ch] = incoming[ch] * (1.0f - alpha * 0.5f * (previous[1 + ch] + current[1 + ch]));
  }
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
      const long long index = k * s.Stride[s.Axis] + ib * s.Stride[s.B] + ic * s.Stride[s.C];
      TransmittanceAtPoint(s, sweep, readBuffer, t, k, ib, ic, p,
        s.Grid.Properties.data() + 4 * index, out + 3 * ib, direction + 3 * ib, groupFactor[ib]);
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
  const double v = ic - sweep.OffsetV;
  if (t == 0 || sweep.Enters || v < 0.0 || v > nc - 1)
  {
    // Light enters the box here (first slice, side face, or no progress along the axis).
    std::fill(out, out + 3 * nb, 1.0f);
    return;
  }
  SlicePoint at;
  at.V = std::min(static_cast<int>(v), std::max(nc - 2, 0));
  at.FV = nc > 1 ? static_cast<float>(v - at.V) : 0.0f;
  const long long strideU = nb > 1 ? 4 * s.Stride[s.B] : 0;
  const long long strideV = nc > 1 ? 4 * s.Stride[s.C] : 0;
  const long long bufferU = nb > 1 ? 3 : 0;
  const long long bufferV = nc > 1 ? 3LL * nb : 0;
  const float* previousSlice = s.Grid.Properties.data() + 4 * (k - s.Sign) * s.Stride[s.Axis];
  const float* currentSlice = s.Grid.Properties.data() + 4 * k * s.Stride[s.Axis];
  const float halfStep = 0.5f * static_cast<float>(sweep.Step);
  for (int ib = 0; ib < nb; ++ib)
  {
    const double u = ib - sweep.OffsetU;
    float* o = out + 3 * ib;
    if (u < 0.0 || u > nb - 1)
    {
      o[0] = o[1] = o[2] = 1.0f;
      continue;
    }
    at.U = std::min(static_cast<int>(u), std::max(nb - 2, 0));
    at.FU = nb > 1 ? static_cast<float>(u - at.U) : 0.0f;
    float incoming[3], previous[4];
    Bilinear<3>(readBuffer, bufferU, bufferV, at, incoming);
    Bilinear<4>(previousSlice, strideU, strideV, at, previous);
    const float* current = currentSlice + 4 * (ib * s.Stride[s.B] + ic * s.Stride[s.C]);
    const float alpha = 1.0f - std::exp(-halfStep * (previous[0] + current[0]));
    for (int ch = 0; ch < 3; ++ch)
    {
      o[ch] = incoming[ch] * (1.0f - alpha * 0.5f * (previous[1 + ch] + current[1 + ch]));
    }
  }
}

// One sweep of the tasks (all in the same group) through the grid.
bool Sweep(const ClassifiedVolume& grid, int group, const std::vector<PropagationTask>& tasks,
  FixedPointIllumination& illumination, PropagationStatistics& statistics,
  const std::function<bool(double)>& progress)
{
  const auto& g = grid.Geometry;
  SweepContext s{ grid, group / 2, group % 2 == 0 ? 1 : -1, (group / 2 + 1) % 3,
    (group / 2 + 2) % 3, { g.Dimensions[0], g.Dimensions[1], g.Dimensions[2] },
    { 1, g.Dimensions[0], static_cast<long long>(g.Dimensions[0]) * g.Dimensions[1] },
    { g.Origin[0], g.Origin[1], g.Origin[2] }, { g.Spacing[0], g.Spacing[1], g.Spacing[2] } };
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
              double factor = groupFactor[nb * j + ib];
              if (deposit.Spot && factor != 0.0)
              {
                const double* d = direction.data() + 3 * (nb * j + ib);
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
  for (const auto& gw : AssignPropagationGroups(light, bounds))
  {
    PropagationTask task;
    task.Light = light;
    task.Group = gw.Group;
    task.Weight = gw.Weight;
    task.Sign = sign;
    task.Inside = inside;
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

void ResampleClassification(
  const ClassifiedVolume& data, const GridGeometry& target, ClassifiedVolume& out)
{
  out.Geometry = target;
  if (target.Dimensions == data.Geometry.Dimensions)
  {
    out.Properties = data.Properties;
    return;
  }
  int sub[3];
  for (int a = 0; a < 3; ++a)
  {
    sub[a] =
      std::max(1, static_cast<int>(std::lround(target.Spacing[a] / data.Geometry.Spacing[a])));
  }
  const long long nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  out.Properties.assign(4 * static_cast<size_t>(target.NumberOfPoints()), 0.0f);
  vtkSMPTools::For(0, target.NumberOfPoints(),
    [&](long long begin, long long end)
    {
      for (long long id = begin; id < end; ++id)
      {
        double p[3];
        target.PointPosition(id % nx, (id / nx) % ny, id / (nx * ny), p);
        double sum[4] = { 0, 0, 0, 0 };
        for (int k = 0; k < sub[2]; ++k)
          for (int j = 0; j < sub[1]; ++j)
            for (int i = 0; i < sub[0]; ++i)
            {
              const double q[3] = { p[0] + ((i + 0.5) / sub[0] - 0.5) * target.Spacing[0],
                p[1] + ((j + 0.5) / sub[1] - 0.5) * target.Spacing[1],
                p[2] + ((k + 0.5) / sub[2] - 0.5) * target.Spacing[2] };
              float s[4];
              data.Sample(q, s);
              for (int c = 0; c < 4; ++c)
              {
                sum[c] += s[c];
              }
            }
        const double n = static_cast<double>(sub[0]) * sub[1] * sub[2];
        for (int c = 0; c < 4; ++c)
        {
          out.Properties[4 * id + c] = static_cast<float>(sum[c] / n);
        }
      }
    });
}

bool PropagateTasks(const ClassifiedVolume& grid, const std::vector<PropagationTask>& tasks,
  bool coherent, int maxSweeps, FixedPointIllumination& illumination,
  std::vector<PropagationTask>& remaining, PropagationStatistics& statistics,
  const ProgressCallback& progress)
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
    if (!Sweep(grid, sweeps[i][0].Group, sweeps[i], illumination, statistics, sweepProgress))
    {
      return false;
    }
    statistics.Sweeps += 1;
    statistics.LightSweeps += static_cast<long long>(sweeps[i].size());
  }
  return true;
}

}
