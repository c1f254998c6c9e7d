/**
 * @file IlluminationClassification.h
 * @brief The optical properties light propagation needs (a classified volume) and the
 * geometry of an illumination volume.
 *
 * IlluminationClassify.h fills a ClassifiedVolume from VTK scalars and transfer functions.
 * The optical model is the emission-absorption model of N. Max, "Optical Models for Direct
 * Volume Rendering", IEEE Transactions on Visualization and Computer Graphics 1(2), 1995.
 * Classification follows vtkVolumeProperty: the scalar opacity function gives the opacity
 * of a sample one "scalar opacity unit distance" thick, so the extinction coefficient is
 * sigma = -ln(1 - opacity) / unitDistance and a step of length dt has the step-corrected
 * opacity a = 1 - exp(-sigma dt). With chromatic attenuation, light passing a step keeps
 * l_out = l_in (1 - a (1 - c)) per channel, c being the colour transfer function's colour
 * (Documentation/design.md); without it l_out = l_in (1 - a).
 */
#ifndef IlluminationClassification_h
#define IlluminationClassification_h

#include "LargeArrays.h"
#include "VolIllumKernelsModule.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace volillum
{

/// Points, origin and spacing of a regular grid.
struct VOLILLUMKERNELS_EXPORT GridGeometry
{
  std::array<int, 3> Dimensions{ { 0, 0, 0 } };
  std::array<double, 3> Origin{ { 0.0, 0.0, 0.0 } };
  std::array<double, 3> Spacing{ { 1.0, 1.0, 1.0 } };

  long long NumberOfPoints() const
  {
    return static_cast<long long>(this->Dimensions[0]) * this->Dimensions[1] * this->Dimensions[2];
  }
  void GetBounds(double bounds[6]) const;
  /// The smallest spacing (absolute value) of the three axes.
  double MinimumSpacing() const
  {
    return std::min(
      std::abs(this->Spacing[0]), std::min(std::abs(this->Spacing[1]), std::abs(this->Spacing[2])));
  }
  void PointPosition(long long i, long long j, long long k, double p[3]) const
  {
    p[0] = this->Origin[0] + i * this->Spacing[0];
    p[1] = this->Origin[1] + j * this->Spacing[1];
    p[2] = this->Origin[2] + k * this->Spacing[2];
  }
};

/// The illumination grid at a resolution scale (1, 1/2 or 1/4 per axis) covering the same
/// bounds as the data grid: the first and last points coincide with the data's.
VOLILLUMKERNELS_EXPORT GridGeometry ScaledGeometry(const GridGeometry& data, double scale);

/// Where the values of a point field on a grid lie: from a point to the next along each axis
/// (Stride, in floats) and from a cell's first value to its next corner's along each axis
/// (Corner: 0 along a flat axis, whose cells have one point).
struct FieldLayout
{
  long long Stride[3] = { 0, 0, 0 };
  long long Corner[3] = { 0, 0, 0 };

  FieldLayout() = default;
  /// A field with `channels` floats per grid point, x fastest.
  FieldLayout(const GridGeometry& geometry, int channels)
    : FieldLayout(geometry,
        { channels, channels * static_cast<long long>(geometry.Dimensions[0]),
          channels * static_cast<long long>(geometry.Dimensions[0]) * geometry.Dimensions[1] })
  {
  }
  /// A field on the grid with the given strides.
  FieldLayout(const GridGeometry& geometry, const std::array<long long, 3>& stride)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->Stride[a] = stride[a];
      this->Corner[a] = geometry.Dimensions[a] > 1 ? stride[a] : 0;
    }
  }
  /// Offset of the first value of the cell whose first point has the given indices.
  long long Offset(const int index[3]) const
  {
    return index[0] * this->Stride[0] + index[1] * this->Stride[1] + index[2] * this->Stride[2];
  }
};

/// Trilinear interpolation of a point field with `channels` floats per grid point (x
/// fastest) at a world position; positions outside the grid are clamped onto it.
VOLILLUMKERNELS_EXPORT void TrilinearSample(
  const GridGeometry& geometry, const float* field, int channels, const double p[3], float* out);

/// The grid cell a trilinear sample reads (the index of its first point per axis) and the
/// sample's fractions in it.
struct TrilinearCell
{
  int Index[3];
  float Fraction[3];
};

/// The cell of a sample at grid coordinates u ((position - origin) / spacing per axis),
/// clamped onto the grid, as TrilinearSample reads it; for kernels that step through the grid
/// in grid coordinates.
inline TrilinearCell CellAt(const GridGeometry& geometry, const double u[3]);

/// CellAt for a sample at world position p.
inline TrilinearCell CellAtPosition(const GridGeometry& geometry, const double p[3]);

/// CellAt along one axis of n points: the cell's first point and the sample's fraction in it.
inline void AxisCell(int n, double u, int& index, float& fraction);

/// Trilinear interpolation in one cell of a float field: q is the cell's first value, dx, dy
/// and dz the offsets of the next value along each axis (0 along a flat axis), f* the
/// fractions.
inline float TrilinearInCell(
  const float* q, long long dx, long long dy, long long dz, float fx, float fy, float fz);

/// TrilinearInCell reading only what a zero fraction leaves: the same value for finite
/// values (which classified volumes hold), from two values instead of eight for a sample on
/// a grid line (cell centres of a table in the data's frame, rays along a grid axis), at the
/// price of two branches.
inline float TrilinearInCellSkippingZeros(
  const float* q, long long dx, long long dy, long long dz, float fx, float fy, float fz);

/// Channel c of a field with `channels` floats per grid point, interpolated in a cell.
inline float Interpolate(
  const GridGeometry& geometry, const float* field, int channels, const TrilinearCell& cell, int c);

/// Optical properties per data point: the extinction coefficient sigma and, with chromatic
/// attenuation, k_c, the fraction of the step opacity that removes light of channel c
/// (1 - colour), interleaved as {sigma, k_r, k_g, k_b} (Channels 4). Without chromatic
/// attenuation every k_c is 1 and only sigma is stored (Channels 1: 4 bytes a point).
struct VOLILLUMKERNELS_EXPORT ClassifiedVolume
{
  GridGeometry Geometry;
  int Channels = 4;
  LargeVector<float> Properties; // written right after allocation (LargeArrays.h)

  /// Whether k_c may differ from 1 (Channels 4).
  bool IsChromatic() const { return this->Channels == 4; }

  /// Extinction at grid point `point` (x fastest).
  float Extinction(long long point) const
  {
    return this->Properties[static_cast<size_t>(this->Channels * point)];
  }

  /// Trilinear interpolation of {sigma, k_r, k_g, k_b} at a world position (k_c 1 without
  /// chromatic attenuation); positions outside the grid are clamped onto it.
  void Sample(const double p[3], float out[4]) const;

  /// Largest sigma in the volume (0 for an empty one).
  float MaxExtinction() const;
};

/// Relative tolerance of the kernels' geometric comparisons: coordinates, lengths and step
/// counts within this fraction of their scale are taken as equal (the rounding of a few
/// double operations stays far below it, a real difference far above).
constexpr double GeometricTolerance = 1e-9;

/// Opacities of exactly 1 would make sigma infinite; they are clamped to this value.
constexpr double MaximumOpacity = 1.0 - 1e-6;

/// Step-corrected opacity of a step of length dt through a medium of extinction sigma.
inline double StepOpacity(double sigma, double dt);

/// Distance from p along the unit direction d to where the ray leaves the box bounds
/// (0 when p is outside and moving away).
VOLILLUMKERNELS_EXPORT double DistanceToBoxExit(
  const double p[3], const double d[3], const double bounds[6]);

}

#include <cmath>

inline volillum::TrilinearCell volillum::CellAt(const GridGeometry& geometry, const double u[3])
{
  TrilinearCell cell;
  for (int a = 0; a < 3; ++a)
  {
    AxisCell(geometry.Dimensions[a], u[a], cell.Index[a], cell.Fraction[a]);
  }
  return cell;
}

inline volillum::TrilinearCell volillum::CellAtPosition(
  const GridGeometry& geometry, const double p[3])
{
  const double u[3] = { (p[0] - geometry.Origin[0]) / geometry.Spacing[0],
    (p[1] - geometry.Origin[1]) / geometry.Spacing[1],
    (p[2] - geometry.Origin[2]) / geometry.Spacing[2] };
  return CellAt(geometry, u);
}

inline void volillum::AxisCell(int n, double u, int& index, float& fraction)
{
  const double c = std::min(std::max(u, 0.0), static_cast<double>(n - 1));
  index = std::min(static_cast<int>(c), std::max(n - 2, 0));
  fraction = n > 1 ? static_cast<float>(c - index) : 0.0f;
}

inline float volillum::Interpolate(
  const GridGeometry& geometry, const float* field, int channels, const TrilinearCell& cell, int c)
{
  const FieldLayout layout(geometry, channels);
  const float* q = field + layout.Offset(cell.Index) + c;
  return TrilinearInCell(q, layout.Corner[0], layout.Corner[1], layout.Corner[2], cell.Fraction[0],
    cell.Fraction[1], cell.Fraction[2]);
}

inline float volillum::TrilinearInCell(
  const float* q, long long dx, long long dy, long long dz, float fx, float fy, float fz)
{
  const float c00 = q[0] + fx * (q[dx] - q[0]);
  const float c10 = q[dy] + fx * (q[dy + dx] - q[dy]);
  const float c01 = q[dz] + fx * (q[dz + dx] - q[dz]);
  const float c11 = q[dz + dy] + fx * (q[dz + dy + dx] - q[dz + dy]);
  const float c0 = c00 + fy * (c10 - c00);
  const float c1 = c01 + fy * (c11 - c01);
  return c0 + fz * (c1 - c0);
}

inline float volillum::TrilinearInCellSkippingZeros(
  const float* q, long long dx, long long dy, long long dz, float fx, float fy, float fz)
{
  // Bilinear in the plane through r (linear along x where fy is 0).
  auto plane = [=](const float* r)
  {
    const float c0 = fx == 0.0f ? r[0] : r[0] + fx * (r[dx] - r[0]);
    if (fy == 0.0f)
    {
      return c0;
    }
    const float c1 = fx == 0.0f ? r[dy] : r[dy] + fx * (r[dy + dx] - r[dy]);
    return c0 + fy * (c1 - c0);
  };
  const float c0 = plane(q);
  return fz == 0.0f ? c0 : c0 + fz * (plane(q + dz) - c0);
}

inline double volillum::StepOpacity(double sigma, double dt)
{
  return 1.0 - std::exp(-sigma * dt);
}

#endif
