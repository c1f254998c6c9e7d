#include "SummedAreaTableKernel.h"

#include "RayMarchKernel.h"

#include "vtkMath.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

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

double RunningIntegralTable::Cumulative(int channel, double x, double y, double z) const
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

double RunningIntegralTable::Box(int channel, const double a[3], const double b[3]) const
{
  BoxTaps taps;
  return this->Box(channel, a, b, taps);
}

double RunningIntegralTable::Box(
  int channel, const double a[3], const double b[3], BoxTaps& taps) const
{
  // The inclusion-exclusion of the eight corners' trilinear interpolations, gathered per
  // axis: at most 4 x 4 x 4 table values, fewer at the grid's ends.
  for (int axis = 0; axis < 3; ++axis)
  {
    taps[axis].Set(a[axis], b[axis], this->N[axis]);
  }
  return this->Sum(channel, taps[0], taps[1], taps[2]);
}

double RunningIntegralTable::Sum(
  int channel, const AxisTaps& x, const AxisTaps& y, const AxisTaps& z) const
{
  double sum = 0.0;
  for (int k = 0; k < z.Count; ++k)
  {
    for (int j = 0; j < y.Count; ++j)
    {
      const double* row = &this->Values[this->Index(channel, 0, y.Index[j], z.Index[k])];
      double line = 0.0;
      for (int i = 0; i < x.Count; ++i)
      {
        line += x.Weight[i] * row[x.Index[i] * this->Channels];
      }
      sum += y.Weight[j] * z.Weight[k] * line;
    }
  }
  return sum;
}

void RunningIntegralTable::CollapseToLine(
  int channel, int axis, const BoxTaps& taps, double* line) const
{
  const long long stride[3] = { this->Channels, (this->N[0] + 1LL) * this->Channels,
    (this->N[0] + 1LL) * (this->N[1] + 1LL) * this->Channels };
  const AxisTaps& u = taps[(axis + 1) % 3];
  const AxisTaps& v = taps[(axis + 2) % 3];
  const long long planes = this->N[axis] + 1LL;
  const long long step = stride[axis];
  std::fill_n(line, planes, 0.0);
  for (int a = 0; a < u.Count; ++a)
  {
    for (int b = 0; b < v.Count; ++b)
    {
      const double w = u.Weight[a] * v.Weight[b];
      const double* column = &this->Values[static_cast<size_t>(
        channel + u.Index[a] * stride[(axis + 1) % 3] + v.Index[b] * stride[(axis + 2) % 3])];
      if (step == 1) // a loop the compiler vectorises
      {
        for (long long m = 0; m < planes; ++m)
        {
          line[m] += w * column[m];
        }
        continue;
      }
      for (long long m = 0; m < planes; ++m)
      {
        line[m] += w * column[m * step];
      }
    }
  }
}

void RunningIntegralTable::Allocate(const std::array<int, 3>& n, int channels)
{
  this->N = n;
  this->Channels = channels;
  this->Values.resize(static_cast<size_t>(n[0] + 1) * (n[1] + 1) * (n[2] + 1) * channels);
  // The zero planes; SetCell writes everything else.
  const long long nx = n[0], ny = n[1], nz = n[2];
  vtkSMPTools::For(0, nz + 1,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
        for (long long j = 0; j <= ny; ++j)
          for (long long i = 0; i <= nx; i += (j == 0 || k == 0) ? 1 : nx + 1)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) = 0.0;
    });
}

void RunningIntegralTable::Integrate()
{
  const long long nx = this->N[0], ny = this->N[1], nz = this->N[2];
  const int channels = this->Channels;
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

void CartesianSAT::ToFrame(const double p[3], double q[3]) const
{
  for (int a = 0; a < 3; ++a)
  {
    q[a] = vtkMath::Dot(p, this->Frame.Axes[a].data()) - this->Origin[a];
  }
}

double CartesianSAT::BeyondBox(
  int channel, int axis, int sign, const RunningIntegralTable::BoxTaps& taps) const
{
  const RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  if (beyond.GetDimensions()[axis] == 0)
  {
    return 0.0;
  }
  // The one cell along the axis, whole.
  static const RunningIntegralTable::AxisTaps whole = []
  {
    RunningIntegralTable::AxisTaps t;
    t.Set(0.0, 1.0, 1);
    return t;
  }();
  return beyond.Sum(
    channel, axis == 0 ? whole : taps[0], axis == 1 ? whole : taps[1], axis == 2 ? whole : taps[2]);
}

double CartesianSAT::BoxIntegral(int channel, const double lo[3], const double hi[3]) const
{
  const double a[3] = { lo[0] / this->H, lo[1] / this->H, lo[2] / this->H };
  const double b[3] = { hi[0] / this->H, hi[1] / this->H, hi[2] / this->H };
  return this->Table.Box(channel, a, b);
}

double CartesianSAT::FilteredOpticalDepth(
  int channel, const double p[3], int axis, int sign, double halfWidth) const
{
  double depth;
  std::vector<double> unused;
  this->FilteredOpticalDepths(channel, p, 1, axis, sign, halfWidth, &depth, unused);
  return depth;
}

void CartesianSAT::FilteredOpticalDepths(int channel, const double* points, int count, int axis,
  int sign, double halfWidth, double* depth, std::vector<double>& line) const
{
  const double end = this->Table.GetDimensions()[axis] * this->H;
  const double area = 4.0 * halfWidth * halfWidth;
  const double perCell = 1.0 / this->H;
  // The box of point i in cell units.
  auto box = [&](int i, double lo[3], double hi[3])
  {
    double q[3];
    this->ToFrame(points + 3 * i, q);
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = q[a] - halfWidth;
      hi[a] = q[a] + halfWidth;
    }
    lo[axis] = sign > 0 ? q[axis] : 0.0;
    hi[axis] = sign > 0 ? end : q[axis];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] *= perCell;
      hi[a] *= perCell;
    }
  };
  // The row's axis (along), when its first, middle and last boxes differ on that axis only,
  // and the ends the others share (key). Collapsing costs up to 16 reads a plane of the axis,
  // a box read from the table up to 64.
  int along = -1;
  double keyLo[3], keyHi[3];
  const auto& n = this->Table.GetDimensions();
  if (count > 1)
  {
    double lo[2][3], hi[2][3];
    box(0, lo[0], hi[0]);
    box(count - 1, lo[1], hi[1]);
    box(count / 2, keyLo, keyHi);
    int differing = 0;
    for (int a = 0; a < 3; ++a)
    {
      bool same = true;
      for (int e = 0; e < 2; ++e)
      {
        same = same && lo[e][a] == keyLo[a] && hi[e][a] == keyHi[a];
      }
      if (!same)
      {
        along = a;
        ++differing;
      }
    }
    along = differing == 1 && 3LL * count > n[along] ? along : -1;
  }
  RunningIntegralTable::BoxTaps taps;
  // The key's columns beyond the window (SetBeyond): a sum when the row runs along the
  // light's axis, else collapsed onto the row's axis (beyondLine).
  const RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  double keyBeyond = 0.0;
  bool beyondLine = false;
  if (along >= 0)
  {
    RunningIntegralTable::BoxTaps keyTaps;
    for (int a = 0; a < 3; ++a)
    {
      keyTaps[a].Set(keyLo[a], keyHi[a], n[a]);
    }
    line.resize(2 * (n[along] + 1LL));
    this->Table.CollapseToLine(channel, along, keyTaps, line.data());
    if (along == axis)
    {
      keyBeyond = this->BeyondBox(channel, axis, sign, keyTaps);
    }
    else if (beyond.GetDimensions()[axis] > 0)
    {
      // The columns beyond, collapsed onto the row's axis too (after the table's line).
      keyTaps[axis].Set(0.0, 1.0, 1);
      beyond.CollapseToLine(channel, along, keyTaps, line.data() + n[along] + 1);
      beyondLine = true;
    }
  }
  for (int i = 0; i < count; ++i)
  {
    double lo[3], hi[3];
    box(i, lo, hi);
    // A box beside the table (a window of a piece's table, CartesianSAT::Build) holds nothing.
    if ((hi[0] <= 0.0 || lo[0] >= n[0]) || (hi[1] <= 0.0 || lo[1] >= n[1]) ||
      (hi[2] <= 0.0 || lo[2] >= n[2]))
    {
      depth[i] = 0.0;
      continue;
    }
    const int u = (along + 1) % 3, v = (along + 2) % 3;
    if (along >= 0 && lo[u] == keyLo[u] && hi[u] == keyHi[u] && lo[v] == keyLo[v] &&
      hi[v] == keyHi[v])
    {
      taps[along].Set(lo[along], hi[along], n[along]);
      const double far = beyondLine
        ? RunningIntegralTable::LineBox(line.data() + n[along] + 1, taps[along])
        : keyBeyond;
      depth[i] = (RunningIntegralTable::LineBox(line.data(), taps[along]) + far) / area;
      continue;
    }
    const double inWindow = this->Table.Box(channel, lo, hi, taps);
    depth[i] = (inWindow + this->BeyondBox(channel, axis, sign, taps)) / area;
  }
}

double CartesianSAT::ConeFilteredOpticalDepth(int channel, const double p[3], int axis, int sign,
  double halfWidth, double start, double spread) const
{
  const auto& n = this->Table.GetDimensions();
  double q[3];
  this->ToFrame(p, q);
  // Distances from the shadow ray's start; the table's end toward the light.
  const double end = start + std::max(sign > 0 ? n[axis] * this->H - q[axis] : q[axis], 0.0);
  // A box this wide covers the table across the axis wherever the point is.
  const double widest = (n[0] + n[1] + n[2]) * this->H;
  const double perCell = 1.0 / this->H;
  auto read = [&](double t0, double t1, double w)
  {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = (q[a] - w) * perCell;
      hi[a] = (q[a] + w) * perCell;
    }
    const double a0 = q[axis] + sign * (t0 - start), a1 = q[axis] + sign * (t1 - start);
    lo[axis] = std::min(a0, a1) * perCell;
    hi[axis] = std::max(a0, a1) * perCell;
    RunningIntegralTable::BoxTaps taps;
    double integral = this->Table.Box(channel, lo, hi, taps);
    if (t1 >= end)
    {
      integral += this->BeyondBox(channel, axis, sign, taps);
    }
    return integral / (4.0 * w * w);
  };
  return ConeSteps(
    start, end, halfWidth, widest, [spread](double t) { return spread * t; },
    [spread](double w) { return w / spread; }, read);
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
  const double ends[2] = { (sign > 0 ? q[axis] : 0.0) / this->H,
    (sign > 0 ? this->Table.GetDimensions()[axis] * this->H : q[axis]) / this->H };
  // Running integrals at the corners of the count x count squares, at both ends of the
  // cuboids: neighbouring squares share them (eq. 25 with 2 (count+1)^2 table reads); and
  // those of the columns beyond the window (SetBeyond), one cell along the axis.
  const RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  const int levels = beyond.GetDimensions()[axis] > 0 ? 3 : 2;
  std::vector<double> corner(levels * (count + 1) * (count + 1));
  for (int e = 0; e < levels; ++e)
  {
    for (int i = 0; i <= count; ++i)
    {
      for (int j = 0; j <= count; ++j)
      {
        double c[3];
        c[axis] = e < 2 ? ends[e] : 1.0;
        c[a1] = (q[a1] - halfWidth + i * side) / this->H;
        c[a2] = (q[a2] - halfWidth + j * side) / this->H;
        corner[(e * (count + 1) + i) * (count + 1) + j] =
          (e < 2 ? this->Table : beyond).Cumulative(channel, c[0], c[1], c[2]);
      }
    }
  }
  auto at = [&](int e, int i, int j) { return corner[(e * (count + 1) + i) * (count + 1) + j]; };
  double depth = 0.0;
  for (int i = 0; i < count; ++i)
  {
    for (int j = 0; j < count; ++j)
    {
      double square = 0.0;
      for (int e = 0; e < levels; ++e)
      {
        const double face = at(e, i + 1, j + 1) - at(e, i, j + 1) - at(e, i + 1, j) + at(e, i, j);
        square += e == 0 ? -face : face;
      }
      depth += weights[i] * weights[j] * square / (side * side);
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
