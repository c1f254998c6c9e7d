/**
 * @class vtkSIIlluminationLightsProperty
 * @brief Server side of the illumination filters' "Lights" property: adds the filter's lights
 * row by row, in either layout, and tells the filter how many numbers it was given.
 *
 * A row is 15 numbers (LightParameterCount), or 14 in lists written before the radius
 * column (LightParametersPerLight: a list that is whole lights of 14 only; radius 0).
 * ParaView's own repeat_command would cut a list into rows of 15 whatever its layout and
 * drop an incomplete last row, so that a Python list of 17 numbers would light one light
 * without a word: this property clears the lights, adds each whole row, then passes the
 * count (in 15-number rows for a 14-number list) to the filter's SetNumberOfLightParameters,
 * which refuses a count that is not whole lights (an error, and an empty output until the
 * count is whole).
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
