#include "DistributedRayMarch.h"

#include "ParallelCollectives.h"
#include "vtkCommunicator.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>

namespace volillum
{

namespace
{
// This process's parts of the rays of `count` rows from row `first` of extent e: per point and
// light on, the transmittance along the part of its ray in this process's block (1 where the
// light does not reach the point).
void MarchRayParts(const ClassifiedVolume& volume, const VolumePiece& piece,
  const std::vector<LightState>& lights, const std::vector<size_t>& on, const GridGeometry& target,
  const RayMarchSettings& settings, const EmptyBlocks* empty, const int* e, size_t first,
  size_t count, double* parts)
{
  const int components = 3 * static_cast<int>(on.size());
  const long long width = e[1] - e[0] + 1, rowsY = e[3] - e[2] + 1;
  std::fill(parts, parts + count * width * components, 1.0);
  if (volume.Geometry.NumberOfPoints() == 0)
  {
    return;
  }
  // Threads share the block's points (a block may hold few rows).
  vtkSMPTools::For(0, static_cast<long long>(count) * width,
    [&](long long begin, long long end)
    {
      for (long long n = begin; n < end; ++n)
      {
        const long long row = static_cast<long long>(first) + n / width;
        double p[3];
        target.PointPosition(e[0] + n % width, e[2] + row % rowsY, e[4] + row / rowsY, p);
        for (size_t m = 0; m < on.size(); ++m)
        {
          const Incidence incidence = ComputeIncidence(lights[on[m]], p);
          if (incidence.ConeFactor > 0.0)
          {
            const auto t = PartialTransmittance(volume, piece, incidence, p, settings,
              settings.MinimumTransmittance / incidence.ConeFactor, empty);
            std::copy(t.begin(), t.end(), parts + components * n + 3 * m);
          }
        }
      }
    });
}

// The illumination of `count` rows from row `first` of this process's extent e from the
// products of the rays' parts over all processes.
void LightFromProducts(const std::vector<LightState>& lights, const std::vector<size_t>& on,
  const GridGeometry& target, const RayMarchSettings& settings, const int* e, size_t first,
  size_t count, const double* products, float* rgb)
{
  const int components = 3 * static_cast<int>(on.size());
  const long long width = e[1] - e[0] + 1, rowsY = e[3] - e[2] + 1;
  for (size_t r = 0; r < count; ++r)
  {
    const long long row = static_cast<long long>(first + r);
    for (long long i = 0; i < width; ++i)
    {
      double p[3];
      target.PointPosition(e[0] + i, e[2] + row % rowsY, e[4] + row / rowsY, p);
      const double* product = products + components * (r * width + i);
      std::array<double, 3> sum{ { 0.0, 0.0, 0.0 } };
      for (size_t m = 0; m < on.size(); ++m)
      {
        const LightState& light = lights[on[m]];
        const auto t = DarkenedTransmittance(ComputeIncidence(light, p).ConeFactor,
          { { product[3 * m], product[3 * m + 1], product[3 * m + 2] } }, settings);
        const auto radiance = light.Radiance();
        for (int c = 0; c < 3; ++c)
        {
          sum[c] += radiance[c] * t[c];
        }
      }
      float* o = rgb + 3 * (row * width + i);
      for (int c = 0; c < 3; ++c)
      {
        o[c] = static_cast<float>(sum[c]);
      }
    }
  }
}
}

//------------------------------------------------------------------------------
void RayMarchDistributed(vtkMultiProcessController* controller, const ClassifiedVolume& volume,
  const VolumePiece& piece, const std::vector<LightState>& lights, const std::vector<size_t>& on,
  const GridGeometry& target, const std::vector<int>& extents, const RayMarchSettings& settings,
  const EmptyBlocks* empty, float* rgb, const std::function<void(double)>& progress)
{
  ReduceOverPieces(
    controller, extents, 3 * static_cast<int>(on.size()), vtkCommunicator::PRODUCT_OP,
    [&](const int* e, size_t first, size_t count, double* parts)
    { MarchRayParts(volume, piece, lights, on, target, settings, empty, e, first, count, parts); },
    [&](const int* e, size_t first, size_t count, const double* products)
    { LightFromProducts(lights, on, target, settings, e, first, count, products, rgb); },
    progress);
}

}
