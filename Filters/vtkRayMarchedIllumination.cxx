#include "vtkRayMarchedIllumination.h"

#include "IlluminationFilterSupport.h"
#include "IlluminationParallel.h"
#include "RayMarchKernel.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"

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
  const bool marches = volume.Geometry.NumberOfPoints() > 0;
  const volillum::EmptyBlocks* empty = marches ? this->GetEmptyBlocks() : nullptr;
  const int components = 3 * static_cast<int>(on.size());
  // Each process marches the parts of the rays in its piece for the points of every extent;
  // the products arrive at the extent's process.
  volillum::ReduceOverPieces(
    controller, extents, components, vtkCommunicator::PRODUCT_OP,
    [&](const int* e, size_t first, size_t count, double* parts)
    {
      const long long width = e[1] - e[0] + 1, rowsY = e[3] - e[2] + 1;
      std::fill(parts, parts + count * width * components, 1.0);
      if (marches)
      {
        // Threads share the block's points (a block may hold few rows).
        vtkSMPTools::For(0, static_cast<long long>(count) * width,
          [&](long long begin, long long end)
          {
            for (long long n = begin; n < end; ++n)
            {
              const long long row = static_cast<long long>(first) + n / width;
              double p[3];
              target.PointPosition(e[0] + n % width, e[2] + row % rowsY, e[4] + row / rowsY, p);
              for (size_t m = 0; m < on.size(); ++m)
              {
                const volillum::Incidence incidence = volillum::ComputeIncidence(lights[on[m]], p);
                if (incidence.ConeFactor > 0.0)
                {
                  const auto t = volillum::PartialTransmittance(volume, piece, incidence, p,
                    settings, settings.MinimumTransmittance / incidence.ConeFactor, empty);
                  std::copy(t.begin(), t.end(), parts + components * n + 3 * m);
                }
              }
            }
          });
      }
    },
    [&](const int* e, size_t first, size_t count, const double* products)
    {
      const long long width = e[1] - e[0] + 1, rowsY = e[3] - e[2] + 1;
      for (size_t r = 0; r < count; ++r)
      {
        const long long row = static_cast<long long>(first + r);
        for (long long i = 0; i < width; ++i)
        {
          double p[3];
          target.PointPosition(e[0] + i, e[2] + row % rowsY, e[4] + row / rowsY, p);
          const double* product = products + components * (r * width + i);
          std::array<double, 3> sum{ { 0.0, 0.0, 0.0 } };
          for (size_t m = 0; m < on.size(); ++m)
          {
            const volillum::LightState& light = lights[on[m]];
            const auto t =
              volillum::DarkenedTransmittance(volillum::ComputeIncidence(light, p).ConeFactor,
                { { product[3 * m], product[3 * m + 1], product[3 * m + 2] } }, settings);
            const auto radiance = light.Radiance();
            for (int c = 0; c < 3; ++c)
            {
              sum[c] += radiance[c] * t[c];
            }
          }
          float* o = rgb + 3 * (row * width + i);
          for (int c = 0; c < 3; ++c)
          {
            o[c] = static_cast<float>(sum[c]);
          }
        }
      }
    },
    [this](double fraction) { this->ReportProgress(fraction); });
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
