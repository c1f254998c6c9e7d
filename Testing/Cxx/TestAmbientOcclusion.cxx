// Tests of the ambient occlusion read from a summed-area table: a uniform medium and a dense
// half-space against their analytic transmittance, and blobs of material against the
// transmittance averaged over many marched rays (MarchedAmbientOcclusion).
#include "AmbientOcclusionKernel.h"

#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace volillum;

namespace
{
// A cube of n^3 points of spacing 1 at the origin whose extinction (channel 0) and
// absorption per colour (channels 1-3) are given per point.
template <typename Extinction>
ClassifiedVolume MakeVolume(int n, const Extinction& extinction, const double k[3])
{
  ClassifiedVolume v;
  v.Geometry.Dimensions = { { n, n, n } };
  std::vector<float> values(4 * static_cast<size_t>(v.Geometry.NumberOfPoints()));
  size_t i = 0;
  for (int z = 0; z < n; ++z)
  {
    for (int y = 0; y < n; ++y)
    {
      for (int x = 0; x < n; ++x, i += 4)
      {
        values[i] = static_cast<float>(extinction(x, y, z));
        for (int c = 0; c < 3; ++c)
        {
          values[i + 1 + c] = static_cast<float>(k[c]);
        }
      }
    }
  }
  v.Store(values);
  return v;
}
}

TEST(AmbientOcclusion, AUniformMediumGivesTheTransmittanceOfOneRadius)
{
  const double k[3] = { 1.0, 0.5, 0.25 };
  const ClassifiedVolume v = MakeVolume(
    40, [](int, int, int) { return 0.2; }, k);
  AmbientOcclusionTable table;
  table.Build(v, 3);
  const double p[3] = { 19.5, 20.0, 18.25 };
  for (double radius : { 0.5, 3.0, 7.5, 12.0 })
  {
    float t[3];
    table.Transmittance(p, radius, t);
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_NEAR(t[c], std::exp(-0.2 * k[c] * radius), 1e-3) << "radius " << radius;
    }
  }
}

TEST(AmbientOcclusion, ADenseHalfSpaceHidesHalfTheDirections)
{
  // Extinction 1e4 up to z = 20, nothing from z = 21 on.
  const double k[3] = { 1.0, 1.0, 1.0 };
  const ClassifiedVolume v = MakeVolume(
    41, [](int, int, int z) { return z <= 20 ? 1e4 : 0.0; }, k);
  AmbientOcclusionTable table;
  table.Build(v, 1);
  double marched[3];
  float t[3];
  // On the surface (where the interpolated extinction reaches 0) half the rays enter the
  // material at once; above it, fewer.
  const double surface[3] = { 20.0, 20.0, 21.0 };
  table.Transmittance(surface, 8.0, t);
  MarchedAmbientOcclusion(v, surface, 8.0, 1, 4096, marched);
  EXPECT_NEAR(t[0], 0.5, 0.01);
  EXPECT_NEAR(marched[0], 0.5, 0.01);
  // A point 4 above: rays of length 8 reach the material (whose interpolated extinction
  // falls to 0 at z = 21) within about 64 degrees of straight down, some 28 % of them. A
  // pyramid of the table that reaches into opaque material counts as wholly hidden (the
  // exponential of its mean optical depth): the pyramids below the point's horizon and the
  // lower halves of those beside it, half of them. So the table gives at most the marched
  // value (a pyramid's mean transmittance is at least the exponential of its mean optical
  // depth), and here the lower half of the directions, 0.5.
  const double above[3] = { 20.0, 20.0, 24.5 };
  table.Transmittance(above, 8.0, t);
  MarchedAmbientOcclusion(v, above, 8.0, 1, 4096, marched);
  std::printf("half-space 4 above: table %.4f marched %.4f\n", t[0], marched[0]);
  EXPECT_NEAR(marched[0], 0.72, 0.02);
  EXPECT_NEAR(t[0], 0.5, 0.01);
}

TEST(AmbientOcclusion, BlobsMatchTheAverageOverManyMarchedRays)
{
  // Random blobs of material, the densest with an optical depth of about 2 across.
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(7);
  std::vector<std::array<double, 5>> blobs(12); // centre, radius, extinction
  for (auto& b : blobs)
  {
    for (int a = 0; a < 3; ++a)
    {
      random->Next();
      b[a] = 8.0 + 32.0 * random->GetValue();
    }
    random->Next();
    b[3] = 3.0 + 5.0 * random->GetValue();
    random->Next();
    b[4] = 0.2 + 1.0 * random->GetValue();
  }
  auto extinction = [&](int x, int y, int z)
  {
    double s = 0.0;
    for (const auto& b : blobs)
    {
      const double r2 =
        ((x - b[0]) * (x - b[0]) + (y - b[1]) * (y - b[1]) + (z - b[2]) * (z - b[2])) /
        (b[3] * b[3]);
      s += r2 < 1.0 ? b[4] * (1.0 - r2) : 0.0;
    }
    return s;
  };
  const double k[3] = { 1.0, 0.6, 0.3 };
  const ClassifiedVolume v = MakeVolume(48, extinction, k);
  AmbientOcclusionTable table;
  table.Build(v, 3);
  for (double radius : { 4.0, 8.0 })
  {
    double squares = 0.0, mean = 0.0;
    int count = 0;
    for (int z = 1; z < 48; z += 3)
    {
      for (int y = 2; y < 48; y += 3)
      {
        for (int x = 0; x < 48; x += 3)
        {
          if (extinction(x, y, z) <= 0.0)
          {
            continue; // material only
          }
          const double p[3] = { double(x), double(y), double(z) };
          float t[3];
          double marched[3];
          table.Transmittance(p, radius, t);
          MarchedAmbientOcclusion(v, p, radius, 3, 512, marched);
          for (int c = 0; c < 3; ++c)
          {
            squares += (t[c] - marched[c]) * (t[c] - marched[c]);
            mean += marched[c];
          }
          count += 3;
        }
      }
    }
    const double rms = std::sqrt(squares / count) / (mean / count);
    std::printf("radius %g: %d values, material RMS %.4f of the mean %.4f\n", radius, count, rms,
      mean / count);
    EXPECT_GT(count, 300);
    EXPECT_LT(rms, 0.025) << "radius " << radius;
  }
}
