/**
 * @class vtkRayMarchedIllumination
 * @brief Reference illumination volume: brute-force single scattering from many lights.
 *
 * From every point of the illumination grid the filter marches to every light that is on
 * and sums colour x intensity x chromatic transmittance (see RayMarchKernel.h). It is the
 * ground truth for the faster methods and the single-scattering baseline of the
 * benchmarks. Cost: points x lights x (path length / StepFraction) samples, all threads
 * through vtkSMPTools. PropagationPasses reports the number of lights marched.
 *
 * In a parallel run no process assembles the input: each classifies its own block of the
 * data and marches, for every point of the illumination grid, the part of the point's ray
 * to each light that crosses its block (PartialTransmittance); the products of the parts
 * go to the process whose piece has the point (ReduceOverPieces, a product, 3 doubles a point and
 * light, in blocks of 8 MiB). The result equals the serial one up to the order of the
 * multiplications. The field array ClassifiedPoints gives the points a process classified.
 *
 * Model: N. Max, "Optical Models for Direct Volume Rendering", IEEE Transactions on Visualization
 * and Computer Graphics 1(2), 1995 (emission-absorption, single scattering).
 *
 * @sa vtkMultiLightIlluminationVolume vtkFilteredVolumetricShadows
 */
#ifndef vtkRayMarchedIllumination_h
#define vtkRayMarchedIllumination_h

#include "vtkIlluminationVolumeAlgorithm.h"

class VOLILLUMFILTERS_EXPORT vtkRayMarchedIllumination : public vtkIlluminationVolumeAlgorithm
{
public:
  static vtkRayMarchedIllumination* New();
  vtkTypeMacro(vtkRayMarchedIllumination, vtkIlluminationVolumeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Step length of the marching as a fraction of the smallest input spacing, clamped to
   * [0.01, 4]. Default 0.5. A value that is not a finite number is refused with an error.
   */
  void SetStepFraction(double value);
  vtkGetMacro(StepFraction, double);
  ///@}

protected:
  vtkRayMarchedIllumination() = default;
  ~vtkRayMarchedIllumination() override = default;

  bool LightsPointsIndependently() const override { return true; }
  bool LightsDistributedPieces() const override { return true; }
  void ComputeDistributedIllumination(vtkMultiProcessController* controller,
    const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    const std::vector<int>& extents, bool inputModified, float* rgb, UpdateReport& report) override;
  bool ComputeIllumination(const volillum::ClassifiedVolume& volume,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    bool inputModified, float* rgb, UpdateReport& report) override;

  double StepFraction = 0.5;

private:
  vtkRayMarchedIllumination(const vtkRayMarchedIllumination&) = delete;
  void operator=(const vtkRayMarchedIllumination&) = delete;
};

#endif
