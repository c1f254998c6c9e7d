// Fidelity where there is material: relative RMS of Multi-Light Illumination Volume and
// Filtered Volumetric Shadows (FilterWidth 0) against the ray-marched reference at the same
// resolution scale, over the points that hold material (IlluminationFidelity.h), for the
// slab, the three spheres and the engine, aneurism and chest CT volumes, each with a
// directional, a point and a spot light. Every figure is printed; each test fails when a
// figure exceeds its bound, set just above what the methods achieve.
#include "IlluminationFidelity.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkMultiLightIlluminationVolume.h"

#include <gtest/gtest.h>

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
