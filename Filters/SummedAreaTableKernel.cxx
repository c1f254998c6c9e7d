#include "SummedAreaTableKernel.h"

#include "vtkMath.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

SatFrame FrameForDirection(const double direction[3])
{
  SatFrame f;
  double w[3] = { direction[0], direction[1], direction[2] };
  vtkMath::Normalize(w);
  // Start from the data axis least aligned with w and make it orthogonal.
  int least = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (std::abs(w[a]) < std::abs(w[least]))
    {
      least = a;
    }
  }
  // Prefer the data axis order so that a light along a data axis gets the data axes.
  double u[3] = { 0.0, 0.0, 0.0 };
  u[least] = 1.0;
  const double d = vtkMath::Dot(u, w);
  for (int a = 0; a < 3; ++a)
  {
    u[a] -= d * w[a];
  }
  vtkMath::Normalize(u);
  double v[3];
  vtkMath::Cross(w, u, v);
  for (int a = 0; a < 3; ++a)
  {
    f.Axes[0][a] = u[a];
    f.Axes[1][a] = v[a];
    f.Axes[2][a] = w[a];
  }
  return f;
}

std::vector<double> GaussianWeights(int count)
{
  std::vector<double> weights(count);
  double total = 0.0;
  for (int i = 0; i < count; ++i)
  {
    const double x = -1.0 + (i + 0.5) * 2.0 / count; // centre of sub-interval i
    weights[i] = std::exp(-0.5 * (x / 0.5) * (x / 0.5));
    total += weights[i];
  }
  for (auto& w : weights)
  {
    w /= total;
  }
  return weights;
}

int AxisOfDirection(const SatFrame& frame, const double direction[3], int& sign)
{
  for (int a = 0; a < 3; ++a)
  {
    const double c = vtkMath::Dot(frame.Axes[a].data(), direction);
    if (std::abs(std::abs(c) - 1.0) < 1e-9)
    {
      sign = c > 0.0 ? 1 : -1;
      return a;
    }
  }
  sign = 0;
  return -1;
}

void CartesianSAT::ToFrame(const double p[3], double q[3]) const
{
  for (int a = 0; a < 3; ++a)
  {
    q[a] = vtkMath::Dot(p, this->Frame.Axes[a].data()) - this->Origin[a];
  }
}

void CartesianSAT::Build(
  const ClassifiedVolume& data, const SatFrame& frame, double cellSize, int channels)
{
  this->Frame = frame;
  this->H = cellSize;
  this->Channels = channels;
  double bounds[6];
  data.Geometry.GetBounds(bounds);
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (int corner = 0; corner < 8; ++corner)
  {
    const double p[3] = { bounds[corner & 1], bounds[2 + ((corner >> 1) & 1)],
      bounds[4 + ((corner >> 2) & 1)] };
    for (int a = 0; a < 3; ++a)
    {
      const double c = vtkMath::Dot(p, frame.Axes[a].data());
      lo[a] = std::min(lo[a], c);
      hi[a] = std::max(hi[a], c);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    this->N[a] = std::max(1, static_cast<int>(std::ceil((hi[a] - lo[a]) / cellSize - 1e-9)));
    // Centre the cells on the rotated bounding box.
    this->Origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * this->N[a] * cellSize;
  }
  const long long nx = this->N[0], ny = this->N[1], nz = this->N[2];
  this->Table.assign(static_cast<size_t>((nx + 1) * (ny + 1) * (nz + 1) * channels), 0.0);

  // Cell integrals: extinction at the cell centre (zero outside the data) times volume.
  const double eps = 1e-9 * std::max(bounds[1] - bounds[0], 1.0);
  const double volume = cellSize * cellSize * cellSize;
  vtkSMPTools::For(0, nz,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
      {
        for (long long j = 0; j < ny; ++j)
        {
          for (long long i = 0; i < nx; ++i)
          {
            const double q[3] = { this->Origin[0] + (i + 0.5) * cellSize,
              this->Origin[1] + (j + 0.5) * cellSize, this->Origin[2] + (k + 0.5) * cellSize };
            double p[3];
            for (int a = 0; a < 3; ++a)
            {
              p[a] = q[0] * frame.Axes[0][a] + q[1] * frame.Axes[1][a] + q[2] * frame.Axes[2][a];
            }
            bool inside = true;
            for (int a = 0; a < 3; ++a)
            {
              inside = inside && p[a] >= bounds[2 * a] - eps && p[a] <= bounds[2 * a + 1] + eps;
            }
            if (!inside)
            {
              continue;
            }
            float s[4];
            data.Sample(p, s);
            for (int c = 0; c < channels; ++c)
            {
              const double absorb = channels == 3 ? s[1 + c] : 1.0;
              this->At(c, i + 1, j + 1, k + 1) = s[0] * absorb * volume;
            }
          }
        }
      }
    });

  // Running sums along x, then y, then z.
  vtkSMPTools::For(1, nz + 1,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
        for (long long j = 1; j <= ny; ++j)
          for (long long i = 2; i <= nx; ++i)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) += this->At(c, i - 1, j, k);
    });
  vtkSMPTools::For(1, nz + 1,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
        for (long long j = 2; j <= ny; ++j)
          for (long long i = 1; i <= nx; ++i)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) += this->At(c, i, j - 1, k);
    });
  vtkSMPTools::For(1, ny + 1,
    [&](long long j0, long long j1)
    {
      for (long long k = 2; k <= nz; ++k)
        for (long long j = j0; j < j1; ++j)
          for (long long i = 1; i <= nx; ++i)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) += this->At(c, i, j, k - 1);
    });
}

double CartesianSAT::Cumulative(int channel, double x, double y, double z) const
{
  // Continuous running integral up to (x, y, z) in cell units: trilinear interpolation of
  // the corner values, exact for a field that is constant in each cell.
  const double c[3] = { std::min(std::max(x, 0.0), static_cast<double>(this->N[0])),
    std::min(std::max(y, 0.0), static_cast<double>(this->N[1])),
    std::min(std::max(z, 0.0), static_cast<double>(this->N[2])) };
  long long i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    i0[a] = std::min(static_cast<long long>(c[a]), static_cast<long long>(this->N[a] - 1));
    f[a] = c[a] - i0[a];
  }
  double result = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
    const double w = (di ? f[0] : 1.0 - f[0]) * (dj ? f[1] : 1.0 - f[1]) * (dk ? f[2] : 1.0 - f[2]);
    if (w != 0.0)
    {
      result += w * this->At(channel, i0[0] + di, i0[1] + dj, i0[2] + dk);
    }
  }
  return result;
}

double CartesianSAT::BoxIntegral(int channel, const double lo[3], const double hi[3]) const
{
  const double a[3] = { lo[0] / this->H, lo[1] / this->H, lo[2] / this->H };
  const double b[3] = { hi[0] / this->H, hi[1] / this->H, hi[2] / this->H };
  return this->Cumulative(channel, b[0], b[1], b[2]) - this->Cumulative(channel, a[0], b[1], b[2]) -
    this->Cumulative(channel, b[0], a[1], b[2]) - this->Cumulative(channel, b[0], b[1], a[2]) +
    this->Cumulative(channel, a[0], a[1], b[2]) + this->Cumulative(channel, a[0], b[1], a[2]) +
    this->Cumulative(channel, b[0], a[1], a[2]) - this->Cumulative(channel, a[0], a[1], a[2]);
}

double CartesianSAT::FilteredOpticalDepth(
  int channel, const double p[3], int axis, int sign, double halfWidth) const
{
  double q[3];
  this->ToFrame(p, q);
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = q[a] - halfWidth;
    hi[a] = q[a] + halfWidth;
  }
  const double end = this->N[axis] * this->H;
  lo[axis] = sign > 0 ? q[axis] : 0.0;
  hi[axis] = sign > 0 ? end : q[axis];
  return this->BoxIntegral(channel, lo, hi) / (4.0 * halfWidth * halfWidth);
}

double CartesianSAT::KernelFilteredOpticalDepth(int channel, const double p[3], int axis, int sign,
  double halfWidth, const std::vector<double>& weights) const
{
  const int count = static_cast<int>(weights.size());
  double q[3];
  this->ToFrame(p, q);
  const int a1 = (axis + 1) % 3;
  const int a2 = (axis + 2) % 3;
  const double side = 2.0 * halfWidth / count;
  double lo[3], hi[3];
  lo[axis] = sign > 0 ? q[axis] : 0.0;
  hi[axis] = sign > 0 ? this->N[axis] * this->H : q[axis];
  double depth = 0.0;
  for (int i = 0; i < count; ++i)
  {
    lo[a1] = q[a1] - halfWidth + i * side;
    hi[a1] = lo[a1] + side;
    for (int j = 0; j < count; ++j)
    {
      lo[a2] = q[a2] - halfWidth + j * side;
      hi[a2] = lo[a2] + side;
      depth += weights[i] * weights[j] * this->BoxIntegral(channel, lo, hi) / (side * side);
    }
  }
  return depth;
}

double CartesianSAT::CellExtinction(int channel, int i, int j, int k) const
{
  const double lo[3] = { i * this->H, j * this->H, k * this->H };
  const double hi[3] = { lo[0] + this->H, lo[1] + this->H, lo[2] + this->H };
  return this->BoxIntegral(channel, lo, hi) / (this->H * this->H * this->H);
}

}
