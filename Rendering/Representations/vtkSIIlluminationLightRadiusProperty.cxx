#include "vtkSIIlluminationLightRadiusProperty.h"

#include "IlluminationLightList.h"

#include "vtkLight.h"
#include "vtkObjectFactory.h"
#include "vtkSMMessage.h"

vtkStandardNewMacro(vtkSIIlluminationLightRadiusProperty);

//------------------------------------------------------------------------------
bool vtkSIIlluminationLightRadiusProperty::Push(vtkSMMessage* message, int offset)
{
  const ProxyState_Property& property = message->GetExtension(ProxyState::property, offset);
  vtkLight* light = vtkLight::SafeDownCast(this->GetVTKObject());
  if (!light || property.value().float64_size() != 1)
  {
    return false;
  }
  volillum::SetLightRadius(light, property.value().float64(0));
  return true;
}
