// Helpers shared by the C++ tests: scenes, lights and error capture.
#ifndef IlluminationTestUtilities_h
#define IlluminationTestUtilities_h

#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <cmath>
#include <string>

namespace volillumtest
{

/// Counts the ErrorEvents (vtkErrorMacro) an object raises, and keeps the last message.
class ErrorCounter : public vtkCommand
{
public:
  static ErrorCounter* New() { return new ErrorCounter; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    ++this->Count;
    this->LastMessage = data ? static_cast<const char*>(data) : "";
  }
  int Count = 0;
  std::string LastMessage;
};

/// Root-mean-square difference relative to the root-mean-square of the reference.
inline double RmsRelative(vtkFloatArray* got, vtkFloatArray* reference)
{
  double error = 0.0, norm = 0.0;
  for (vtkIdType i = 0; i < got->GetNumberOfValues(); ++i)
  {
    const double d = got->GetValue(i) - reference->GetValue(i);
    error += d * d;
    norm += reference->GetValue(i) * reference->GetValue(i);
  }
  return std::sqrt(error / norm);
}

inline vtkSmartPointer<vtkLight> DirectionalLight(
  double dx, double dy, double dz, double r = 1, double g = 1, double b = 1)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetPositional(false);
  light->SetPosition(0, 0, 0);
  light->SetFocalPoint(dx, dy, dz);
  light->SetDiffuseColor(r, g, b);
  return light;
}

inline vtkSmartPointer<vtkLight> PointLight(
  double x, double y, double z, double r = 1, double g = 1, double b = 1)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetPositional(true);
  light->SetConeAngle(180);
  light->SetPosition(x, y, z);
  light->SetFocalPoint(32, 32, 32);
  light->SetDiffuseColor(r, g, b);
  return light;
}

}

#endif
