// Helpers shared by the C++ tests: scenes, lights and error capture.
#ifndef IlluminationTestUtilities_h
#define IlluminationTestUtilities_h

#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

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
