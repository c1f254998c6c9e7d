#include "IlluminationLights.h"

#include "vtkLight.h"
#include "vtkMath.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

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

//------------------------------------------------------------------------------
bool LightList::Add(vtkLight* light)
{
  if (!light)
  {
    return false;
  }
  this->Lights.emplace_back(light);
  return true;
}

//------------------------------------------------------------------------------
bool LightList::Clear()
{
  const bool had = !this->Lights.empty();
  this->Lights.clear();
  return had;
}

//------------------------------------------------------------------------------
vtkLight* LightList::Get(int index) const
{
  return index >= 0 && index < this->Size() ? this->Lights[index].Get() : nullptr;
}

//------------------------------------------------------------------------------
bool LightList::SetNumberOfParameters(int count, bool& changed)
{
  changed = false;
  if (count < 0 || count % LightParameterCount != 0)
  {
    return false;
  }
  const size_t lights = static_cast<size_t>(count / LightParameterCount);
  changed = lights != this->Lights.size();
  while (this->Lights.size() < lights)
  {
    this->Lights.push_back(vtkSmartPointer<vtkLight>::New());
  }
  this->Lights.resize(lights);
  return true;
}

//------------------------------------------------------------------------------
bool LightList::SetParameter(int index, double value)
{
  const int light = index / LightParameterCount;
  if (index < 0 || light >= this->Size())
  {
    return false;
  }
  double p[LightParameterCount];
  GetLightParameters(this->Lights[light], p);
  p[index % LightParameterCount] = value;
  // vtkLight marks itself modified only for values that change.
  ApplyLightParameters(this->Lights[light], p);
  return true;
}

//------------------------------------------------------------------------------
double LightList::GetParameter(int index) const
{
  const int light = index / LightParameterCount;
  if (index < 0 || light >= this->Size())
  {
    return 0.0;
  }
  double p[LightParameterCount];
  GetLightParameters(this->Lights[light], p);
  return p[index % LightParameterCount];
}

//------------------------------------------------------------------------------
std::vector<LightState> LightList::States() const
{
  std::vector<LightState> states;
  states.reserve(this->Lights.size());
  for (const auto& light : this->Lights)
  {
    states.push_back(CaptureLight(light));
  }
  return states;
}

//------------------------------------------------------------------------------
vtkMTimeType LightList::GetMTime() const
{
  vtkMTimeType t = 0;
  for (const auto& light : this->Lights)
  {
    t = std::max(t, light->GetMTime());
  }
  return t;
}

//------------------------------------------------------------------------------
std::string LightList::Validate() const
{
  std::ostringstream message;
  for (int i = 0; i < this->Size(); ++i)
  {
    double p[LightParameterCount];
    GetLightParameters(this->Lights[i], p);
    for (double v : p)
    {
      if (!std::isfinite(v))
      {
        message << "Light " << i << " has a parameter that is not a finite number.";
        return message.str();
      }
    }
    if (CaptureLight(this->Lights[i]).Intensity < 0.0)
    {
      message << "Light " << i << " has a negative intensity.";
      return message.str();
    }
  }
  return std::string();
}

}
