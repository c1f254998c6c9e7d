// Tests of vtkFilteredVolumetricShadows: hard shadows against the ray-marched reference,
// sharing of tables between orthodirectional lights, reuse of tables when only light
// colours change, lights of finite size, selective shading of edited lights, and lights it
// cannot handle yet.
#include "IlluminationFidelity.h"
#include "IlluminationLightList.h"
#include "IlluminationTestUtilities.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using volillumtest::DirectionalLight;
using volillumtest::ErrorCounter;
using volillumtest::PointLight;
using volillumtest::Result;
using volillumtest::RmsRelative;

namespace
{
vtkSmartPointer<vtkImageData> Spheres(int n)
{
  vtkNew<vtkIlluminationPhantomSource> source;
  source->SetDimensions(n, n, n);
  source->Update();
  return source->GetOutput();
}

vtkSmartPointer<vtkPiecewiseFunction> Opacity()
{
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(200.0, 0.3);
  return otf;
}

// RMS relative difference between hard filtered shadows (FilterWidth 0, tables at full
// resolution) and the ray-marched reference for one light over the material points (the
// whole volume's in whole); the tables built are returned.
double HardShadowDifference(vtkImageData* image, vtkPiecewiseFunction* otf, vtkLight* light,
  double& whole, int* tables = nullptr);

int Passes(vtkImageAlgorithm* filter)
{
  return static_cast<int>(
    filter->GetOutput()->GetFieldData()->GetArray("PropagationPasses")->GetTuple1(0));
}
}

namespace
{
double HardShadowDifference(
  vtkImageData* image, vtkPiecewiseFunction* otf, vtkLight* light, double& whole, int* tables)
{
  vtkNew<vtkRayMarchedIllumination> reference;
  vtkNew<vtkFilteredVolumetricShadows> filtered;
  filtered->SetFilterWidth(0);
  filtered->SetSATResolutionScale(1);
  for (vtkIlluminationVolumeAlgorithm* f :
    { static_cast<vtkIlluminationVolumeAlgorithm*>(reference),
      static_cast<vtkIlluminationVolumeAlgorithm*>(filtered) })
  {
    f->SetInputData(image);
    f->SetOpacityFunction(otf);
    f->AddLight(light);
    f->Update();
  }
  if (tables)
  {
    *tables = Passes(filtered);
  }
  whole = RmsRelative(Result(filtered), Result(reference));
  return volillumfidelity::MaterialRms(filtered, Result(filtered), Result(reference));
}
}

TEST(FilteredVolumetricShadows, HardShadowsAgreeWithTheRayMarchedReference)
{
  auto image = Spheres(64);
  auto otf = Opacity();
  for (const auto& d :
    { std::array<double, 3>{ 0, 0, -1 }, std::array<double, 3>{ 0.5, -0.3, -1 } })
  {
    auto light = DirectionalLight(d[0], d[1], d[2], 1, 0.8, 0.5);
    double whole = 0.0;
    const double rms = HardShadowDifference(image, otf, light, whole);
    std::cout << "FilterWidth 0 vs RayMarchedIllumination, light travelling (" << d[0] << ","
              << d[1] << "," << d[2] << "): RMS relative difference over material " << rms
              << " (whole volume " << whole << ")" << std::endl;
    // Hard shadows at the table's resolution: a one-cell box across the light. Along a data
    // axis the table's cells are centred on the data points, so the box reads exactly the
    // column through the point; an oblique table resamples the extinction.
    EXPECT_LE(rms, d[0] == 0.0 ? 1e-6 : 0.03);
    EXPECT_LE(whole, 0.06);
  }
}

TEST(FilteredVolumetricShadows, OrthodirectionalLightsShareOneTable)
{
  auto image = Spheres(32);
  auto otf = Opacity();
  std::vector<vtkSmartPointer<vtkLight>> lights = { DirectionalLight(1, 0, 0, 1, 0, 0),
    DirectionalLight(-1, 0, 0, 0, 1, 0), DirectionalLight(0, 0, -1, 0, 0, 1),
    DirectionalLight(0, 1, 0, 1, 1, 1) };
  vtkNew<vtkFilteredVolumetricShadows> together;
  together->SetInputData(image);
  together->SetOpacityFunction(otf);
  for (auto& l : lights)
  {
    together->AddLight(l);
  }
  together->Update();
  EXPECT_EQ(Passes(together), 1);
  auto combined = Result(together);
  std::vector<double> sum(combined->GetNumberOfValues(), 0.0);
  for (auto& l : lights)
  {
    vtkNew<vtkFilteredVolumetricShadows> alone;
    alone->SetInputData(image);
    alone->SetOpacityFunction(otf);
    alone->AddLight(l);
    alone->Update();
    auto part = Result(alone);
    for (size_t i = 0; i < sum.size(); ++i)
    {
      sum[i] += part->GetValue(i);
    }
  }
  double worst = 0.0;
  for (size_t i = 0; i < sum.size(); ++i)
  {
    worst = std::max(worst, std::abs(combined->GetValue(i) - sum[i]));
  }
  EXPECT_LE(worst, 1e-5);
}

TEST(FilteredVolumetricShadows, OnlyLightColourChangesReuseTheTables)
{
  auto image = Spheres(32);
  auto otf = Opacity();
  vtkNew<vtkFilteredVolumetricShadows> filter;
  filter->SetInputData(image);
  filter->SetOpacityFunction(otf);
  auto light = DirectionalLight(0.3, 0.2, -1);
  filter->AddLight(light);
  filter->Update();
  EXPECT_EQ(Passes(filter), 1);
  auto narrow = Result(filter);
  light->SetDiffuseColor(1, 0, 0);
  light->SetIntensity(2);
  filter->Update();
  EXPECT_EQ(Passes(filter), 0);
  filter->SetFilterWidth(9);
  filter->Update();
  EXPECT_EQ(Passes(filter), 0);
  // A wider filter changes the shadows but not the light far from any occluder.
  auto wide = Result(filter);
  double changed = 0.0;
  for (vtkIdType i = 0; i < wide->GetNumberOfTuples(); ++i)
  {
    changed =
      std::max(changed, std::abs(wide->GetComponent(i, 0) - 2.0 * narrow->GetComponent(i, 0)));
  }
  EXPECT_GT(changed, 0.05);
  EXPECT_NEAR(wide->GetComponent(wide->GetNumberOfTuples() - 1, 0), 2.0, 1e-6);
  light->SetFocalPoint(0.3, 0.25, -1);
  filter->Update();
  EXPECT_EQ(Passes(filter), 1);
  otf->AddPoint(100.0, 0.05);
  filter->Update();
  EXPECT_EQ(Passes(filter), 1);
}

TEST(FilteredVolumetricShadows, ALightsRadiusSoftensItsShadowsAndZeroRestoresThem)
{
  // A light's radius spreads its shadows' edges (the illumination changes, and the sum of
  // squared differences between neighbouring points falls) without rebuilding the tables and
  // without touching the light that reaches points in the open; radius 0 gives back the hard
  // light's output bit for bit. Directional (degrees) and point lights (world units).
  auto image = Spheres(32);
  auto otf = Opacity();
  auto roughness = [](vtkFloatArray* a)
  {
    double sum = 0.0;
    for (vtkIdType i = 1; i < a->GetNumberOfTuples(); ++i)
    {
      if (i % 32 != 0) // neighbours along x
      {
        const double d = a->GetComponent(i, 0) - a->GetComponent(i - 1, 0);
        sum += d * d;
      }
    }
    return sum;
  };
  const std::pair<vtkSmartPointer<vtkLight>, double> cases[] = {
    { DirectionalLight(0.3, 0.2, -1), 10.0 }, { PointLight(-10, 12, 40), 4.0 }
  };
  for (const auto& c : cases)
  {
    vtkNew<vtkFilteredVolumetricShadows> filter;
    filter->SetInputData(image);
    filter->SetOpacityFunction(otf);
    filter->SetFilterWidth(0);
    filter->AddLight(c.first);
    filter->Update();
    auto hard = Result(filter);
    volillum::SetLightRadius(c.first, c.second);
    filter->Update();
    EXPECT_EQ(Passes(filter), 0);
    auto soft = Result(filter);
    const vtkIdType open = hard->GetNumberOfTuples() - 1; // a corner no shadow reaches
    std::cout << (c.first->GetPositional() ? "point" : "directional") << " light, radius "
              << c.second << ": neighbours' squared differences " << roughness(hard) << " hard, "
              << roughness(soft) << " soft; open corner " << hard->GetComponent(open, 0) << " / "
              << soft->GetComponent(open, 0) << std::endl;
    double moved = 0.0;
    for (vtkIdType i = 0; i < hard->GetNumberOfTuples(); ++i)
    {
      moved = std::max(moved, std::abs(soft->GetComponent(i, 0) - hard->GetComponent(i, 0)));
    }
    std::cout << "  largest change " << moved << std::endl;
    EXPECT_GT(moved, 0.05);
    EXPECT_LT(roughness(soft), roughness(hard));
    EXPECT_NEAR(soft->GetComponent(open, 0), hard->GetComponent(open, 0), 1e-6);
    volillum::SetLightRadius(c.first, 0.0);
    filter->Update();
    auto again = Result(filter);
    double largest = 0.0;
    for (vtkIdType i = 0; i < hard->GetNumberOfTuples(); ++i)
    {
      largest = std::max(largest, std::abs(again->GetComponent(i, 0) - hard->GetComponent(i, 0)));
    }
    EXPECT_EQ(largest, 0.0);
  }
}

TEST(FilteredVolumetricShadows, EditsShadeOnlyTheLightsWhoseGeometryChanged)
{
  // Three lights (two directional, one spot) under 60 random edits of one light each: its
  // colour or intensity (no light shaded again), its radius, its switch or its position
  // (that light only, when it is on; a move builds its table anew). After every edit the
  // output equals a new filter's with the same lights, bit for bit.
  auto image = Spheres(32);
  auto otf = Opacity();
  std::vector<vtkSmartPointer<vtkLight>> lights = { DirectionalLight(0.3, 0.2, -1, 1, 0.8, 0.6),
    DirectionalLight(-1, 0.1, 0.2, 0.4, 0.5, 1), PointLight(-10, 12, 40, 0.9, 1, 0.7) };
  lights[2]->SetConeAngle(40);
  vtkNew<vtkFilteredVolumetricShadows> filter;
  filter->SetInputData(image);
  filter->SetOpacityFunction(otf);
  filter->SetChromaticAttenuation(true);
  for (const auto& l : lights)
  {
    filter->AddLight(l);
  }
  filter->Update();
  auto shaded = [&]()
  {
    return static_cast<int>(
      filter->GetOutput()->GetFieldData()->GetArray("ShadedLights")->GetTuple1(0));
  };
  EXPECT_EQ(shaded(), 3);
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(48);
  auto next = [&]()
  {
    random->Next();
    return random->GetValue();
  };
  int counts[4] = { 0, 0, 0, 0 };
  for (int edit = 0; edit < 60; ++edit)
  {
    vtkLight* light = lights[static_cast<size_t>(next() * 2.999)];
    const int kind = static_cast<int>(next() * 3.999);
    const bool wasOn = light->GetSwitch() != 0;
    if (kind == 0)
    {
      light->SetDiffuseColor(next(), next(), next());
      light->SetIntensity(0.5 + next());
    }
    else if (kind == 1)
    {
      volillum::SetLightRadius(light, light->GetPositional() ? 6 * next() : 20 * next());
    }
    else if (kind == 2)
    {
      light->SetSwitch(!light->GetSwitch());
    }
    else
    {
      double p[3];
      light->GetPosition(p);
      light->SetPosition(p[0] + next() - 0.5, p[1] + next() - 0.5, p[2]);
    }
    filter->Update();
    // The edited light alone is shaded again when it is on and its geometry changed.
    const int expected = kind != 0 && light->GetSwitch() && (kind != 2 || !wasOn) ? 1 : 0;
    EXPECT_EQ(shaded(), expected) << "edit " << edit << ", kind " << kind;
    if (kind < 2)
    {
      EXPECT_EQ(Passes(filter), 0) << "edit " << edit;
    }
    ++counts[kind];
    vtkNew<vtkFilteredVolumetricShadows> fresh;
    fresh->SetInputData(image);
    fresh->SetOpacityFunction(otf);
    fresh->SetChromaticAttenuation(true);
    for (const auto& l : lights)
    {
      fresh->AddLight(l);
    }
    fresh->Update();
    auto a = Result(filter), b = Result(fresh);
    double largest = 0.0;
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
    {
      largest = std::max(largest, std::abs(double(a->GetValue(i)) - b->GetValue(i)));
    }
    ASSERT_EQ(largest, 0.0) << "edit " << edit << ", kind " << kind;
  }
  for (int count : counts)
  {
    EXPECT_GT(count, 5);
  }
}

TEST(FilteredVolumetricShadows, KeptEmptyBlocksFollowTheTransferFunction)
{
  // Hard shadows skip the empty blocks of the classification along their near segments; the
  // blocks are kept between updates. After a transfer-function change that fills the empty
  // background, the kept filter must equal a new one exactly.
  auto image = Spheres(32);
  auto otf = Opacity();
  auto light = DirectionalLight(0.3, 0.2, -1);
  vtkNew<vtkFilteredVolumetricShadows> kept;
  kept->SetInputData(image);
  kept->SetOpacityFunction(otf);
  kept->SetFilterWidth(0);
  kept->AddLight(light);
  kept->Update();
  auto before = Result(kept);
  otf->AddPoint(0.0, 0.2);
  kept->Update();
  vtkNew<vtkFilteredVolumetricShadows> fresh;
  fresh->SetInputData(image);
  fresh->SetOpacityFunction(otf);
  fresh->SetFilterWidth(0);
  fresh->AddLight(light);
  fresh->Update();
  auto after = Result(kept);
  auto want = Result(fresh);
  double difference = 0.0, change = 0.0;
  for (vtkIdType i = 0; i < want->GetNumberOfValues(); ++i)
  {
    difference = std::max(difference, std::abs(double(after->GetValue(i)) - want->GetValue(i)));
    change = std::max(change, std::abs(double(after->GetValue(i)) - before->GetValue(i)));
  }
  EXPECT_GT(change, 0.1);
  EXPECT_EQ(difference, 0.0);
}

TEST(FilteredVolumetricShadows, PointAndSpotLightsAgreeWithTheReference)
{
  auto image = Spheres(64);
  auto otf = Opacity();
  auto outside = PointLight(-40, 32, 40, 1, 1, 0);
  auto inside = PointLight(32, 40, 8, 1, 1, 1);
  auto spot = PointLight(32, 32, 110, 1, 0.5, 0);
  spot->SetFocalPoint(32, 32, 0);
  spot->SetConeAngle(25);
  for (vtkLight* light : { outside.Get(), inside.Get(), spot.Get() })
  {
    int tables = 0;
    double whole = 0.0;
    const double rms = HardShadowDifference(image, otf, light, whole, &tables);
    const char* name = light == outside ? "point light outside"
      : light == inside                 ? "point light inside"
                                        : "spot light";
    std::cout << "FilterWidth 0, " << name
              << ": RMS relative difference to the reference over material " << rms
              << " (whole volume " << whole << "), tables built " << tables << std::endl;
    EXPECT_EQ(tables, 1);
    EXPECT_LE(rms, 0.02) << name;
    EXPECT_LE(whole, 0.1) << name;
  }
}

TEST(FilteredVolumetricShadows, PointLightTablesFollowTheLight)
{
  auto image = Spheres(32);
  vtkNew<vtkFilteredVolumetricShadows> filter;
  filter->SetInputData(image);
  filter->SetOpacityFunction(Opacity());
  auto light = PointLight(-20, 16, 16);
  filter->AddLight(light);
  filter->Update();
  EXPECT_EQ(Passes(filter), 1);
  light->SetDiffuseColor(0, 1, 0);
  filter->Update();
  EXPECT_EQ(Passes(filter), 0);
  light->SetPosition(-20, 18, 16);
  filter->Update();
  EXPECT_EQ(Passes(filter), 1);
}

TEST(FilteredVolumetricShadows, KeptAndRebuiltTablesEqualNewOnes)
{
  // Two point lights at one position keep a table each when one changes colour, and a
  // directional light that turns is rebuilt in its old table's memory: both equal a new
  // filter's result.
  auto image = Spheres(32);
  auto otf = Opacity();
  auto first = PointLight(-20, 16, 16);
  auto second = PointLight(-20, 16, 16, 0, 0.5, 1);
  auto directional = DirectionalLight(0.3, 0.2, -1);
  vtkNew<vtkFilteredVolumetricShadows> filter;
  filter->SetInputData(image);
  filter->SetOpacityFunction(otf);
  for (auto* light : { first.Get(), second.Get(), directional.Get() })
  {
    filter->AddLight(light);
  }
  filter->Update();
  EXPECT_EQ(Passes(filter), 3);
  auto differenceFromNew = [&]()
  {
    vtkNew<vtkFilteredVolumetricShadows> fresh;
    fresh->SetInputData(image);
    fresh->SetOpacityFunction(otf);
    for (auto* light : { first.Get(), second.Get(), directional.Get() })
    {
      fresh->AddLight(light);
    }
    fresh->Update();
    auto kept = Result(filter);
    auto expected = Result(fresh);
    double worst = 0.0;
    for (vtkIdType i = 0; i < kept->GetNumberOfValues(); ++i)
    {
      worst =
        std::max(worst, std::abs(static_cast<double>(kept->GetValue(i)) - expected->GetValue(i)));
    }
    return worst;
  };
  second->SetDiffuseColor(1, 0.5, 0);
  filter->Update();
  EXPECT_EQ(Passes(filter), 0);
  EXPECT_EQ(differenceFromNew(), 0.0);
  directional->SetFocalPoint(-0.2, 0.3, -1);
  filter->Update();
  EXPECT_EQ(Passes(filter), 1);
  EXPECT_EQ(differenceFromNew(), 0.0);
}

TEST(FilteredVolumetricShadows, PerLightTransmittancesAddUpToTheIllumination)
{
  auto image = Spheres(32);
  vtkNew<vtkFilteredVolumetricShadows> filter;
  filter->SetInputData(image);
  filter->SetOpacityFunction(Opacity());
  filter->PerLightTransmittanceOn();
  filter->AddLight(DirectionalLight(0.2, 0.1, -1, 1, 0.5, 0));
  auto off = PointLight(50, 16, 16);
  off->SwitchOff();
  filter->AddLight(off);
  auto point = PointLight(-20, 16, 16, 0, 0.5, 1);
  point->SetIntensity(2);
  filter->AddLight(point);
  filter->Update();
  vtkPointData* pd = filter->GetOutput()->GetPointData();
  ASSERT_NE(pd->GetArray("Transmittance0"), nullptr);
  EXPECT_EQ(pd->GetArray("Transmittance1"), nullptr); // switched off
  ASSERT_NE(pd->GetArray("Transmittance2"), nullptr);
  vtkDataArray* t0 = pd->GetArray("Transmittance0");
  vtkDataArray* t2 = pd->GetArray("Transmittance2");
  vtkDataArray* illumination = pd->GetArray("Illumination");
  const double radiance0[3] = { 1, 0.5, 0 }, radiance2[3] = { 0, 1, 2 };
  double worst = 0.0;
  for (vtkIdType i = 0; i < illumination->GetNumberOfTuples(); ++i)
  {
    EXPECT_GE(t0->GetComponent(i, 0), 0.0);
    EXPECT_LE(t0->GetComponent(i, 0), 1.0);
    for (int c = 0; c < 3; ++c)
    {
      const double expected =
        radiance0[c] * t0->GetComponent(i, 0) + radiance2[c] * t2->GetComponent(i, 0);
      worst = std::max(worst, std::abs(illumination->GetComponent(i, c) - expected));
    }
  }
  EXPECT_LE(worst, 1e-5);
}

TEST(FilteredVolumetricShadows, BadTableResolutionIsAnError)
{
  auto image = Spheres(16);
  vtkNew<vtkFilteredVolumetricShadows> filter;
  vtkNew<ErrorCounter> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(image);
  filter->SetSATResolutionScale(0.3);
  filter->AddLight(DirectionalLight(0, 0, -1));
  filter->Update();
  EXPECT_EQ(errors->Count, 1);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}
