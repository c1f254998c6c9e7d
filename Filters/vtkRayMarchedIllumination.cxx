#include "vtkRayMarchedIllumination.h"

#include "DistributedRayMarch.h"
#include "IlluminationFilterSupport.h"
#include "RayMarchKernel.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"

#include <algorithm>
#include <array>

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
void vtkRayMarchedIllumination::ComputeDistributedIllumination(
  vtkMultiProcessController* controller, const volillum::ClassifiedVolume& volume,
  const volillum::VolumePiece& piece, const std::vector<volillum::LightState>& lights,
  const volillum::GridGeometry& target, const std::vector<int>& extents, bool, float* rgb,
  UpdateReport& report)
{
  volillum::RayMarchSettings settings;
  settings.StepFraction = this->StepFraction;
  // The lights that are on: the same on every process (`lights`, in the data's frame, is
  // empty where the process has no piece).
  std::vector<size_t> on;
  const std::vector<volillum::LightState> states = this->GetLightStates();
  for (size_t l = 0; l < states.size(); ++l)
  {
    if (states[l].On)
    {
      on.push_back(l);
    }
  }
  report.Mode = 0;
  report.Passes = static_cast<int>(on.size());
  if (on.empty())
  {
    return; // dark
  }
  // Each process marches the parts of the rays in its piece for the points of every extent;
  // the products arrive at the extent's process.
  const volillum::EmptyBlocks* empty =
    volume.Geometry.NumberOfPoints() > 0 ? this->GetEmptyBlocks() : nullptr;
  volillum::RayMarchDistributed(controller, volume, piece, lights, on, target, extents, settings,
    empty, rgb, [this](double fraction) { this->ReportProgress(fraction); });
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
