/**
 * @file IlluminationLights.h
 * @brief Plain C++ description of the lights every illumination filter uses.
 *
 * The filters accept VTK's own vtkLight (IlluminationLightList.h converts it; see
 * Documentation/design.md): a non-positional light is directional (it shines from its
 * position toward its focal point), a positional light with a cone angle of 90 degrees or
 * more is a point light and one with a smaller cone angle a spot light. LightState is a value
 * snapshot of one light so that a filter can compare what it last applied with what the user
 * has now, parameter by parameter, instead of trusting modification times.
 */
#ifndef IlluminationLights_h
#define IlluminationLights_h

#include "VolIllumKernelsModule.h"

#include <array>
#include <vector>

namespace volillum
{

enum class LightKind
{
  Directional,
  Point,
  Spot
};

/// Number of values per light in the flat parameter list of the pvpython API:
/// positional, position xyz, focal point xyz, colour rgb, intensity, cone angle,
/// exponent, switch, radius.
constexpr int LightParameterCount = 15;

/// The lists written before the radius: the first 14 of those values (radius 0).
constexpr int LegacyLightParameterCount = 14;

/// Values per light of a flat list of `count` values: LightParameterCount, or
/// LegacyLightParameterCount for a list that is whole lights of that layout only (so a list
/// of a multiple of 210 values is read as 15 a light).
inline int LightParametersPerLight(int count)
{
  return count % LightParameterCount != 0 && count % LegacyLightParameterCount == 0
    ? LegacyLightParameterCount
    : LightParameterCount;
}

struct VOLILLUMKERNELS_EXPORT LightState
{
  LightKind Kind = LightKind::Directional;
  std::array<double, 3> Position{ { 0.0, 0.0, 1.0 } };
  std::array<double, 3> FocalPoint{ { 0.0, 0.0, 0.0 } };
  std::array<double, 3> Color{ { 1.0, 1.0, 1.0 } };
  double Intensity = 1.0;
  double ConeAngle = 30.0;
  double Exponent = 1.0;
  bool On = true;
  /// The light's size (the Lights' 15th number, the Light Inspector's Shadow Radius): the
  /// apparent (angular) diameter in degrees of a directional light, the radius in world
  /// units of a point or spot light's disc facing the point it lights. 0: a hard light.
  /// Filtered shadows soften with it.
  double Radius = 0.0;

  /// Unit vector from the position toward the focal point (the direction light travels
  /// for a directional light, the cone axis of a spot light).
  std::array<double, 3> Direction() const;

  /// Radiance this light contributes per channel when nothing occludes it.
  std::array<double, 3> Radiance() const;

  bool operator==(const LightState& other) const;
  bool operator!=(const LightState& other) const { return !(*this == other); }
};

/// Half-width of the square whose shadow edge spreads as a disc's of radius 1 does: the
/// square with the disc's second moment (sqrt(3) / 2), so that the penumbra's width from 10 %
/// to 90 % is within 1 % of the disc's.
constexpr double DiscSquareRatio = 0.8660254037844386;

/// How fast the shadow cone toward a directional light of this angular diameter (degrees,
/// LightState::Radius) widens: the half-width of its square (DiscSquareRatio of the disc's
/// radius) per unit of distance. 0 for a hard light.
VOLILLUMKERNELS_EXPORT double DirectionalConeSpread(double angularDiameter);

/// Light arriving at a point before any attenuation: the unit direction toward the
/// light, how far light has to travel to reach the point (infinite for a directional
/// light) and the spot-cone factor (1 outside spot lights, 0 outside the cone).
struct Incidence
{
  std::array<double, 3> ToLight;
  double Distance;
  double ConeFactor;
};

VOLILLUMKERNELS_EXPORT Incidence ComputeIncidence(const LightState& light, const double point[3]);

/// Brightest light accepted (colour x intensity per channel): keeps sums of light, and the
/// fixed-point scales chosen from them (FixedPointIllumination), far from overflow.
constexpr double MaximumRadiance = 1e6;

/// A point or spot light farther than this many volume diagonals from the volume's centre
/// is a far light: ForBounds makes it a directional light.
constexpr double FarLightDistance = 1e4;

/**
 * The lights as the kernels see them for a volume with these bounds: a directional light
 * keeps its direction (computed without overflow, however large its coordinates) with a
 * position one unit from the centre; a point or spot light farther than FarLightDistance
 * diagonals becomes a directional light shining from where it is toward the centre (a spot
 * light's intensity takes its cone factor at the centre, its radius becomes the angle it
 * subtends there); a nearer spot light's focal
 * point becomes its position plus its unit axis.
 */
VOLILLUMKERNELS_EXPORT std::vector<LightState> ForBounds(
  const std::vector<LightState>& lights, const double bounds[6]);

/// True when the light position lies inside the axis-aligned box bounds
/// (xmin, xmax, ymin, ymax, zmin, zmax). Directional lights are never inside.
VOLILLUMKERNELS_EXPORT bool IsLightInside(const LightState& light, const double bounds[6]);

/**
 * Remembers the light states a filter applied last and tells which lights changed
 * since then. Lights are matched by their index in the list.
 */
class VOLILLUMKERNELS_EXPORT LightChangeTracker
{
public:
  /// Indices whose state differs from the applied state, including lights that were
  /// added or removed since (indices beyond the shorter list).
  std::vector<int> ChangedLights(const std::vector<LightState>& current) const;

  /// Remember the states as applied.
  void Commit(const std::vector<LightState>& applied) { this->Applied = applied; }
  void Reset() { this->Applied.clear(); }
  const std::vector<LightState>& GetApplied() const { return this->Applied; }

private:
  std::vector<LightState> Applied;
};

}

#endif
