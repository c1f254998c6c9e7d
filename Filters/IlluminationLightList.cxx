#include "IlluminationLightList.h"

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkLight.h"
#include "vtkNew.h"

#include <cmath>
#include <sstream>

namespace volillum
{

namespace
{
// The key of a light's size in its vtkInformation.
vtkInformationDoubleKey* RadiusKey()
{
  static vtkInformationDoubleKey* key =
    new vtkInformationDoubleKey("VOLILLUM_LIGHT_RADIUS", "volillum::LightList");
  return key;
}
}

double GetLightRadius(vtkLight* light)
{
  vtkInformation* info = light->GetInformation();
  return info && info->Has(RadiusKey()) ? info->Get(RadiusKey()) : 0.0;
}

void SetLightRadius(vtkLight* light, double radius)
{
  if (GetLightRadius(light) == radius)
  {
    return;
  }
  if (!light->GetInformation())
  {
    vtkNew<vtkInformation> info;
    light->SetInformation(info);
  }
  light->GetInformation()->Set(RadiusKey(), radius);
  light->Modified();
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
  s.Radius = GetLightRadius(light);
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
  SetLightRadius(light, p[14]);
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
  p[14] = GetLightRadius(light);
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
  const bool had = !this->Lights.empty() || this->IncompleteCount >= 0;
  this->Lights.clear();
  this->IncompleteCount = -1;
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
  if (count < 0)
  {
    return false;
  }
  if (count % LightParameterCount != 0)
  {
    changed = this->IncompleteCount != count;
    this->IncompleteCount = count;
    return false;
  }
  changed = this->IncompleteCount >= 0;
  this->IncompleteCount = -1;
  const size_t lights = static_cast<size_t>(count / LightParameterCount);
  changed = changed || lights != this->Lights.size();
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
  if (this->IncompleteCount >= 0)
  {
    message << "The light list has " << this->IncompleteCount << " numbers, not a whole number "
            << "of lights: each light takes " << LightParameterCount << " ("
            << this->IncompleteCount % LightParameterCount << " left over).";
    return message.str();
  }
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
    const LightState state = CaptureLight(this->Lights[i]);
    // (A light that is off lights nothing: ParaView's lights table adds a row of zeros.)
    const bool aimless = state.On && state.Position == state.FocalPoint;
    if (state.Kind == LightKind::Directional && aimless)
    {
      message << "Light " << i << " is directional but has no direction: its position equals "
              << "its focal point.";
      return message.str();
    }
    if (state.On && state.Kind == LightKind::Spot && state.ConeAngle <= 0.0)
    {
      message << "Light " << i << " has a cone angle of " << state.ConeAngle
              << " degrees; a spot light needs one above 0 (90 or more: a point light).";
      return message.str();
    }
    if (state.Kind == LightKind::Spot && aimless)
    {
      message << "Light " << i << " is a spot light (cone angle below 90) but has no "
              << "direction: its focal point equals its position.";
      return message.str();
    }
    if (state.Intensity < 0.0)
    {
      message << "Light " << i << " has a negative intensity.";
      return message.str();
    }
    if (state.Radius < 0.0)
    {
      message << "Light " << i << " has a negative radius.";
      return message.str();
    }
    if (state.Kind == LightKind::Directional && state.Radius >= 180.0)
    {
      message << "Light " << i << " is directional with a radius of " << state.Radius
              << ": its apparent diameter must be below 180 degrees.";
      return message.str();
    }
    for (double c : state.Color)
    {
      if (c < 0.0)
      {
        message << "Light " << i << " has a negative colour component.";
        return message.str();
      }
      if (c * state.Intensity > MaximumRadiance)
      {
        message << "Light " << i << " is too bright: colour x intensity " << c * state.Intensity
                << " exceeds the limit " << MaximumRadiance << ".";
        return message.str();
      }
    }
  }
  return std::string();
}

}
