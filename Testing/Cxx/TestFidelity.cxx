// Fidelity where there is material: relative RMS of Multi-Light Illumination Volume and
// Filtered Volumetric Shadows (FilterWidth 0) against the ray-marched reference at the same
// resolution scale, over the points that hold material (IlluminationFidelity.h), for the
// slab, the three spheres and the engine, aneurism and chest CT volumes, each with a
// directional, a point and a spot light; and the ambient occlusion against many marched
// rays. Every figure is printed; each test fails when a
// figure exceeds its bound, set just above what the methods achieve.
#include "AmbientOcclusionKernel.h"
#include "IlluminationFidelity.h"
#include "vtkFieldData.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkMultiLightIlluminationVolume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

using volillumfidelity::Fidelity;
using volillumfidelity::Scene;

namespace
{
const std::string Data = VOLILLUM_SHARED_DATA;

// One method at one illumination scale, and the largest material RMS it may reach.
struct Variant
{
  const char* Name;
  double Scale;
  double Bound;
  std::function<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>()> Make;
};

vtkSmartPointer<vtkIlluminationVolumeAlgorithm> Propagation()
{
  return vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
}

// Hard filtered shadows with the tables at `tables` times the illumination resolution.
std::function<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>()> Filtered(double tables)
{
  return [tables]()
  {
    auto f = vtkSmartPointer<vtkFilteredVolumetricShadows>::New();
    f->SetFilterWidth(0);
    f->SetSATResolutionScale(tables);
    return vtkSmartPointer<vtkIlluminationVolumeAlgorithm>(f);
  };
}

// Bounds in per cent: propagation at scale 1 and 0.5, filtered shadows at scale 0.5 with
// the default tables (half resolution) and at scale 1 with full-resolution tables.
void CheckScene(const Scene& scene, double propagation1, double propagation05, double filtered05,
  double filteredTables1)
{
  if (!scene.Image)
  {
    GTEST_SKIP() << scene.Name << " is not in " << Data;
  }
  const Variant variants[] = { { "propagation", 1.0, propagation1, Propagation },
    { "propagation", 0.5, propagation05, Propagation },
    { "filtered, default tables", 0.5, filtered05, Filtered(0.5) },
    { "filtered, tables at scale 1", 1.0, filteredTables1, Filtered(1.0) } };
  for (const std::string light : { "directional", "point", "spot" })
  {
    for (const Variant& v : variants)
    {
      auto filter = v.Make();
      filter->SetInputData(scene.Image);
      filter->SetOpacityFunction(scene.Opacity);
      filter->SetColorTransferFunction(scene.Color);
      filter->SetResolutionScale(v.Scale);
      filter->AddLight(volillumfidelity::SceneLight(light, scene.Image->GetBounds()));
      filter->Update();
      const Fidelity f = volillumfidelity::Measure(filter, 10000);
      std::printf("%-9s %-12s %-28s scale %-4g material RMS %6.2f %% (bound %5.1f %%; whole "
                  "volume %5.2f %%; material %4.1f %% of points)\n",
        scene.Name.c_str(), light.c_str(), v.Name, v.Scale, 100.0 * f.MaterialRms, v.Bound,
        100.0 * f.WholeRms, 100.0 * f.MaterialFraction);
      EXPECT_GT(f.Samples, 0) << scene.Name;
      EXPECT_LE(100.0 * f.MaterialRms, v.Bound)
        << scene.Name << " " << light << " " << v.Name << " scale " << v.Scale;
    }
  }
}
}

TEST(Fidelity, Slab)
{
  CheckScene(volillumfidelity::PhantomScene("slab", vtkIlluminationPhantomSource::Slab, 64, 0.05),
    0.5, 3.5, 2.8, 1.5);
}

TEST(Fidelity, ThreeSpheres)
{
  CheckScene(
    volillumfidelity::PhantomScene("spheres", vtkIlluminationPhantomSource::ThreeSpheres, 64, 0.3),
    2, 6, 2, 1.2);
}

TEST(Fidelity, Engine)
{
  CheckScene(volillumfidelity::FileScene("engine", Data + "/volumes/engine.vti", 0.3, 0.8), 2.5, 5,
    5.5, 2.6);
}

TEST(Fidelity, Aneurism)
{
  CheckScene(volillumfidelity::FileScene("aneurism", Data + "/volumes/aneurism.vti", 0.3, 0.8), 5.5,
    9, 8.5, 4.6);
}

TEST(Fidelity, ChestCT)
{
  CheckScene(
    volillumfidelity::FileScene("lidc2", Data + "/volumes/LIDC2.mha", 0.3, 0.8), 5, 10.5, 9.6, 4.7);
}

namespace
{
// Ambient occlusion (the filters' AmbientOcclusion array, read from a summed-area table)
// against the transmittance averaged over 256 marched rays (MarchedAmbientOcclusion) at up
// to 3000 material points, at the default radius (a twentieth of the diagonal) and at half
// of it; bounds in per cent of the reference's RMS. The table's figures are darker on
// average than the rays' where material is dense (a pyramid that reaches into opaque
// material counts as hidden: AmbientOcclusionKernel.h), so the error grows with the radius.
void CheckAmbientOcclusion(const Scene& scene, double bound, double halfRadiusBound)
{
  if (!scene.Image)
  {
    GTEST_SKIP() << scene.Name << " is not in " << Data;
  }
  vtkNew<vtkFilteredVolumetricShadows> filter; // no light: the ambient light alone
  filter->SetInputData(scene.Image);
  filter->SetOpacityFunction(scene.Opacity);
  filter->SetResolutionScale(0.5);
  filter->SetAmbientOcclusion(1.0);
  double bounds[6];
  scene.Image->GetBounds(bounds);
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  for (double radius : { 0.0, 0.025 * diagonal })
  {
    filter->SetAmbientOcclusionRadius(radius);
    filter->Update();
    volillum::ClassifiedVolume classified;
    volillum::GridGeometry target;
    ASSERT_TRUE(volillumfidelity::ClassifiedInput(filter, classified, target));
    const auto mask = volillumfidelity::MaterialMask(classified, target);
    std::vector<long long> material;
    for (long long id = 0; id < static_cast<long long>(mask.size()); ++id)
    {
      if (mask[id])
      {
        material.push_back(id);
      }
    }
    const auto ids = volillumfidelity::Subsample(material, 3000);
    const double length = radius > 0.0 ? radius : 0.05 * diagonal;
    std::vector<double> reference(3 * ids.size());
    const long long nx = target.Dimensions[0], ny = target.Dimensions[1];
    vtkSMPTools::For(0, static_cast<long long>(ids.size()),
      [&](long long begin, long long end)
      {
        for (long long n = begin; n < end; ++n)
        {
          double p[3], t[3];
          target.PointPosition(ids[n] % nx, (ids[n] / nx) % ny, ids[n] / (nx * ny), p);
          volillum::MarchedAmbientOcclusion(classified, p, length, 1, 256, t);
          std::fill_n(reference.begin() + 3 * n, 3, t[0]);
        }
      });
    auto* occlusion = vtkFloatArray::SafeDownCast(
      filter->GetOutput()->GetPointData()->GetArray("AmbientOcclusion"));
    ASSERT_NE(occlusion, nullptr);
    const double rms =
      100.0 * volillumfidelity::RelativeRms(occlusion->GetPointer(0), reference, ids);
    double got = 0.0, expected = 0.0;
    for (size_t n = 0; n < ids.size(); ++n)
    {
      got += occlusion->GetValue(3 * ids[n]);
      expected += reference[3 * n];
    }
    std::printf("%s: ambient occlusion, radius %.3g (%zu material points): material RMS %.2f %%, "
                "mean %.3f against %.3f\n",
      scene.Name.c_str(), length, ids.size(), rms, got / ids.size(), expected / ids.size());
    EXPECT_GT(ids.size(), 500u);
    EXPECT_LT(rms, radius > 0.0 ? halfRadiusBound : bound) << scene.Name << ", radius " << length;
  }
}
}

TEST(Fidelity, AmbientOcclusionOfThreeSpheres)
{
  CheckAmbientOcclusion(
    volillumfidelity::PhantomScene("spheres", vtkIlluminationPhantomSource::ThreeSpheres, 64, 0.3),
    1.5, 0.8);
}

TEST(Fidelity, AmbientOcclusionOfTheEngine)
{
  CheckAmbientOcclusion(
    volillumfidelity::FileScene("engine", Data + "/volumes/engine.vti", 0.3, 0.8), 18, 9.5);
}

TEST(Fidelity, AmbientOcclusionOfTheChestCT)
{
  CheckAmbientOcclusion(
    volillumfidelity::FileScene("lidc2", Data + "/volumes/LIDC2.mha", 0.3, 0.8), 15, 10);
}
