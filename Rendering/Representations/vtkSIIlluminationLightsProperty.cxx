#include "vtkSIIlluminationLightsProperty.h"

#include "IlluminationLights.h"

#include "vtkClientServerStream.h"
#include "vtkObjectFactory.h"
#include "vtkSMMessage.h"

vtkStandardNewMacro(vtkSIIlluminationLightsProperty);

//------------------------------------------------------------------------------
bool vtkSIIlluminationLightsProperty::Push(vtkSMMessage* message, int offset)
{
  const ProxyState_Property& property = message->GetExtension(ProxyState::property, offset);
  const auto& values = property.value();
  const int count = values.float64_size();
  const int perLight = volillum::LightParametersPerLight(count);
  vtkObjectBase* filter = this->GetVTKObject();
  vtkClientServerStream stream;
  stream << vtkClientServerStream::Invoke << filter << "RemoveAllLights"
         << vtkClientServerStream::End;
  for (int first = 0; first + perLight <= count; first += perLight)
  {
    double row[volillum::LightParameterCount] = {}; // radius 0 in a 14-number row
    for (int i = 0; i < perLight; ++i)
    {
      row[i] = values.float64(first + i);
    }
    stream << vtkClientServerStream::Invoke << filter << "AddLightParameters"
           << vtkClientServerStream::InsertArray(row, volillum::LightParameterCount)
           << vtkClientServerStream::End;
  }
  const int sent = count % perLight == 0 ? count / perLight * volillum::LightParameterCount : count;
  stream << vtkClientServerStream::Invoke << filter << "SetNumberOfLightParameters" << sent
         << vtkClientServerStream::End;
  return this->ProcessMessage(stream);
}
