#include "IlluminationLights.h"

#include "vtkMath.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{

namespace
{
// The difference b - a without overflow: the halves of the coordinates are subtracted
// (that cannot overflow) and divided by the largest component, which is returned as the
// scale (0 when a equals b): b - a = 2 x scale x d.
double ScaledDifference(const double a[3], const double b[3], double d[3])
{
  double scale = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    d[i] = 0.5 * b[i] - 0.5 * a[i];
    scale = std::max(scale, std::abs(d[i]));
  }
  for (int i = 0; scale > 0.0 && i < 3; ++i)
  {
    d[i] /= scale;
  }
  return scale;
}

// Unit vector from a toward b; ok is false when a equals b.
std::array<double, 3> UnitVector(const double a[3], const double b[3], bool& ok)
{
  double d[3];
  ok = ScaledDifference(a, b, d) > 0.0;
  if (!ok)
  {
    return { { 0.0, 0.0, 0.0 } };
  }
  const double n = vtkMath::Norm(d);
  return { { d[0] / n, d[1] / n, d[2] / n } };
}

// Spot-cone factor for a ray leaving the light at an angle of cosine cosAngle to its axis.
double SpotFactor(const LightState& light, double cosAngle)
{
  const double cosCone = std::cos(vtkMath::RadiansFromDegrees(light.ConeAngle));
  return cosAngle < cosCone ? 0.0 : std::pow(std::max(cosAngle, 0.0), light.Exponent);
}

// Distance from a to b (infinite only beyond the double range).
double Distance(const double a[3], const double b[3])
{
  double d[3];
  const double scale = ScaledDifference(a, b, d);
  return scale > 0.0 ? 2.0 * scale * vtkMath::Norm(d) : 0.0;
}
}

std::array<double, 3> LightState::Direction() const
{
  bool ok;
  const auto d = UnitVector(this->Position.data(), this->FocalPoint.data(), ok);
  if (!ok)
  {
    // A light whose position equals its focal point shines along -z, as a headlight would.
    return { { 0.0, 0.0, -1.0 } };
  }
  return d;
}

std::array<double, 3> LightState::Radiance() const
{
  if (!this->On)
  {
    return { { 0.0, 0.0, 0.0 } };
  }
  return { { this->Color[0] * this->Intensity, this->Color[1] * this->Intensity,
    this->Color[2] * this->Intensity } };
}

bool LightState::operator==(const LightState& o) const
{
  return this->Kind == o.Kind && this->Position == o.Position && this->FocalPoint == o.FocalPoint &&
    this->Color == o.Color && this->Intensity == o.Intensity && this->ConeAngle == o.ConeAngle &&
    this->Exponent == o.Exponent && this->On == o.On && this->Radius == o.Radius;
}

double DirectionalConeSpread(double angularDiameter)
{
  const double half = 0.5 * vtkMath::RadiansFromDegrees(std::min(angularDiameter, 179.0));
  return angularDiameter > 0.0 ? DiscSquareRatio * std::tan(half) : 0.0;
}

Incidence ComputeIncidence(const LightState& light, const double point[3])
{
  Incidence inc;
  inc.ConeFactor = 1.0;
  if (light.Kind == LightKind::Directional)
  {
    const auto d = light.Direction();
    inc.ToLight = { { -d[0], -d[1], -d[2] } };
    inc.Distance = std::numeric_limits<double>::infinity();
    return inc;
  }
  std::array<double, 3> v{ { light.Position[0] - point[0], light.Position[1] - point[1],
    light.Position[2] - point[2] } };
  inc.Distance = vtkMath::Norm(v.data());
  if (inc.Distance > 0.0)
  {
    inc.ToLight = { { v[0] / inc.Distance, v[1] / inc.Distance, v[2] / inc.Distance } };
  }
  else
  {
    inc.ToLight = { { 0.0, 0.0, 1.0 } };
  }
  if (light.Kind == LightKind::Spot)
  {
    const auto axis = light.Direction();
    // Cosine between the cone axis and the ray leaving the light toward the point.
    const double cosAngle = -vtkMath::Dot(axis.data(), inc.ToLight.data());
    inc.ConeFactor = inc.Distance == 0.0 ? 1.0 : SpotFactor(light, cosAngle);
  }
  return inc;
}

std::vector<LightState> ForBounds(const std::vector<LightState>& lights, const double bounds[6])
{
  double centre[3], diagonal = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    diagonal += (bounds[2 * a + 1] - bounds[2 * a]) * (bounds[2 * a + 1] - bounds[2 * a]);
  }
  diagonal = diagonal > 0.0 ? std::sqrt(diagonal) : 1.0;
  const double farthest = FarLightDistance * diagonal;
  // A directional light shining along travel, positioned one unit from the centre.
  const auto makeDirectional = [&centre](LightState& l, const std::array<double, 3>& travel)
  {
    l.Kind = LightKind::Directional;
    for (int a = 0; a < 3; ++a)
    {
      l.FocalPoint[a] = centre[a];
      l.Position[a] = centre[a] - travel[a];
    }
  };
  std::vector<LightState> tamed = lights;
  for (LightState& light : tamed)
  {
    const auto direction = light.Direction();
    if (light.Kind == LightKind::Directional)
    {
      makeDirectional(light, direction); // only the direction matters
      continue;
    }
    if (Distance(centre, light.Position.data()) > farthest)
    {
      // A far light: its rays are parallel across the volume. A spot light keeps the cone
      // factor it has at the centre.
      bool ok;
      const auto travel = UnitVector(light.Position.data(), centre, ok);
      if (light.Kind == LightKind::Spot)
      {
        light.Intensity *= SpotFactor(light, vtkMath::Dot(travel.data(), direction.data()));
      }
      light.Radius = vtkMath::DegreesFromRadians(
        2.0 * std::atan(light.Radius / Distance(centre, light.Position.data())));
      makeDirectional(light, travel);
      continue;
    }
    for (int a = 0; a < 3; ++a)
    {
      light.FocalPoint[a] = light.Position[a] + direction[a];
    }
  }
  return tamed;
}

bool IsLightInside(const LightState& light, const double bounds[6])
{
  if (light.Kind == LightKind::Directional)
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (light.Position[a] < bounds[2 * a] || light.Position[a] > bounds[2 * a + 1])
    {
      return false;
    }
  }
  return true;
}

std::vector<int> LightChangeTracker::ChangedLights(const std::vector<LightState>& current) const
{
  std::vector<int> changed;
  const size_t n = std::max(current.size(), this->Applied.size());
  for (size_t i = 0; i < n; ++i)
  {
    if (i >= current.size() || i >= this->Applied.size() || current[i] != this->Applied[i])
    {
      changed.push_back(static_cast<int>(i));
    }
  }
  return changed;
}

}
