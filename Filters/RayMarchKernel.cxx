#include "RayMarchKernel.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

std::array<double, 3> RayMarchTransmittance(const ClassifiedVolume& volume, const LightState& light,
  const double p[3], const RayMarchSettings& settings)
{
  const Incidence inc = ComputeIncidence(light, p);
  std::array<double, 3> t{ { inc.ConeFactor, inc.ConeFactor, inc.ConeFactor } };
  if (inc.ConeFactor == 0.0)
  {
    return t;
  }
  double bounds[6];
  volume.Geometry.GetBounds(bounds);
  const double tMax = std::min(inc.Distance, DistanceToBoxExit(p, inc.ToLight.data(), bounds));
  const auto& sp = volume.Geometry.Spacing;
  const double step =
    settings.StepFraction * std::min(std::abs(sp[0]), std::min(std::abs(sp[1]), std::abs(sp[2])));
  const long long n = std::max(1LL, static_cast<long long>(std::ceil(tMax / step)));
  const double h = tMax / n;
  float s[4];
  for (long long i = 0; i < n; ++i)
  {
    const double d = (i + 0.5) * h;
    const double q[3] = { p[0] + d * inc.ToLight[0], p[1] + d * inc.ToLight[1],
      p[2] + d * inc.ToLight[2] };
    volume.Sample(q, s);
    const double a = StepOpacity(s[0], h);
    t[0] *= 1.0 - a * s[1];
    t[1] *= 1.0 - a * s[2];
    t[2] *= 1.0 - a * s[3];
    if (std::max(t[0], std::max(t[1], t[2])) < settings.MinimumTransmittance)
    {
      break;
    }
  }
  return t;
}

bool RayMarchIllumination(const ClassifiedVolume& volume, const std::vector<LightState>& lights,
  const GridGeometry& target, const RayMarchSettings& settings, float* rgb,
  const ProgressCallback& progress)
{
  std::vector<LightState> active;
  for (const auto& l : lights)
  {
    if (l.On)
    {
      active.push_back(l);
    }
  }
  const long long nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  const long long nz = target.Dimensions[2];
  std::fill(rgb, rgb + 3 * nx * ny * nz, 0.0f);
  if (active.empty())
  {
    return true;
  }
  // Slices are done in chunks so that progress is reported from this thread.
  const long long chunk = std::max(1LL, nz / 20);
  for (long long k0 = 0; k0 < nz; k0 += chunk)
  {
    const long long k1 = std::min(nz, k0 + chunk);
    vtkSMPTools::For(k0 * ny, k1 * ny,
      [&](long long begin, long long end)
      {
        for (long long row = begin; row < end; ++row)
        {
          const long long j = row % ny;
          const long long k = row / ny;
          for (long long i = 0; i < nx; ++i)
          {
            double p[3];
            target.PointPosition(i, j, k, p);
            double sum[3] = { 0.0, 0.0, 0.0 };
            for (const auto& light : active)
            {
              const auto t = RayMarchTransmittance(volume, light, p, settings);
              const auto r = light.Radiance();
              for (int c = 0; c < 3; ++c)
              {
                sum[c] += r[c] * t[c];
              }
            }
            float* o = rgb + 3 * (i + nx * row);
            o[0] = static_cast<float>(sum[0]);
            o[1] = static_cast<float>(sum[1]);
            o[2] = static_cast<float>(sum[2]);
          }
        }
      });
    if (progress && !progress(static_cast<double>(k1) / nz))
    {
      return false;
    }
  }
  return true;
}

}
