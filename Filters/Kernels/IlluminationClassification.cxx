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

void ClassifiedVolume::Sample(const double p[3], float out[4]) const
{
  TrilinearSample(this->Geometry, this->Properties.data(), this->Channels, p, out);
  if (this->Channels == 1)
  {
    out[1] = out[2] = out[3] = 1.0f;
  }
}

float ClassifiedVolume::MaxExtinction() const
{
  float m = 0.0f;
  for (size_t i = 0; i < this->Properties.size(); i += static_cast<size_t>(this->Channels))
  {
    m = std::max(m, this->Properties[i]);
  }
  return m;
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
