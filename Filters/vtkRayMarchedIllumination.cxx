#include "vtkRayMarchedIllumination.h"

#include "IlluminationFilterSupport.h"
#include "RayMarchKernel.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkRayMarchedIllumination);

//------------------------------------------------------------------------------
bool vtkRayMarchedIllumination::ComputeIllumination(const volillum::ClassifiedVolume& volume,
  const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target, bool,
  float* rgb, UpdateReport& report)
{
  volillum::RayMarchSettings settings;
  settings.StepFraction = this->StepFraction;
  report.Mode = 0;
  report.Passes = 0;
  for (const auto& light : lights)
  {
    report.Passes += light.On ? 1 : 0;
  }
  return volillum::RayMarchIllumination(
    volume, lights, target, settings, rgb, [this](double f) { return this->ReportProgress(f); });
}

//------------------------------------------------------------------------------
void vtkRayMarchedIllumination::SetStepFraction(double value)
{
  volillum::SetFiniteClamped(this, this->StepFraction, value, 0.01, 4.0, "StepFraction");
}

//------------------------------------------------------------------------------
void vtkRayMarchedIllumination::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "StepFraction: " << this->StepFraction << "\n";
}
