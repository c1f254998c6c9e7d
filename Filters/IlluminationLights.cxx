#include "IlluminationLights.h"

#include "vtkLight.h"
#include "vtkMath.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{

std::array<double, 3> LightState::Direction() const
{
  std::array<double, 3> d{ { this->FocalPoint[0] - this->Position[0],
    this->FocalPoint[1] - this->Position[1], this->FocalPoint[2] - this->Position[2] } };
  const double n = vtkMath::Norm(d.data());
  if (n > 0.0)
  {
    d[0] /= n;
    d[1] /= n;
    d[2] /= n;
  }
  else
  {
    // A light whose position equals its focal point shines along -z, as a headlight would.
    d = { { 0.0, 0.0, -1.0 } };
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
    this->Exponent == o.Exponent && this->On == o.On;
}

LightState CaptureLight(vtkLight* light)
{
  LightState s;
  if (!light->GetPositional())
  {
    s.Kind = LightKind::Directional;
  }
  else
  {
    s.Kind = light->GetConeAngle() >= 90.0 ? LightKind::Point : LightKind::Spot;
  }
  light->GetPosition(s.Position.data());
  light->GetFocalPoint(s.FocalPoint.data());
  light->GetDiffuseColor(s.Color.data());
  s.Intensity = light->GetIntensity();
  s.ConeAngle = light->GetConeAngle();
  s.Exponent = light->GetExponent();
  s.On = light->GetSwitch() != 0;
  return s;
}

void ApplyLightParameters(vtkLight* light, const double* p)
{
  light->SetPositional(p[0] != 0.0);
  light->SetPosition(p[1], p[2], p[3]);
  light->SetFocalPoint(p[4], p[5], p[6]);
  light->SetDiffuseColor(p[7], p[8], p[9]);
  light->SetIntensity(p[10]);
  light->SetConeAngle(p[11]);
  light->SetExponent(p[12]);
  light->SetSwitch(p[13] != 0.0);
}

void GetLightParameters(vtkLight* light, double* p)
{
  p[0] = light->GetPositional();
  light->GetPosition(p + 1);
  light->GetFocalPoint(p + 4);
  light->GetDiffuseColor(p + 7);
  p[10] = light->GetIntensity();
  p[11] = light->GetConeAngle();
  p[12] = light->GetExponent();
  p[13] = light->GetSwitch();
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
    const double cosCone = std::cos(vtkMath::RadiansFromDegrees(light.ConeAngle));
    if (inc.Distance == 0.0)
    {
      inc.ConeFactor = 1.0;
    }
    else if (cosAngle < cosCone)
    {
      inc.ConeFactor = 0.0;
    }
    else
    {
      inc.ConeFactor = std::pow(std::max(cosAngle, 0.0), light.Exponent);
    }
  }
  return inc;
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
