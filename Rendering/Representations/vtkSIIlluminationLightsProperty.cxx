#include "vtkSIIlluminationLightsProperty.h"

#include "vtkClientServerStream.h"
#include "vtkObjectFactory.h"
#include "vtkSMMessage.h"

vtkStandardNewMacro(vtkSIIlluminationLightsProperty);

//------------------------------------------------------------------------------
bool vtkSIIlluminationLightsProperty::Push(vtkSMMessage* message, int offset)
{
  if (!this->Superclass::Push(message, offset))
  {
    return false;
  }
  const ProxyState_Property& property = message->GetExtension(ProxyState::property, offset);
  vtkClientServerStream stream;
  stream << vtkClientServerStream::Invoke << this->GetVTKObject() << "SetNumberOfLightParameters"
         << property.value().float64_size() << vtkClientServerStream::End;
  return this->ProcessMessage(stream);
}
