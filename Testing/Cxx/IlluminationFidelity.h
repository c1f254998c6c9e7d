// Fidelity where it is seen: the error of an illumination volume over the points that hold
// material, against the ray-marched reference evaluated at the same points. Shared by the
// fidelity tests and the benchmark.
#ifndef IlluminationFidelity_h
#define IlluminationFidelity_h

#include "IlluminationClassify.h"
#include "IlluminationLights.h"
#include "IlluminationTestUtilities.h"
#include "RayMarchKernel.h"
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkIlluminationVolumeAlgorithm.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkMetaImageReader.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkXMLImageDataReader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace volillumfidelity
{

/// A volume with the opacity and colour the fidelity figures use for it.
struct Scene
{
  std::string Name;
  vtkSmartPointer<vtkImageData> Image;
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
  vtkSmartPointer<vtkColorTransferFunction> Color;
};

/// Opacity 0 up to `threshold` (a fraction of the scalar range), then rising linearly to
/// `maximum` at the top of the range; colour from a warm grey to white over the same ramp.
inline void ThresholdRamp(Scene& scene, double threshold, double maximum)
{
  double range[2];
  scene.Image->GetPointData()->GetScalars()->GetRange(range);
  const double start = range[0] + threshold * (range[1] - range[0]);
  scene.Opacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
  scene.Opacity->AddPoint(range[0], 0.0);
  scene.Opacity->AddPoint(start, 0.0);
  scene.Opacity->AddPoint(range[1], maximum);
  scene.Color = vtkSmartPointer<vtkColorTransferFunction>::New();
  scene.Color->AddRGBPoint(start, 0.8, 0.55, 0.4);
  scene.Color->AddRGBPoint(range[1], 1.0, 1.0, 1.0);
}

/// The slab or three-spheres phantom, n points per axis.
inline Scene PhantomScene(const std::string& name, int kind, int n, double opacity)
{
  Scene scene{ name, volillumtest::PhantomScene(kind, n), nullptr, nullptr };
  ThresholdRamp(scene, 0.0, opacity);
  return scene;
}

/// A volume of the shared data folder (.vti or .mha); Image is null when it is missing.
inline Scene FileScene(
  const std::string& name, const std::string& path, double threshold, double maximum)
{
  Scene scene{ name, nullptr, nullptr, nullptr };
  if (!std::ifstream(path).good())
  {
    return scene;
  }
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".mha") == 0)
  {
    vtkNew<vtkMetaImageReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    scene.Image = reader->GetOutput();
  }
  else
  {
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    scene.Image = reader->GetOutput();
  }
  ThresholdRamp(scene, threshold, maximum);
  return scene;
}

/// A directional, a point or a spot light for a volume with the given bounds: the
/// directional light oblique to every axis, the point light beyond a corner of the box,
/// the spot light beyond a face pointing at the centre with a cone that leaves part of
/// the volume dark.
inline vtkSmartPointer<vtkLight> SceneLight(const std::string& kind, const double bounds[6])
{
  double centre[3], size[3];
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    size[a] = bounds[2 * a + 1] - bounds[2 * a];
  }
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetFocalPoint(centre);
  if (kind == "directional")
  {
    light->SetPositional(false);
    light->SetPosition(centre[0] - 0.35 * size[0], centre[1] - 0.6 * size[1], centre[2] + size[2]);
    light->SetDiffuseColor(1.0, 0.9, 0.7);
  }
  else if (kind == "point")
  {
    light->SetPositional(true);
    light->SetConeAngle(180);
    light->SetPosition(
      bounds[0] - 0.3 * size[0], bounds[2] - 0.2 * size[1], bounds[5] + 0.4 * size[2]);
    light->SetDiffuseColor(0.6, 0.8, 1.0);
  }
  else
  {
    light->SetPositional(true);
    light->SetConeAngle(25);
    light->SetExponent(2);
    light->SetPosition(
      centre[0] + 0.3 * size[0], bounds[3] + 0.8 * size[1], centre[2] + 0.2 * size[2]);
    light->SetDiffuseColor(1.0, 0.7, 0.9);
  }
  return light;
}

/// Error figures of one illumination volume.
struct Fidelity
{
  double MaterialRms = 0.0; // relative RMS over the sampled material points
  double WholeRms = 0.0;    // relative RMS over points sampled from the whole volume
  double MaterialFraction = 0.0;
  long long Samples = 0;
};

/**
 * Material points of the illumination grid `target`: those whose 2x2x2 neighbourhood of
 * data points (the data point at or just below the position and the next one along each
 * axis) holds a classified extinction above 0.
 */
inline std::vector<char> MaterialMask(
  const volillum::ClassifiedVolume& data, const volillum::GridGeometry& target)
{
  const auto& g = data.Geometry;
  const long long nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  std::vector<char> mask(static_cast<size_t>(target.NumberOfPoints()), 0);
  vtkSMPTools::For(0, target.NumberOfPoints(),
    [&](long long begin, long long end)
    {
      for (long long id = begin; id < end; ++id)
      {
        double p[3];
        target.PointPosition(id % nx, (id / nx) % ny, id / (nx * ny), p);
        int i0[3];
        for (int a = 0; a < 3; ++a)
        {
          i0[a] = std::min(g.Dimensions[a] - 1,
            std::max(0, static_cast<int>(std::floor((p[a] - g.Origin[a]) / g.Spacing[a] + 1e-6))));
        }
        bool material = false;
        for (int dk = 0; dk < 2 && !material; ++dk)
          for (int dj = 0; dj < 2 && !material; ++dj)
            for (int di = 0; di < 2 && !material; ++di)
            {
              const long long i = std::min(i0[0] + di, g.Dimensions[0] - 1);
              const long long j = std::min(i0[1] + dj, g.Dimensions[1] - 1);
              const long long k = std::min(i0[2] + dk, g.Dimensions[2] - 1);
              material = data.Extinction(i + g.Dimensions[0] * (j + g.Dimensions[1] * k)) > 0.0f;
            }
        mask[id] = material ? 1 : 0;
      }
    });
  return mask;
}

/// At most `count` indices drawn without repetition (a fixed seed) from those given.
inline std::vector<long long> Subsample(std::vector<long long> ids, size_t count)
{
  if (ids.size() > count)
  {
    std::mt19937_64 random(20261122);
    std::shuffle(ids.begin(), ids.end(), random);
    ids.resize(count);
    std::sort(ids.begin(), ids.end());
  }
  return ids;
}

/// The ray-marched illumination (the reference filter's kernel) at the listed points.
inline std::vector<double> ReferenceAt(const volillum::ClassifiedVolume& data,
  const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
  const std::vector<long long>& ids)
{
  const long long nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  std::vector<double> rgb(3 * ids.size(), 0.0);
  volillum::RayMarchSettings settings;
  vtkSMPTools::For(0, static_cast<long long>(ids.size()),
    [&](long long begin, long long end)
    {
      for (long long n = begin; n < end; ++n)
      {
        const long long id = ids[n];
        double p[3];
        target.PointPosition(id % nx, (id / nx) % ny, id / (nx * ny), p);
        const auto sum = volillum::RayMarchIlluminationAt(data, lights, p, settings);
        std::copy(sum.begin(), sum.end(), rgb.begin() + 3 * n);
      }
    });
  return rgb;
}

inline double RelativeRms(
  const float* got, const std::vector<double>& reference, const std::vector<long long>& ids)
{
  double error = 0.0, norm = 0.0;
  for (size_t n = 0; n < ids.size(); ++n)
  {
    for (int c = 0; c < 3; ++c)
    {
      const double d = got[3 * ids[n] + c] - reference[3 * n + c];
      error += d * d;
      norm += reference[3 * n + c] * reference[3 * n + c];
    }
  }
  return norm > 0.0 ? std::sqrt(error / norm) : 0.0;
}

/// The classification of an updated filter's input (as the filter classifies it) and the
/// geometry of its output; false when either is missing.
inline bool ClassifiedInput(vtkIlluminationVolumeAlgorithm* filter,
  volillum::ClassifiedVolume& classified, volillum::GridGeometry& target)
{
  vtkImageData* input = vtkImageData::SafeDownCast(filter->GetInputDataObject(0, 0));
  vtkImageData* output = filter->GetOutput();
  if (!input || !input->GetPointData()->GetScalars() || output->GetNumberOfPoints() == 0)
  {
    return false;
  }
  volillum::GridGeometry data;
  int dims[3];
  input->GetDimensions(dims);
  output->GetDimensions(target.Dimensions.data());
  output->GetOrigin(target.Origin.data());
  output->GetSpacing(target.Spacing.data());
  for (int a = 0; a < 3; ++a)
  {
    data.Dimensions[a] = dims[a];
    data.Origin[a] = input->GetOrigin()[a] + input->GetExtent()[2 * a] * input->GetSpacing()[a];
    data.Spacing[a] = input->GetSpacing()[a];
  }
  volillum::ClassificationSettings settings;
  settings.Color = filter->GetColorTransferFunction();
  settings.Opacity = filter->GetOpacityFunction();
  settings.UnitDistance = filter->GetScalarOpacityUnitDistance();
  settings.Chromatic = filter->GetChromaticAttenuation();
  std::string error;
  return volillum::Classify(input->GetPointData()->GetScalars(), data, settings, classified, error);
}

/**
 * Relative RMS of an updated filter's illumination against a reference volume computed at
 * the same points, over the material points only (MaterialMask); -1 without material.
 */
inline double MaterialRms(
  vtkIlluminationVolumeAlgorithm* filter, vtkFloatArray* got, vtkFloatArray* reference)
{
  volillum::ClassifiedVolume classified;
  volillum::GridGeometry target;
  if (!ClassifiedInput(filter, classified, target))
  {
    return -1.0;
  }
  const auto mask = MaterialMask(classified, target);
  double error = 0.0, norm = 0.0;
  for (size_t id = 0; id < mask.size(); ++id)
  {
    for (int c = 0; mask[id] && c < 3; ++c)
    {
      const double r = reference->GetValue(3 * id + c);
      const double d = got->GetValue(3 * id + c) - r;
      error += d * d;
      norm += r * r;
    }
  }
  return norm > 0.0 ? std::sqrt(error / norm) : -1.0;
}

/**
 * Compare the output of an updated illumination filter with the reference at up to
 * `samples` material points and as many points drawn from the whole volume. The filter's
 * classification and lights (as it applies them) are those of the reference.
 */
inline Fidelity Measure(vtkIlluminationVolumeAlgorithm* filter, size_t samples = 20000)
{
  Fidelity f;
  volillum::ClassifiedVolume classified;
  volillum::GridGeometry target;
  auto* result =
    vtkFloatArray::SafeDownCast(filter->GetOutput()->GetPointData()->GetArray("Illumination"));
  if (!result || !ClassifiedInput(filter, classified, target))
  {
    return f;
  }
  double bounds[6];
  classified.Geometry.GetBounds(bounds);
  const auto lights = volillum::ForBounds(filter->GetLightStates(), bounds);
  const auto mask = MaterialMask(classified, target);
  std::vector<long long> material, all;
  for (long long id = 0; id < static_cast<long long>(mask.size()); ++id)
  {
    all.push_back(id);
    if (mask[id])
    {
      material.push_back(id);
    }
  }
  f.MaterialFraction = static_cast<double>(material.size()) / std::max<size_t>(1, mask.size());
  material = Subsample(material, samples);
  all = Subsample(all, samples);
  f.Samples = static_cast<long long>(material.size());
  const float* got = result->GetPointer(0);
  f.MaterialRms = RelativeRms(got, ReferenceAt(classified, lights, target, material), material);
  f.WholeRms = RelativeRms(got, ReferenceAt(classified, lights, target, all), all);
  return f;
}
}

#endif
