/**
 * @file IlluminationLightingMacros.h
 * @brief Definitions of the lighting API every illumination filter declares.
 *
 * The image filters (vtkIlluminationVolumeAlgorithm) and the unstructured-grid filter
 * derive from different VTK algorithms but offer the same lighting API: the light list
 * (AddLight ... GetLightParameter, forwarding to a volillum::LightList member "Lights"),
 * the transfer functions (members ColorTransferFunction and OpacityFunction) and a GetMTime
 * that includes them. Like vtkCxxSetObjectMacro, the macro below defines those methods in
 * the class's .cxx file; the header declares them as usual (so that wrapping sees them).
 */
#ifndef IlluminationLightingMacros_h
#define IlluminationLightingMacros_h

#include "IlluminationLightList.h"
#include "vtkColorTransferFunction.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSetGet.h"

#include <algorithm>

// clang-format off
#define volillumLightingImplementationMacro(thisClass)                                         \
  vtkCxxSetObjectMacro(thisClass, ColorTransferFunction, vtkColorTransferFunction);            \
  vtkCxxSetObjectMacro(thisClass, OpacityFunction, vtkPiecewiseFunction);                      \
  void thisClass::AddLight(vtkLight* light)                                                    \
  {                                                                                            \
    if (this->Lights.Add(light))                                                               \
    {                                                                                          \
      this->Modified();                                                                        \
    }                                                                                          \
  }                                                                                            \
  void thisClass::RemoveAllLights()                                                            \
  {                                                                                            \
    if (this->Lights.Clear())                                                                  \
    {                                                                                          \
      this->Modified();                                                                        \
    }                                                                                          \
  }                                                                                            \
  vtkLight* thisClass::GetLight(int index) const { return this->Lights.Get(index); }          \
  void thisClass::AddLightParameters(const double parameters[volillum::LightParameterCount])   \
  {                                                                                            \
    vtkNew<vtkLight> light;                                                                    \
    volillum::ApplyLightParameters(light, parameters);                                         \
    this->AddLight(light);                                                                     \
  }                                                                                            \
  void thisClass::SetNumberOfLightParameters(int count)                                        \
  {                                                                                            \
    bool changed = false;                                                                      \
    if (!this->Lights.SetNumberOfParameters(count, changed))                                   \
    {                                                                                          \
      vtkErrorMacro("The light list needs " << volillum::LightParameterCount                   \
                                            << " numbers per light, got " << count << ".");    \
    }                                                                                          \
    if (changed)                                                                               \
    {                                                                                          \
      this->Modified();                                                                        \
    }                                                                                          \
  }                                                                                            \
  int thisClass::GetNumberOfLightParameters() const                                            \
  {                                                                                            \
    return this->Lights.GetNumberOfParameters();                                               \
  }                                                                                            \
  void thisClass::SetLightParameter(int index, double value)                                   \
  {                                                                                            \
    if (!this->Lights.SetParameter(index, value))                                              \
    {                                                                                          \
      vtkErrorMacro("Light parameter " << index << " is out of range.");                       \
    }                                                                                          \
  }                                                                                            \
  double thisClass::GetLightParameter(int index) const                                         \
  {                                                                                            \
    return this->Lights.GetParameter(index);                                                   \
  }                                                                                            \
  vtkMTimeType thisClass::GetMTime()                                                           \
  {                                                                                            \
    vtkMTimeType t = std::max(this->Superclass::GetMTime(), this->Lights.GetMTime());          \
    if (this->ColorTransferFunction)                                                           \
    {                                                                                          \
      t = std::max(t, this->ColorTransferFunction->GetMTime());                                \
    }                                                                                          \
    if (this->OpacityFunction)                                                                 \
    {                                                                                          \
      t = std::max(t, this->OpacityFunction->GetMTime());                                      \
    }                                                                                          \
    return t;                                                                                  \
  }
// clang-format on

#endif
