// Tests of the light-aligned summed-area tables: box integrals and filtered optical depth
// against direct sums over the cells, precision at large sizes, and sharing one table
// between orthodirectional lights.
#include "RayMarchKernel.h"
#include "SummedAreaTableKernel.h"

#include "vtkMath.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace volillum;

namespace
{
// A classified volume with random extinction (0 to 8) and absorption (0 to 1): channels of
// different scales (ClassifiedVolume::Scale).
ClassifiedVolume RandomVolume(int nx, int ny, int nz, double spacing, int seed)
{
  ClassifiedVolume v;
  v.Geometry.Dimensions = { { nx, ny, nz } };
  v.Geometry.Spacing = { { spacing, spacing, spacing } };
  v.Geometry.Origin = { { -1.0, 2.0, 0.5 } };
  std::vector<float> values(4 * static_cast<size_t>(v.Geometry.NumberOfPoints()));
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(seed);
  for (size_t i = 0; i < values.size(); ++i)
  {
    random->Next();
    values[i] = static_cast<float>(random->GetValue() * (i % 4 == 0 ? 8.0 : 1.0));
  }
  v.Store(values);
  return v;
}

// A table of v (cells of 0.5) in the frame of an oblique light, and the frame axis and sign
// of that light's direction.
CartesianSAT ObliqueTable(const ClassifiedVolume& v, int& axis, int& sign)
{
  double d[3] = { -0.4, 0.2, -0.9 };
  vtkMath::Normalize(d);
  CartesianSAT sat;
  sat.Build(v, FrameForDirection(d), 0.5, 1);
  axis = AxisOfDirection(sat.GetFrame(), d, sign);
  return sat;
}

// Extinction of a table cell computed directly from the volume: the sample at the cell's
// centre, zero outside the data.
double CellExtinction(
  const ClassifiedVolume& v, const CartesianSAT& sat, int channel, int i, int j, int k)
{
  const double h = sat.GetCellSize();
  const double zero[3] = { 0, 0, 0 };
  double shift[3];
  sat.ToFrame(zero, shift);
  const double q[3] = { (i + 0.5) * h - shift[0], (j + 0.5) * h - shift[1],
    (k + 0.5) * h - shift[2] };
  const auto& axes = sat.GetFrame().Axes;
  double p[3], bounds[6];
  v.Geometry.GetBounds(bounds);
  for (int a = 0; a < 3; ++a)
  {
    p[a] = q[0] * axes[0][a] + q[1] * axes[1][a] + q[2] * axes[2][a];
  }
  for (int a = 0; a < 3; ++a)
  {
    if (p[a] < bounds[2 * a] - 1e-9 || p[a] > bounds[2 * a + 1] + 1e-9)
    {
      return 0.0;
    }
  }
  float s[4];
  v.Sample(p, s);
  return sat.GetNumberOfChannels() == 3 ? s[0] * s[1 + channel] : s[0];
}

// The integral of the table's cell field over a box, summed cell by cell with the overlap
// of each cell (the direct evaluation of eq. 12), independent of the running sums.
double DirectBoxIntegral(const ClassifiedVolume& v, const CartesianSAT& sat, int channel,
  const double lo[3], const double hi[3])
{
  const double h = sat.GetCellSize();
  const auto& n = sat.GetDimensions();
  int first[3], last[3];
  for (int a = 0; a < 3; ++a)
  {
    first[a] = std::max(0, static_cast<int>(std::floor(lo[a] / h)));
    last[a] = std::min(n[a] - 1, static_cast<int>(std::floor(hi[a] / h)));
  }
  double sum = 0.0;
  for (int k = first[2]; k <= last[2]; ++k)
    for (int j = first[1]; j <= last[1]; ++j)
      for (int i = first[0]; i <= last[0]; ++i)
      {
        const int c[3] = { i, j, k };
        double overlap = 1.0;
        for (int a = 0; a < 3; ++a)
        {
          overlap *= std::max(0.0, std::min(hi[a], (c[a] + 1) * h) - std::max(lo[a], c[a] * h));
        }
        if (overlap > 0.0)
        {
          sum += overlap * CellExtinction(v, sat, channel, i, j, k);
        }
      }
  return sum;
}
}

TEST(SummedAreaTable, CellsHoldTheSampledExtinction)
{
  ClassifiedVolume v = RandomVolume(9, 7, 8, 0.5, 3);
  const double up[3] = { 0, 0, 1 };
  CartesianSAT sat;
  sat.Build(v, FrameForDirection(up), 0.5, 3);
  // In the data's own frame, cell (i, j, k) is centred half a spacing past point (i, j, k).
  double origin[3];
  const double zero[3] = { 0, 0, 0 };
  sat.ToFrame(zero, origin);
  for (int k = 0; k < 7; k += 3)
    for (int j = 0; j < 6; j += 2)
      for (int i = 0; i < 8; i += 3)
      {
        double q[3] = { (i + 0.5) * 0.5, (j + 0.5) * 0.5, (k + 0.5) * 0.5 };
        const auto& axes = sat.GetFrame().Axes;
        double p[3];
        for (int a = 0; a < 3; ++a)
        {
          p[a] = (q[0] - origin[0]) * axes[0][a] + (q[1] - origin[1]) * axes[1][a] +
            (q[2] - origin[2]) * axes[2][a];
        }
        float s[4];
        v.Sample(p, s);
        EXPECT_NEAR(sat.CellExtinction(1, i, j, k), s[0] * s[2], 1e-5);
      }
}

TEST(SummedAreaTable, BoxIntegralsEqualDirectSumsOverRandomCuboids)
{
  ClassifiedVolume v = RandomVolume(21, 17, 19, 1.0, 11);
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(5);
  auto next = [&](double lo, double hi)
  {
    random->Next();
    return random->GetRangeValue(lo, hi);
  };
  for (const auto& direction :
    { std::array<double, 3>{ 0, 0, 1 }, std::array<double, 3>{ 0.3, -0.5, 0.8 } })
  {
    double d[3] = { direction[0], direction[1], direction[2] };
    vtkMath::Normalize(d);
    CartesianSAT sat;
    sat.Build(v, FrameForDirection(d), 0.75, 3);
    const auto& n = sat.GetDimensions();
    const double everything[3] = { n[0] * sat.GetCellSize(), n[1] * sat.GetCellSize(),
      n[2] * sat.GetCellSize() };
    const double origin[3] = { 0, 0, 0 };
    const double total = sat.BoxIntegral(0, origin, everything);
    double worst = 0.0;
    for (int trial = 0; trial < 200; ++trial)
    {
      double lo[3], hi[3];
      for (int a = 0; a < 3; ++a)
      {
        const double extent = n[a] * sat.GetCellSize();
        const double x0 = next(-1.0, extent), x1 = next(-1.0, extent + 1.0);
        lo[a] = std::min(x0, x1);
        hi[a] = std::max(x0, x1);
        if (trial % 4 == 0)
        {
          // Whole cells too.
          lo[a] = std::floor(lo[a] / sat.GetCellSize()) * sat.GetCellSize();
          hi[a] = std::ceil(hi[a] / sat.GetCellSize()) * sat.GetCellSize();
        }
      }
      const int channel = trial % 3;
      const double expected = DirectBoxIntegral(v, sat, channel, lo, hi);
      const double got = sat.BoxIntegral(channel, lo, hi);
      // Boxes in the empty corners of a rotated table hold (almost) nothing: their
      // difference is measured against a billionth of the whole table's integral.
      const double error = std::abs(got - expected) / std::max(std::abs(expected), 1e-9 * total);
      worst = std::max(worst, error);
    }
    std::cout << "largest relative difference over 200 cuboids: " << worst << std::endl;
    EXPECT_LE(worst, 1e-6);
  }
}

TEST(SummedAreaTable, EmptyBlocksLeaveTheTableAsItIs)
{
  // Half of the volume holds no extinction: a table built with the empty blocks skips the
  // samples there, and every cell equals the table's built from every sample.
  ClassifiedVolume v = RandomVolume(26, 21, 23, 1.0, 29);
  for (long long point = 0; point < v.Geometry.NumberOfPoints(); ++point)
  {
    if ((point / 26) % 21 < 11)
    {
      v.Properties[static_cast<size_t>(4 * point)] = 0; // the code of 0
    }
  }
  const EmptyBlocks empty(v);
  double d[3] = { 0.3, -0.5, 0.8 };
  vtkMath::Normalize(d);
  for (const int channels : { 1, 3 })
  {
    CartesianSAT every, skipping;
    every.Build(v, FrameForDirection(d), 0.75, channels);
    skipping.Build(v, FrameForDirection(d), 0.75, channels, &empty);
    const auto& n = every.GetDimensions();
    double worst = 0.0, zero = 0.0;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i)
          for (int c = 0; c < channels; ++c)
          {
            const double value = every.CellExtinction(c, i, j, k);
            worst = std::max(worst, std::abs(value - skipping.CellExtinction(c, i, j, k)));
            zero += value == 0.0 ? 1.0 : 0.0;
          }
    std::cout << channels << " channels: cells of extinction 0 " << zero << ", largest difference "
              << worst << std::endl;
    EXPECT_GT(zero, 0.3 * n[0] * n[1] * n[2] * channels);
    EXPECT_EQ(worst, 0.0);
  }
}

TEST(SummedAreaTable, FilteredOpticalDepthEqualsTheDirectBoxFilter)
{
  ClassifiedVolume v = RandomVolume(24, 20, 22, 1.0, 17);
  int axis, sign;
  const CartesianSAT sat = ObliqueTable(v, axis, sign);
  ASSERT_EQ(axis, 2);
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(23);
  auto next = [&](double lo, double hi)
  {
    random->Next();
    return random->GetRangeValue(lo, hi);
  };
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial)
  {
    const double p[3] = { next(0, 22), next(3, 20), next(1, 21) };
    const double halfWidth = next(0.25, 4.0);
    double q[3], lo[3], hi[3];
    sat.ToFrame(p, q);
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = q[a] - halfWidth;
      hi[a] = q[a] + halfWidth;
    }
    lo[axis] = sign > 0 ? q[axis] : 0.0;
    hi[axis] = sign > 0 ? sat.GetDimensions()[axis] * sat.GetCellSize() : q[axis];
    const double expected = DirectBoxIntegral(v, sat, 0, lo, hi) / (4.0 * halfWidth * halfWidth);
    const double got = sat.FilteredOpticalDepth(0, p, axis, sign, halfWidth);
    worst = std::max(worst, std::abs(got - expected) / std::max(expected, 1e-12));
  }
  std::cout << "filtered optical depth: largest relative difference " << worst << std::endl;
  EXPECT_LE(worst, 1e-3);
}

TEST(SummedAreaTable, LargeTablesKeepSmallBoxesAccurate)
{
  // A homogeneous 512^3 table of 0.1 per cell: every box integral is a tenth of its
  // volume, however large the running sums grow (1.3e7 here). Single precision would lose
  // everything (its unit in the last place at 1.3e7 is 1); double keeps ~1e-8.
  RunningIntegralTable table;
  table.Allocate({ { 512, 512, 512 } }, 1);
  for (long long k = 0; k < 512; ++k)
    for (long long j = 0; j < 512; ++j)
      for (long long i = 0; i < 512; ++i)
        table.SetCell(0, i, j, k, 0.1);
  table.Integrate();
  double worst = 0.0;
  for (double corner : { 0.5, 100.25, 300.0, 510.25 })
  {
    const double lo[3] = { corner, 511.0 - corner, corner };
    const double hi[3] = { lo[0] + 1.5, lo[1] + 0.5, lo[2] + 1.0 };
    const double expected = 0.1 * 1.5 * 0.5 * 1.0;
    worst = std::max(worst, std::abs(table.Box(0, lo, hi) - expected) / expected);
  }
  std::cout << "512^3 table, small boxes: largest relative error " << worst << std::endl;
  EXPECT_LE(worst, 1e-4);
}

TEST(SummedAreaTable, OrthodirectionalLightsShareOneTable)
{
  ClassifiedVolume v = RandomVolume(16, 18, 14, 1.0, 29);
  const double down[3] = { 0, 0, -1 };
  CartesianSAT shared;
  shared.Build(v, FrameForDirection(down), 1.0, 1);
  const double directions[6][3] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 },
    { 0, 0, 1 }, { 0, 0, -1 } };
  for (const auto& d : directions)
  {
    int sharedSign = 0;
    const int sharedAxis = AxisOfDirection(shared.GetFrame(), d, sharedSign);
    ASSERT_GE(sharedAxis, 0);
    CartesianSAT own;
    own.Build(v, FrameForDirection(d), 1.0, 1);
    int ownSign = 0;
    const int ownAxis = AxisOfDirection(own.GetFrame(), d, ownSign);
    for (const auto& p :
      { std::array<double, 3>{ 3.2, 5.5, 7.1 }, std::array<double, 3>{ 10, 2, 12.5 } })
    {
      for (double halfWidth : { 0.5, 2.5 })
      {
        const double a =
          shared.FilteredOpticalDepth(0, p.data(), sharedAxis, sharedSign, halfWidth);
        const double b = own.FilteredOpticalDepth(0, p.data(), ownAxis, ownSign, halfWidth);
        EXPECT_NEAR(a, b, 1e-9 * std::max(1.0, std::abs(b)));
      }
    }
  }
}

TEST(SummedAreaTable, RowsOfPointsEqualEachPointAlone)
{
  // Rows along each axis of a table in the data's frame read the table collapsed onto the
  // row (FilteredOpticalDepths); points moved toward the light (as near segments move them)
  // or off the row read boxes of their own. Every depth equals the point's read alone.
  ClassifiedVolume v = RandomVolume(24, 20, 22, 1.0, 37);
  const double down[3] = { 0, 0, -1 };
  const double directions[6][3] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 },
    { 0, 0, 1 }, { 0, 0, -1 } };
  for (const int channels : { 1, 3 })
  {
    CartesianSAT sat;
    sat.Build(v, FrameForDirection(down), 1.0, channels);
    double worst = 0.0, largest = 0.0;
    int rows = 0;
    for (const auto& d : directions)
    {
      int sign = 0;
      const int axis = AxisOfDirection(sat.GetFrame(), d, sign);
      ASSERT_GE(axis, 0);
      for (int along = 0; along < 3; ++along)
      {
        const int count = v.Geometry.Dimensions[along];
        std::vector<double> points(3 * count);
        for (int i = 0; i < count; ++i)
        {
          double* p = &points[3 * i];
          p[0] = -1.0 + 7.0;
          p[1] = 2.0 + 9.5;
          p[2] = 0.5 + 6.0;
          p[along] = v.Geometry.Origin[along] + i;
          // Some points moved toward the light, one off the row; the first, middle and last
          // stay on it (the row is collapsed).
          const bool kept = i == 0 || i == count / 2 || i == count - 1;
          const double toward = i % 5 == 4 && !kept ? 0.75 * (i % 3 + 1) : 0.0;
          for (int a = 0; a < 3; ++a)
          {
            p[a] -= toward * d[a];
          }
          p[(along + 1) % 3] += i == count / 3 ? 0.3 : 0.0;
        }
        for (double halfWidth : { 0.5, 1.5, 4.0 })
        {
          for (int c = 0; c < channels; ++c)
          {
            std::vector<double> row(count), line;
            sat.FilteredOpticalDepths(
              c, points.data(), count, axis, sign, halfWidth, row.data(), line);
            for (int i = 0; i < count; ++i)
            {
              const double alone =
                sat.FilteredOpticalDepth(c, &points[3 * i], axis, sign, halfWidth);
              worst = std::max(worst, std::abs(row[i] - alone));
              largest = std::max(largest, alone);
            }
            ++rows;
          }
        }
      }
    }
    std::cout << channels << " channels, " << rows << " rows: largest difference " << worst
              << " (largest depth " << largest << ")" << std::endl;
    EXPECT_GT(largest, 1.0);
    EXPECT_LE(worst, 1e-12 * largest);
  }
}

TEST(SummedAreaTable, GaussianKernelIsAWeightedSumOfSubCuboids)
{
  ClassifiedVolume v = RandomVolume(20, 20, 20, 1.0, 31);
  const double down[3] = { 0, 0, -1 };
  CartesianSAT sat;
  sat.Build(v, FrameForDirection(down), 1.0, 1);
  int sign = 0;
  const int axis = AxisOfDirection(sat.GetFrame(), down, sign);
  const auto weights = GaussianWeights(5);
  double total = 0.0;
  for (double w : weights)
  {
    total += w;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_GT(weights[2], weights[1]);
  EXPECT_NEAR(weights[0], weights[4], 1e-15);
  const double p[3] = { 9.3, 8.7, 6.2 };
  const double halfWidth = 3.0;
  double q[3];
  sat.ToFrame(p, q);
  // Direct evaluation of eq. 25: every sub-cuboid summed cell by cell.
  double expected = 0.0;
  const double side = 2.0 * halfWidth / 5;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
    {
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      double lo[3], hi[3];
      lo[a1] = q[a1] - halfWidth + i * side;
      hi[a1] = lo[a1] + side;
      lo[a2] = q[a2] - halfWidth + j * side;
      hi[a2] = lo[a2] + side;
      lo[axis] = sign > 0 ? q[axis] : 0.0;
      hi[axis] = sign > 0 ? sat.GetDimensions()[axis] * sat.GetCellSize() : q[axis];
      expected += weights[i] * weights[j] * DirectBoxIntegral(v, sat, 0, lo, hi) / (side * side);
    }
  const double gaussian = sat.KernelFilteredOpticalDepth(0, p, axis, sign, halfWidth, weights);
  const double box = sat.FilteredOpticalDepth(0, p, axis, sign, halfWidth);
  EXPECT_NEAR(gaussian, expected, 1e-6 * expected);
  // On this random medium the two kernels differ.
  EXPECT_GT(std::abs(gaussian - box), 1e-4 * box);
}

TEST(SummedAreaTable, KernelsAgreeWhereTheMediumIsLaterallyUniform)
{
  // Extinction varying only along z: every shadow ray of the patch sees the same depth.
  ClassifiedVolume v = RandomVolume(12, 12, 30, 1.0, 37);
  const long long nx = 12, ny = 12;
  for (long long id = 0; id < v.Geometry.NumberOfPoints(); ++id)
  {
    v.Properties[4 * id] = v.Pack(0, 0.05 * (1 + (id / (nx * ny)) % 5));
  }
  const double up[3] = { 0, 0, 1 };
  CartesianSAT sat;
  sat.Build(v, FrameForDirection(up), 1.0, 1);
  int sign = 0;
  const int axis = AxisOfDirection(sat.GetFrame(), up, sign);
  const double p[3] = { 5.5, 6.0, 4.0 };
  const double box = sat.FilteredOpticalDepth(0, p, axis, sign, 2.0);
  const double gaussian = sat.KernelFilteredOpticalDepth(0, p, axis, sign, 2.0, GaussianWeights(5));
  const double thin = sat.FilteredOpticalDepth(0, p, axis, sign, 0.5);
  EXPECT_NEAR(box, gaussian, 1e-9 * box);
  EXPECT_NEAR(box, thin, 1e-9 * box);
}

TEST(SummedAreaTable, SphericalTablesIntegrateAUniformMediumFromTheLight)
{
  // Extinction sigma everywhere in the box [0, 31]^3: the optical depth from a point light
  // to p is sigma times the length of the ray inside the box, for lights beside a face and
  // beyond a corner (cube-map face angles fitted to the corners) and inside the box (polar
  // angles), with the table's cells starting where the box begins. Cells that the box's
  // face cuts are sampled at their centre, so the depth may be off by sigma x half a cell
  // there.
  ClassifiedVolume v;
  v.Geometry.Dimensions = { { 32, 32, 32 } };
  std::vector<float> values(4 * static_cast<size_t>(v.Geometry.NumberOfPoints()), 1.0f);
  const double sigma = 0.0625; // exactly stored (PackedValue)
  for (size_t i = 0; i < values.size(); i += 4)
  {
    values[i] = static_cast<float>(sigma);
  }
  v.Store(values);
  double bounds[6];
  v.Geometry.GetBounds(bounds);
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(7);
  for (const auto& light : { std::array<double, 3>{ -20.0, 15.5, 15.5 },
         std::array<double, 3>{ -10.0, -12.0, 45.0 }, std::array<double, 3>{ 10.0, 20.0, 12.0 } })
  {
    SphericalSAT table;
    table.Build(v, light.data(), 1.0, 1);
    const bool inside = light[0] >= 0.0 && light[0] <= 31.0 && light[1] >= 0.0 &&
      light[1] <= 31.0 && light[2] >= 0.0 && light[2] <= 31.0;
    EXPECT_EQ(table.IsPolar(), inside);
    double worst = 0.0;
    for (int n = 0; n < 200; ++n)
    {
      double p[3], toLight[3];
      for (int a = 0; a < 3; ++a)
      {
        random->Next();
        p[a] = 2.0 + 27.0 * random->GetValue();
        toLight[a] = light[a] - p[a];
      }
      const double distance = vtkMath::Normalize(toLight);
      const double inside = std::min(distance, DistanceToBoxExit(p, toLight, bounds));
      const double got = table.FilteredOpticalDepth(0, p, 0.0);
      // The error as a length along the ray, in cells.
      worst = std::max(worst, std::abs(got - sigma * inside) / (sigma * table.GetCellSize()));
    }
    std::cout << "light (" << light[0] << "," << light[1] << "," << light[2]
              << "): largest error of the optical depth " << worst << " sigma x cell" << std::endl;
    EXPECT_LE(worst, 0.5);
  }
}

namespace
{
// Half the 10-90 % width of the shadow a straight edge casts from a uniform disc of radius 1:
// x with (x sqrt(1 - x^2) + asin x) / pi = 0.4, the part of the disc beyond the chord at x.
double DiscPenumbraHalfWidth()
{
  double low = 0.0, high = 1.0;
  for (int i = 0; i < 60; ++i)
  {
    const double x = 0.5 * (low + high);
    ((x * std::sqrt(1.0 - x * x) + std::asin(x)) / vtkMath::Pi() < 0.4 ? low : high) = x;
  }
  return 0.5 * (low + high);
}

// A plate with a straight edge: extinction 0.1 at the points with z in {60, 61} and x <= 47
// of a 96 x 8 x 72 grid of unit spacing, 0 elsewhere (optical depth 0.1 across it, so a
// shadow's optical depth is 0.1 x the part of the light the plate hides).
ClassifiedVolume EdgePlate()
{
  ClassifiedVolume v;
  v.Geometry.Dimensions = { { 96, 8, 72 } };
  std::vector<float> values(4 * static_cast<size_t>(v.Geometry.NumberOfPoints()), 1.0f);
  for (int k = 0; k < 72; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 96; ++i)
      {
        values[4 * (i + 96 * (j + 8 * k))] = (k == 60 || k == 61) && i <= 47 ? 0.1f : 0.0f;
      }
  v.Store(values);
  return v;
}

// The 10-90 % width along x of the shadow of EdgePlate at height z, from the optical depths
// depth(x) at x in [8, 88] (the plate's full shadow is the largest of them).
template <typename Depth>
double PenumbraWidth(const Depth& depth)
{
  std::vector<double> x, d;
  for (double at = 8.0; at <= 88.0; at += 0.05)
  {
    x.push_back(at);
    d.push_back(depth(at));
  }
  const double full = *std::max_element(d.begin(), d.end());
  // The depth falls with x: where it crosses a fraction f of full.
  auto crossing = [&](double f)
  {
    for (size_t i = 1; i < d.size(); ++i)
    {
      if (d[i - 1] >= f * full && d[i] < f * full)
      {
        return x[i - 1] + (d[i - 1] - f * full) / (d[i - 1] - d[i]) * (x[i] - x[i - 1]);
      }
    }
    return 0.0;
  };
  return crossing(0.1) - crossing(0.9);
}
}

TEST(SummedAreaTable, ConesOfALightOfNoSizeAreTheFilterBoxes)
{
  // Spread 0: FilteredOpticalDepth's cuboid, wherever the box starts.
  ClassifiedVolume v = RandomVolume(24, 20, 22, 1.0, 31);
  int axis, sign;
  const CartesianSAT sat = ObliqueTable(v, axis, sign);
  double worst = 0.0;
  for (int n = 0; n < 40; ++n)
  {
    const double p[3] = { 1.0 + 0.5 * n, 3.0 + 0.3 * n, 20.0 - 0.4 * n };
    const double halfWidth = 0.3 + 0.08 * n;
    const double box = sat.FilteredOpticalDepth(0, p, axis, sign, halfWidth);
    worst = std::max(worst,
      std::abs(sat.ConeFilteredOpticalDepth(0, p, axis, sign, halfWidth, 0.1 * n, 0.0) - box) /
        std::max(box, 1e-12));
  }
  std::cout << "cones of spread 0: largest relative difference " << worst << std::endl;
  EXPECT_LE(worst, 1e-9);
}

TEST(SummedAreaTable, ConesKeepTheDepthOfAUniformMedium)
{
  // Extinction 0.0625 everywhere: however wide the cone, where it stays inside the medium the
  // mean optical depth is the medium's along the ray (the boxes' widths change what they
  // average, not the depth).
  ClassifiedVolume v;
  v.Geometry.Dimensions = { { 40, 40, 40 } };
  std::vector<float> values(4 * static_cast<size_t>(v.Geometry.NumberOfPoints()), 1.0f);
  for (size_t i = 0; i < values.size(); i += 4)
  {
    values[i] = 0.0625f;
  }
  v.Store(values);
  const double down[3] = { 0.0, 0.0, -1.0 };
  CartesianSAT sat;
  sat.Build(v, FrameForDirection(down), 1.0, 1);
  const double toward[3] = { 0.0, 0.0, 1.0 };
  int sign = 0;
  const int axis = AxisOfDirection(sat.GetFrame(), toward, sign);
  const double p[3] = { 19.5, 19.5, 25.0 };
  const double plain = sat.FilteredOpticalDepth(0, p, axis, sign, 1.0);
  // A light 30 degrees across: the cone widens to 0.232 x 14.5 = 3.4 cells at the top face,
  // inside the medium.
  const double cone = sat.ConeFilteredOpticalDepth(0, p, axis, sign, 1.0, 0.0, 0.2320);
  std::cout << "uniform medium: depth along the ray " << plain << ", through the cone " << cone
            << std::endl;
  EXPECT_NEAR(plain, 0.0625 * 14.5, 0.0625 * 0.5);
  EXPECT_NEAR(cone, plain, 1e-6 * plain);
}

TEST(SummedAreaTable, PenumbraOfADirectionalDiscWidensAsItsAnalyticShadow)
{
  // A directional light of angular diameter alpha straight above EdgePlate: the shadow's
  // 10-90 % width at a distance t below the plate's middle is that of the disc of radius
  // t tan(alpha / 2) (2 x DiscPenumbraHalfWidth of it). The plate's edge, sampled at grid
  // points, and the table's cells blur the hard shadow (alpha 0) over about 0.8 units: the
  // cases keep that under a third of the disc's penumbra.
  const ClassifiedVolume v = EdgePlate();
  const double toward[3] = { 0.0, 0.0, 1.0 };
  CartesianSAT sat;
  sat.Build(v, FrameForDirection(toward), 0.5, 1);
  int sign = 0;
  const int axis = AxisOfDirection(sat.GetFrame(), toward, sign);
  for (const double t : { 25.0, 50.0 })
  {
    double previous = 0.0;
    for (const double alpha : { 0.0, 10.0, 20.0, 30.0 })
    {
      const double spread = DirectionalConeSpread(alpha);
      const double width = PenumbraWidth(
        [&](double x)
        {
          const double p[3] = { x, 3.5, 60.5 - t };
          return sat.ConeFilteredOpticalDepth(0, p, axis, sign, 0.25, 0.0, spread);
        });
      const double expected =
        2.0 * DiscPenumbraHalfWidth() * t * std::tan(0.5 * vtkMath::RadiansFromDegrees(alpha));
      std::cout << "directional light of " << alpha << " degrees, " << t
                << " below the plate: penumbra " << width << ", a disc's " << expected << std::endl;
      if (alpha == 0.0)
      {
        EXPECT_LT(width, 1.0); // the hard shadow's edge
      }
      else
      {
        EXPECT_NEAR(width, expected, 0.05 * expected);
      }
      EXPECT_GT(width, previous); // wider with the light's size
      previous = width;
    }
  }
}

TEST(SummedAreaTable, PenumbraOfAPointDiscWidensAsItsAnalyticShadow)
{
  // A point light of radius R 40 above EdgePlate's middle (at 60.5), above its edge: at
  // t = 40 below the plate, D = 80 from the light, the shadow's 10-90 % width is the disc's
  // penumbra R t / (D - t) times 2 DiscPenumbraHalfWidth. The hard shadow's edge is twice the
  // plate's blur there (about 1.6 units): the radii keep it under a third of the penumbra.
  const ClassifiedVolume v = EdgePlate();
  const double light[3] = { 47.5, 3.5, 100.5 };
  SphericalSAT table;
  table.Build(v, light, 0.5, 1);
  const double t = 40.0, D = 80.0;
  double previous = 0.0;
  for (const double radius : { 0.0, 4.0, 8.0, 12.0 })
  {
    const double width = PenumbraWidth(
      [&](double x)
      {
        const double p[3] = { x, 3.5, 60.5 - t };
        const double distance = std::sqrt(vtkMath::Distance2BetweenPoints(p, light));
        // Per unit of path across the plate: a slanted ray crosses more of it.
        return table.ConeFilteredOpticalDepth(
                 0, p, 0.25, 0.0, DiscSquareRatio * radius / distance) *
          (light[2] - p[2]) / distance;
      });
    const double expected = 2.0 * DiscPenumbraHalfWidth() * radius * t / (D - t);
    std::cout << "point light of radius " << radius << ": penumbra " << width << ", a disc's "
              << expected << std::endl;
    if (radius == 0.0)
    {
      EXPECT_LT(width, 2.0);
    }
    else
    {
      EXPECT_NEAR(width, expected, 0.05 * expected);
    }
    EXPECT_GT(width, previous);
    previous = width;
  }
}
