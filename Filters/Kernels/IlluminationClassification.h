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
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
/// (Stride, in values) and from a cell's first value to its next corner's along each axis
/// (Corner: 0 along a flat axis, whose cells have one point).
struct FieldLayout
{
  long long Stride[3] = { 0, 0, 0 };
  long long Corner[3] = { 0, 0, 0 };

  FieldLayout() = default;
  /// A field with `channels` values per grid point, x fastest.
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

/**
 * A classified value packed in 16 bits (ClassifiedVolume): the exponent and 10 mantissa bits
 * of a float below 2^-63 (its bits 13 to 28). Unpacking is a shift: 0 stays exactly 0, every
 * other value is a normal float in [2^-126, 2^-63) (an interpolation near 0 may give a
 * subnormal one, at most 2^-62 of the largest value). A volume stores each channel scaled by a
 * power of two into that range (ClassifiedVolume::Scale undoes it): 11 significant bits (rounding
 * within 2^-11, 0.05 %, of the value) over at least 61 binary orders of magnitude below the
 * channel's largest value; smaller values are stored as 0.
 */
using PackedValue = std::uint16_t;

/// The float a packed value holds (before its channel's scale).
inline float Unpack(PackedValue code)
{
  const std::uint32_t bits = static_cast<std::uint32_t>(code) << 13;
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}
/// Fields of floats read as they are.
inline float Unpack(float value)
{
  return value;
}

/// Trilinear interpolation in one cell of a field of floats or packed values (unpacked, not
/// scaled): q is the cell's first value, dx, dy and dz the offsets of the next value along
/// each axis (0 along a flat axis), f* the fractions.
template <typename T>
inline float TrilinearInCell(
  const T* q, long long dx, long long dy, long long dz, float fx, float fy, float fz);

/// TrilinearInCell for packed values whose next value along x follows in memory (dx 1, one
/// channel): the same result, the eight values read as four pairs and unpacked together
/// (with SSE2; elsewhere TrilinearInCell itself).
inline float TrilinearInPackedCell(
  const PackedValue* q, long long dy, long long dz, float fx, float fy, float fz);

/// TrilinearInCell reading only what a zero fraction leaves: the same value for finite
/// values (which classified volumes hold), from two values instead of eight for a sample on
/// a grid line (cell centres of a table in the data's frame, rays along a grid axis), at the
/// price of two branches.
template <typename T>
inline float TrilinearInCellSkippingZeros(
  const T* q, long long dx, long long dy, long long dz, float fx, float fy, float fz);

/// Channel c of a field with `channels` values per grid point, interpolated in a cell.
template <typename T>
inline float Interpolate(
  const GridGeometry& geometry, const T* field, int channels, const TrilinearCell& cell, int c);
/// Interpolate for packed values (TrilinearInPackedCell where it applies).
inline float Interpolate(const GridGeometry& geometry, const PackedValue* field, int channels,
  const TrilinearCell& cell, int c);

/// Optical properties per data point: the extinction coefficient sigma and, with chromatic
/// attenuation, k_c, the fraction of the step opacity that removes light of channel c
/// (1 - colour), interleaved as {sigma, k_r, k_g, k_b} (Channels 4). Without chromatic
/// attenuation every k_c is 1 and only sigma is stored (Channels 1). Values are packed in 16
/// bits (PackedValue: 2 bytes a point without chromatic attenuation): channel c's value is
/// Unpack(code) x Scale[c]. Kernels interpolate the unpacked values and fold the scale into
/// their step lengths.
struct VOLILLUMKERNELS_EXPORT ClassifiedVolume
{
  GridGeometry Geometry;
  int Channels = 4;
  LargeVector<PackedValue> Properties; // written right after allocation (LargeArrays.h)
  /// Per channel, the power of two an unpacked value is multiplied by (SetScales).
  std::array<float, 4> Scale{ { 1.0f, 1.0f, 1.0f, 1.0f } };

  /// Whether k_c may differ from 1 (Channels 4).
  bool IsChromatic() const { return this->Channels == 4; }

  /// Largest sigma a volume holds: larger values are stored as this (opaque over any step
  /// longer than 1e-16: an optical depth of 100 or more).
  static constexpr double MaximumSigma = 1e18;
  /// Smallest nonzero unpacked value (2^-126, the smallest normal float).
  static constexpr float SmallestPacked = std::numeric_limits<float>::min();

  /// Choose the scales for channel values up to largest[c] (sigma at most MaximumSigma, k_c
  /// at most 1) before packing.
  void SetScales(const double largest[4]);
  /// The code of `value` of channel c (0 <= value <= the largest SetScales was given;
  /// negative values and NaN give 0).
  PackedValue Pack(int c, double value) const
  {
    const float scaled = static_cast<float>(value / this->Scale[c]);
    if (!(scaled >= SmallestPacked))
    {
      return 0;
    }
    std::uint32_t bits;
    std::memcpy(&bits, &scaled, sizeof(bits));
    return static_cast<PackedValue>(std::min<std::uint32_t>((bits + 0x1000) >> 13, 0xffff));
  }
  /// Channel c of the value at index `index` of Properties, unpacked and scaled.
  float Value(size_t index) const
  {
    return Unpack(this->Properties[index]) * this->Scale[index % this->Channels];
  }
  /// Set the geometry's values from floats (Channels per point, x fastest): SetScales for
  /// their largest values, then Pack.
  void Store(const std::vector<float>& values);

  /// Step length h times Scale[0] (at most the largest float): multiplied by an unpacked,
  /// interpolated extinction it gives the optical depth of a step h.
  float ScaledStep(double h) const
  {
    return static_cast<float>(
      std::min(h * this->Scale[0], static_cast<double>(std::numeric_limits<float>::max())));
  }

  /// Extinction at grid point `point` (x fastest): Value of channel 0, without its modulo
  /// (EmptyBlocks reads every point).
  float Extinction(long long point) const
  {
    return Unpack(this->Properties[static_cast<size_t>(this->Channels * point)]) * this->Scale[0];
  }

  /// Trilinear interpolation of {sigma, k_r, k_g, k_b} at a world position (k_c 1 without
  /// chromatic attenuation); positions outside the grid are clamped onto it.
  void Sample(const double p[3], float out[4]) const;
  /// Sample for a cell of this volume's grid (CellAt).
  void SampleCell(const TrilinearCell& cell, float out[4]) const;

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

template <typename T>
inline float volillum::Interpolate(
  const GridGeometry& geometry, const T* field, int channels, const TrilinearCell& cell, int c)
{
  const FieldLayout layout(geometry, channels);
  const T* q = field + layout.Offset(cell.Index) + c;
  return TrilinearInCell(q, layout.Corner[0], layout.Corner[1], layout.Corner[2], cell.Fraction[0],
    cell.Fraction[1], cell.Fraction[2]);
}

inline float volillum::Interpolate(const GridGeometry& geometry, const PackedValue* field,
  int channels, const TrilinearCell& cell, int c)
{
  const FieldLayout layout(geometry, channels);
  const PackedValue* q = field + layout.Offset(cell.Index) + c;
  if (layout.Corner[0] == 1)
  {
    return TrilinearInPackedCell(
      q, layout.Corner[1], layout.Corner[2], cell.Fraction[0], cell.Fraction[1], cell.Fraction[2]);
  }
  return TrilinearInCell(q, layout.Corner[0], layout.Corner[1], layout.Corner[2], cell.Fraction[0],
    cell.Fraction[1], cell.Fraction[2]);
}

template <typename T>
inline float volillum::TrilinearInCell(
  const T* q, long long dx, long long dy, long long dz, float fx, float fy, float fz)
{
  auto at = [q](long long offset) { return Unpack(q[offset]); };
  const float c00 = at(0) + fx * (at(dx) - at(0));
  const float c10 = at(dy) + fx * (at(dy + dx) - at(dy));
  const float c01 = at(dz) + fx * (at(dz + dx) - at(dz));
  const float c11 = at(dz + dy) + fx * (at(dz + dy + dx) - at(dz + dy));
  const float c0 = c00 + fy * (c10 - c00);
  const float c1 = c01 + fy * (c11 - c01);
  return c0 + fz * (c1 - c0);
}

inline float volillum::TrilinearInPackedCell(
  const PackedValue* q, long long dy, long long dz, float fx, float fy, float fz)
{
#if defined(__SSE2__)
  // Lanes hold the values TrilinearInCell combines, combined by the same operations: the
  // same result to the bit.
  auto pair = [q](long long offset)
  {
    std::int32_t both;
    std::memcpy(&both, q + offset, sizeof(both));
    return _mm_cvtsi32_si128(both);
  };
  const __m128i codes = _mm_unpacklo_epi64(
    _mm_unpacklo_epi32(pair(0), pair(dy)), _mm_unpacklo_epi32(pair(dz), pair(dz + dy)));
  const __m128i zero = _mm_setzero_si128();
  // q[0], q[dx], q[dy], q[dy + dx] and the same from q[dz].
  const __m128 planeZ0 = _mm_castsi128_ps(_mm_slli_epi32(_mm_unpacklo_epi16(codes, zero), 13));
  const __m128 planeZ1 = _mm_castsi128_ps(_mm_slli_epi32(_mm_unpackhi_epi16(codes, zero), 13));
  const __m128 first = _mm_shuffle_ps(planeZ0, planeZ1, _MM_SHUFFLE(2, 0, 2, 0));
  const __m128 next = _mm_shuffle_ps(planeZ0, planeZ1, _MM_SHUFFLE(3, 1, 3, 1));
  // c00, c10, c01, c11, then c0, c1.
  const __m128 x = _mm_add_ps(first, _mm_mul_ps(_mm_set1_ps(fx), _mm_sub_ps(next, first)));
  const __m128 low = _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 0, 2, 0));
  const __m128 high = _mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 1, 3, 1));
  const __m128 y = _mm_add_ps(low, _mm_mul_ps(_mm_set1_ps(fy), _mm_sub_ps(high, low)));
  const float c0 = _mm_cvtss_f32(y);
  const float c1 = _mm_cvtss_f32(_mm_shuffle_ps(y, y, _MM_SHUFFLE(1, 1, 1, 1)));
  return c0 + fz * (c1 - c0);
#else
  return TrilinearInCell(q, 1, dy, dz, fx, fy, fz);
#endif
}

template <typename T>
inline float volillum::TrilinearInCellSkippingZeros(
  const T* q, long long dx, long long dy, long long dz, float fx, float fy, float fz)
{
  // Bilinear in the plane through r (linear along x where fy is 0).
  auto plane = [=](const T* r)
  {
    auto at = [r](long long offset) { return Unpack(r[offset]); };
    const float c0 = fx == 0.0f ? at(0) : at(0) + fx * (at(dx) - at(0));
    if (fy == 0.0f)
    {
      return c0;
    }
    const float c1 = fx == 0.0f ? at(dy) : at(dy) + fx * (at(dy + dx) - at(dy));
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
