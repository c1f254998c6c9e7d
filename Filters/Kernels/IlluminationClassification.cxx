#include "IlluminationClassification.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{

void GridGeometry::GetBounds(double bounds[6]) const
{
  for (int a = 0; a < 3; ++a)
  {
    const double lo = this->Origin[a];
    const double hi = this->Origin[a] + (this->Dimensions[a] - 1) * this->Spacing[a];
    bounds[2 * a] = std::min(lo, hi);
    bounds[2 * a + 1] = std::max(lo, hi);
  }
}

GridGeometry ScaledGeometry(const GridGeometry& data, double scale)
{
  GridGeometry g;
  g.Origin = data.Origin;
  for (int a = 0; a < 3; ++a)
  {
    const int n = data.Dimensions[a];
    if (n <= 1)
    {
      g.Dimensions[a] = n;
      g.Spacing[a] = data.Spacing[a];
      continue;
    }
    const int m = std::max(2, static_cast<int>(std::lround((n - 1) * scale)) + 1);
    g.Dimensions[a] = std::min(m, n);
    g.Spacing[a] = data.Spacing[a] * (n - 1) / (g.Dimensions[a] - 1);
  }
  return g;
}

void TrilinearSample(
  const GridGeometry& g, const float* field, int channels, const double p[3], float* out)
{
  const TrilinearCell cell = CellAtPosition(g, p);
  for (int c = 0; c < channels; ++c)
  {
    out[c] = Interpolate(g, field, channels, cell, c);
  }
}

void ClassifiedVolume::SetScales(const double largest[4])
{
  for (int c = 0; c < 4; ++c)
  {
    // largest = m 2^e with m in [1/2, 1): scaled by 2^-(64 + e) it lies below 2^-64, and
    // rounding its code up keeps it below 2^-63. The exponent is kept where the scale is a
    // normal float (larger values are clamped: MaximumSigma, k_c at most 1).
    int e = 0;
    const double value = c == 0 ? std::min(largest[c], MaximumSigma) : largest[c];
    if (value > 0.0 && std::isfinite(value))
    {
      std::frexp(value, &e);
    }
    this->Scale[c] = static_cast<float>(std::ldexp(1.0, 64 + std::min(std::max(e, -190), 62)));
  }
}

void ClassifiedVolume::Store(const std::vector<float>& values)
{
  double largest[4] = { 0.0, 0.0, 0.0, 0.0 };
  for (size_t i = 0; i < values.size(); ++i)
  {
    double& m = largest[i % this->Channels];
    m = std::max(m, static_cast<double>(values[i]));
  }
  this->SetScales(largest);
  this->Properties.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i)
  {
    const int c = static_cast<int>(i % this->Channels);
    const double v = values[i];
    this->Properties[i] = this->Pack(c, c == 0 ? std::min(v, MaximumSigma) : v);
  }
}

void ClassifiedVolume::Sample(const double p[3], float out[4]) const
{
  this->SampleCell(CellAtPosition(this->Geometry, p), out);
}

void ClassifiedVolume::SampleCell(const TrilinearCell& cell, float out[4]) const
{
  for (int c = 0; c < this->Channels; ++c)
  {
    out[c] = Interpolate(this->Geometry, this->Properties.data(), this->Channels, cell, c) *
      this->Scale[c];
  }
  if (this->Channels == 1)
  {
    out[1] = out[2] = out[3] = 1.0f;
  }
}

float ClassifiedVolume::MaxExtinction() const
{
  PackedValue m = 0; // codes grow with the values
  for (size_t i = 0; i < this->Properties.size(); i += static_cast<size_t>(this->Channels))
  {
    m = std::max(m, this->Properties[i]);
  }
  return Unpack(m) * this->Scale[0];
}

double DistanceToBoxExit(const double p[3], const double d[3], const double bounds[6])
{
  double tExit = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    if (d[a] > 0.0)
    {
      tExit = std::min(tExit, (bounds[2 * a + 1] - p[a]) / d[a]);
    }
    else if (d[a] < 0.0)
    {
      tExit = std::min(tExit, (bounds[2 * a] - p[a]) / d[a]);
    }
  }
  return std::max(tExit, 0.0);
}

}
