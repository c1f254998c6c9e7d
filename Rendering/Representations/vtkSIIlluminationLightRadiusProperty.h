/**
 * @class vtkSIIlluminationLightRadiusProperty
 * @brief Server side of the Light Inspector's "Shadow Radius" (an extension of ParaView's
 * Light proxy): stores the light's size in its vtkLight for the Illuminated Volume
 * representation.
 *
 * ParaView's own Radius property of a light reaches the light only in builds with ray
 * tracing (vtkPVLight::SetRadius is empty without it, and the Light Inspector hides it).
 * This property calls no method: its Push keeps the value where the representation reads
 * it, volillum::SetLightRadius on the vtkPVLight.
 */
#ifndef vtkSIIlluminationLightRadiusProperty_h
#define vtkSIIlluminationLightRadiusProperty_h

#include "VolIllumRepresentationsModule.h" // for export macro
#include "vtkSIDoubleVectorProperty.h"

class VOLILLUMREPRESENTATIONS_EXPORT vtkSIIlluminationLightRadiusProperty
  : public vtkSIDoubleVectorProperty
{
public:
  static vtkSIIlluminationLightRadiusProperty* New();
  vtkTypeMacro(vtkSIIlluminationLightRadiusProperty, vtkSIDoubleVectorProperty);

protected:
  vtkSIIlluminationLightRadiusProperty() = default;
  ~vtkSIIlluminationLightRadiusProperty() override = default;

  bool Push(vtkSMMessage* message, int offset) override;

private:
  vtkSIIlluminationLightRadiusProperty(const vtkSIIlluminationLightRadiusProperty&) = delete;
  void operator=(const vtkSIIlluminationLightRadiusProperty&) = delete;
};

#endif
