/**
 * @file IlluminationClassification.h
 * @brief Turns scalars and transfer functions into the optical properties light
 * propagation needs, and describes the geometry of an illumination volume.
 *
 * Classification follows vtkVolumeProperty: the scalar opacity function gives the opacity
 * of a sample one "scalar opacity unit distance" thick, so the extinction coefficient is
 * sigma = -ln(1 - opacity) / unitDistance and a step of length dt has the step-corrected
 * opacity a = 1 - exp(-sigma dt). With chromatic attenuation, light passing a step keeps
 * l_out = l_in (1 - a (1 - c)) per channel, c being the colour transfer function's colour
 * (DESIGN.md); without it l_out = l_in (1 - a).
 */
#ifndef IlluminationClassification_h
#define IlluminationClassification_h

#include "VolIllumFiltersModule.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

class vtkColorTransferFunction;
class vtkDataArray;
class vtkPiecewiseFunction;

namespace volillum
{

/// Points, origin and spacing of a regular grid.
struct VOLILLUMFILTERS_EXPORT GridGeometry
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
VOLILLUMFILTERS_EXPORT GridGeometry ScaledGeometry(const GridGeometry& data, double scale);

/// Trilinear interpolation of a point field with `channels` floats per grid point (x
/// fastest) at a world position; positions outside the grid are clamped onto it.
VOLILLUMFILTERS_EXPORT void TrilinearSample(
  const GridGeometry& geometry, const float* field, int channels, const double p[3], float* out);

/// Optical properties per data point, interleaved as {sigma, k_r, k_g, k_b} where sigma is
/// the extinction coefficient and k_c the fraction of the step opacity that removes light of
/// channel c (1 - colour with chromatic attenuation, 1 without).
struct VOLILLUMFILTERS_EXPORT ClassifiedVolume
{
  GridGeometry Geometry;
  std::vector<float> Properties;

  /// Trilinear interpolation of the four properties at a world position; positions outside
  /// the grid are clamped onto it.
  void Sample(const double p[3], float out[4]) const;

  /// Largest sigma in the volume (0 for an empty one).
  float MaxExtinction() const;
};

/// Settings of classification.
struct ClassificationSettings
{
  vtkColorTransferFunction* Color = nullptr;
  vtkPiecewiseFunction* Opacity = nullptr;
  double UnitDistance = 1.0;
  bool Chromatic = true;
  int Component = 0;
};

/// Opacities of exactly 1 would make sigma infinite; they are clamped to this value.
constexpr double MaximumOpacity = 1.0 - 1e-6;

/**
 * Classify the scalars (any numeric type; NaN counts as empty space). Without transfer
 * functions a grey ramp over the scalar range applies: colour and opacity rise linearly
 * from 0 at the minimum to 1 at the maximum. Returns false with a message in error when
 * the input cannot be classified.
 */
VOLILLUMFILTERS_EXPORT bool Classify(vtkDataArray* scalars, const GridGeometry& geometry,
  const ClassificationSettings& settings, ClassifiedVolume& out, std::string& error,
  long long* nanCount = nullptr);

/// Step-corrected opacity of a step of length dt through a medium of extinction sigma.
inline double StepOpacity(double sigma, double dt);

/// Distance from p along the unit direction d to where the ray leaves the box bounds
/// (0 when p is outside and moving away).
VOLILLUMFILTERS_EXPORT double DistanceToBoxExit(
  const double p[3], const double d[3], const double bounds[6]);

}

#include <cmath>
inline double volillum::StepOpacity(double sigma, double dt)
{
  return 1.0 - std::exp(-sigma * dt);
}

#endif
