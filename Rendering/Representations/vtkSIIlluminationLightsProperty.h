/**
 * @class vtkSIIlluminationLightsProperty
 * @brief Server side of the illumination filters' "Lights" property: tells the filter how
 * many numbers it was given.
 *
 * The Lights property adds one light per 14 numbers (repeat_command): ParaView's server
 * manager drops the numbers of an incomplete last row, so a Python list of 17 numbers
 * would light one light without a word. After the lights, this property passes the count
 * of numbers to the filter's SetNumberOfLightParameters, which refuses a count that is not
 * whole lights (an error, and an empty output until the count is whole).
 */
#ifndef vtkSIIlluminationLightsProperty_h
#define vtkSIIlluminationLightsProperty_h

#include "VolIllumRepresentationsModule.h" // for export macro
#include "vtkSIDoubleVectorProperty.h"

class VOLILLUMREPRESENTATIONS_EXPORT vtkSIIlluminationLightsProperty
  : public vtkSIDoubleVectorProperty
{
public:
  static vtkSIIlluminationLightsProperty* New();
  vtkTypeMacro(vtkSIIlluminationLightsProperty, vtkSIDoubleVectorProperty);

protected:
  vtkSIIlluminationLightsProperty() = default;
  ~vtkSIIlluminationLightsProperty() override = default;

  bool Push(vtkSMMessage* message, int offset) override;

private:
  vtkSIIlluminationLightsProperty(const vtkSIIlluminationLightsProperty&) = delete;
  void operator=(const vtkSIIlluminationLightsProperty&) = delete;
};

#endif
