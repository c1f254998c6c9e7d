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

// Light of one task as the sweep needs it.
struct PreparedLight
{
  bool Directional;
  bool Spot;
  bool Inside;
  double Travel[3]; // directional lights: direction light travels
  double Position[3];
  double Axis[3]; // spot cone axis
  double CosCone;
  double Exponent;
  float Radiance[3];
  double SignedWeight;

  explicit PreparedLight(const PropagationTask& task)
  {
    const LightState& l = task.Light;
    this->Directional = l.Kind == LightKind::Directional;
    this->Spot = l.Kind == LightKind::Spot;
    this->Inside = task.Inside;
    const auto d = l.Direction();
    for (int a = 0; a < 3; ++a)
    {
      this->Travel[a] = d[a];
      this->Axis[a] = d[a];
      this->Position[a] = l.Position[a];
    }
    this->CosCone = std::cos(vtkMath::RadiansFromDegrees(l.ConeAngle));
    this->Exponent = l.Exponent;
    const auto r = l.Radiance();
    for (int c = 0; c < 3; ++c)
    {
      this->Radiance[c] = static_cast<float>(r[c]);
    }
    this->SignedWeight = task.Weight * task.Sign;
  }
};

// Bilinear interpolation of n interleaved channels of a slice (width nb) at (u, v), with
// u in [0, nb-1] and v in [0, nc-1]; strides in values.
template <int Channels>
void Bilinear(const float* base, long long strideU, long long strideV, int nb, int nc, double u,
  double v, float* out)
{
  int iu = std::min(static_cast<int>(u), nb - 2);
  int iv = std::min(static_cast<int>(v), nc - 2);
  iu = std::max(iu, 0);
  iv = std::max(iv, 0);
  const float fu = nb > 1 ? static_cast<float>(u - iu) : 0.0f;
  const float fv = nc > 1 ? static_cast<float>(v - iv) : 0.0f;
  const long long du = nb > 1 ? strideU : 0;
  const long long dv = nc > 1 ? strideV : 0;
  const float* q = base + iu * strideU + iv * strideV;
  for (int ch = 0; ch < Channels; ++ch)
  {
    const float a = q[ch] + fu * (q[du + ch] - q[ch]);
    const float b = q[dv + ch] + fu * (q[dv + du + ch] - q[dv + ch]);
    out[ch] = a + fv * (b - a);
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

// Light of one task arriving at point p of slice t (before any spot cone), and the factor
// (group weight of an inside light, spot cone) it is deposited with.
void LightAtPoint(const SweepContext& s, const PreparedLight& light, const float* readBuffer, int t,
  int k, int ib, int ic, const double p[3], const float* current, float out[3], double& pointWeight)
{
  out[0] = out[1] = out[2] = 0.0f;
  pointWeight = 1.0;
  double d[3];
  double distance = 0.0;
  if (light.Directional)
  {
    d[0] = light.Travel[0];
    d[1] = light.Travel[1];
    d[2] = light.Travel[2];
  }
  else
  {
    for (int a = 0; a < 3; ++a)
    {
      d[a] = p[a] - light.Position[a];
    }
    distance = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (distance < 1e-12)
    {
      // The point is the light: every group shares it.
      pointWeight = light.Inside ? 1.0 / NumberOfPropagationGroups : 1.0;
      std::copy(light.Radiance, light.Radiance + 3, out);
      return;
    }
    d[0] /= distance;
    d[1] /= distance;
    d[2] /= distance;
  }
  const int a = s.Axis;
  if (light.Inside)
  {
    if (s.Sign * (p[a] - light.Position[a]) <= 0.0)
    {
      pointWeight = 0.0;
      return;
    }
    pointWeight = d[a] * d[a];
  }
  if (light.Spot)
  {
    // The buffers carry the light as if there were no cone; the cone factor is constant
    // along a ray from the light, so it is applied where the light is deposited. This
    // keeps the cone's edge sharp.
    const double cosine = d[0] * light.Axis[0] + d[1] * light.Axis[1] + d[2] * light.Axis[2];
    pointWeight *= cosine < light.CosCone ? 0.0 : std::pow(std::max(cosine, 0.0), light.Exponent);
  }
  const float* entering = light.Radiance;
  const double along = s.Sign * d[a];
  const double step = s.Spacing[a] / std::max(along, 1e-300);
  if (light.Inside && s.Sign * (p[a] - s.Sign * s.Spacing[a] - light.Position[a]) <= 0.0)
  {
    // The light lies between the previous slice and this point: attenuate over the short
    // path from the light with this point's properties.
    const double alpha = StepOpacity(current[0], distance);
    for (int ch = 0; ch < 3; ++ch)
    {
      out[ch] = static_cast<float>(entering[ch] * (1.0 - alpha * current[1 + ch]));
    }
    return;
  }
  if (t == 0 || along <= 1e-6)
  {
    std::copy(entering, entering + 3, out);
    return;
  }
  const int nb = s.N[s.B];
  const int nc = s.N[s.C];
  const double u = ib - d[s.B] * step / s.Spacing[s.B];
  const double v = ic - d[s.C] * step / s.Spacing[s.C];
  if (u < 0.0 || v < 0.0 || u > nb - 1 || v > nc - 1)
  {
    // The light entered the box through a side face after the previous slice.
    std::copy(entering, entering + 3, out);
    return;
  }
  float incoming[3];
  Bilinear<3>(readBuffer, 3, 3LL * nb, nb, nc, u, v, incoming);
  float previous[4];
  const int kPrevious = k - s.Sign;
  const float* slice = s.Grid.Properties.data() + 4 * kPrevious * s.Stride[a];
  Bilinear<4>(slice, 4 * s.Stride[s.B], 4 * s.Stride[s.C], nb, nc, u, v, previous);
  const double alpha = StepOpacity(0.5 * (previous[0] + current[0]), step);
  for (int ch = 0; ch < 3; ++ch)
  {
    const double absorb = 0.5 * (previous[1 + ch] + current[1 + ch]);
    out[ch] = static_cast<float>(incoming[ch] * (1.0 - alpha * absorb));
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
  std::vector<PreparedLight> lights;
  for (const auto& task : tasks)
  {
    lights.emplace_back(task);
  }
  const size_t count = lights.size();
  std::vector<std::vector<float>> read(count, std::vector<float>(sliceValues, 0.0f));
  std::vector<std::vector<float>> write(count, std::vector<float>(sliceValues, 0.0f));
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
        double p[3];
        float light[3];
        for (int ic = begin; ic < end; ++ic)
        {
          for (int ib = 0; ib < nb; ++ib)
          {
            const long long index = k * s.Stride[s.Axis] + ib * s.Stride[s.B] + ic * s.Stride[s.C];
            p[s.Axis] = s.Origin[s.Axis] + k * s.Spacing[s.Axis];
            p[s.B] = s.Origin[s.B] + ib * s.Spacing[s.B];
            p[s.C] = s.Origin[s.C] + ic * s.Spacing[s.C];
            const float* current = grid.Properties.data() + 4 * index;
            const size_t pixel = 3 * (static_cast<size_t>(ic) * nb + ib);
            std::int64_t sum[3] = { 0, 0, 0 };
            for (size_t j = 0; j < count; ++j)
            {
              double pointWeight;
              LightAtPoint(
                s, lights[j], read[j].data(), t, k, ib, ic, p, current, light, pointWeight);
              std::copy(light, light + 3, write[j].data() + pixel);
              const double w = lights[j].SignedWeight * pointWeight * FixedPointIllumination::Scale;
              if (w != 0.0)
              {
                for (int ch = 0; ch < 3; ++ch)
                {
                  sum[ch] += std::llround(w * light[ch]);
                }
              }
            }
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
