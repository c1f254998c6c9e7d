// Bad and extreme input for the image illumination filters: very distant lights are far
// (directional) lights, never overflows; too bright lights, inconsistent scalars and
// absurd geometry are refused with an error and an empty output; a tiny opacity unit
// distance still gives finite illumination.
#include "IlluminationTestUtilities.h"
#include "ParallelMessages.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkDummyController.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using volillumtest::DirectionalLight;
using volillumtest::ErrorCounter;

namespace
{
constexpr int N = 24;

vtkSmartPointer<vtkImageData> Spheres()
{
  vtkNew<vtkIlluminationPhantomSource> source;
  source->SetScene(vtkIlluminationPhantomSource::ThreeSpheres);
  source->SetDimensions(N, N, N);
  source->Update();
  return source->GetOutput();
}

// One filter of each image method, lit by the given lights.
std::vector<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>> Filters(
  vtkImageData* image, const std::vector<vtkSmartPointer<vtkLight>>& lights)
{
  std::vector<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>> filters = {
    vtkSmartPointer<vtkRayMarchedIllumination>::New(),
    vtkSmartPointer<vtkMultiLightIlluminationVolume>::New(),
    vtkSmartPointer<vtkFilteredVolumetricShadows>::New()
  };
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(1.0, 0.3);
  for (auto& f : filters)
  {
    f->SetInputData(image);
    f->SetOpacityFunction(otf);
    for (const auto& light : lights)
    {
      f->AddLight(light);
    }
  }
  return filters;
}

vtkFloatArray* Illumination(vtkIlluminationVolumeAlgorithm* filter)
{
  filter->Update();
  return vtkFloatArray::SafeDownCast(filter->GetOutput()->GetPointData()->GetArray("Illumination"));
}

double MaxDifference(vtkFloatArray* a, vtkFloatArray* b)
{
  double worst = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    worst = std::max(worst, static_cast<double>(std::abs(a->GetValue(i) - b->GetValue(i))));
  }
  return worst;
}

vtkSmartPointer<vtkLight> Light(bool positional, const std::array<double, 3>& position,
  const std::array<double, 3>& focal, double cone = 180.0)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetPositional(positional);
  light->SetPosition(position.data());
  light->SetFocalPoint(focal.data());
  light->SetConeAngle(cone);
  return light;
}
}

TEST(BadInput, VeryDistantLightsAreFarLights)
{
  auto image = Spheres();
  const double c = 0.5 * (N - 1);
  const std::array<double, 3> d = { { 0.3, -0.2, -1.0 } }; // direction light travels
  const std::array<double, 3> centre = { { c, c, c } };
  auto reference = Filters(image, { DirectionalLight(d[0], d[1], d[2]) });
  struct Case
  {
    const char* What;
    vtkSmartPointer<vtkLight> Light;
    double Tolerance; // largest difference to the directional light
  };
  const double big = 1e200, huge = 1e308;
  const std::vector<Case> cases = {
    { "directional light at 1e200",
      Light(false, { { -d[0] * big, -d[1] * big, -d[2] * big } }, { { 0.0, 0.0, 0.0 } }), 1e-5 },
    { "directional light whose direction overflows",
      Light(false, { { -d[0] * huge, -d[1] * huge, -d[2] * huge } },
        { { d[0] * huge, d[1] * huge, d[2] * huge } }),
      1e-5 },
    { "point light at 1e200",
      Light(true, { { c - d[0] * big, c - d[1] * big, c - d[2] * big } }, centre), 1e-5 },
    { "spot light at 1e200 aimed at the volume",
      Light(true, { { c - d[0] * big, c - d[1] * big, c - d[2] * big } }, centre, 20.0), 1e-5 },
  };
  for (const Case& k : cases)
  {
    auto filters = Filters(image, { k.Light });
    for (size_t m = 0; m < filters.size(); ++m)
    {
      vtkFloatArray* got = Illumination(filters[m]);
      vtkFloatArray* want = Illumination(reference[m]);
      ASSERT_NE(got, nullptr) << k.What << ", method " << m;
      const double difference = MaxDifference(got, want);
      EXPECT_LE(difference, k.Tolerance) << k.What << ", " << filters[m]->GetClassName();
      std::cout << k.What << ", " << filters[m]->GetClassName() << ": largest difference "
                << difference << "\n";
    }
  }
  // A far spot light aimed away from the volume lights nothing.
  auto away = Light(true, { { c - d[0] * big, c - d[1] * big, c - d[2] * big } },
    { { c - 2 * d[0] * big, c - 2 * d[1] * big, c - 2 * d[2] * big } }, 20.0);
  for (auto& f : Filters(image, { away }))
  {
    double range[2];
    Illumination(f)->GetRange(range, -1);
    EXPECT_EQ(range[1], 0.0) << f->GetClassName();
  }
}

TEST(BadInput, TooBrightOrAimlessLightsAndInconsistentScalarsAreRefused)
{
  auto image = Spheres();
  auto bright = DirectionalLight(0, 0, -1);
  bright->SetIntensity(1e10);
  vtkNew<vtkImageData> shortScalars;
  shortScalars->CopyStructure(image);
  vtkNew<vtkFloatArray> values;
  values->SetNumberOfTuples(image->GetNumberOfPoints() - 1);
  values->FillValue(0.5f);
  shortScalars->GetPointData()->SetScalars(values);
  vtkNew<vtkImageData> farAway;
  farAway->DeepCopy(image);
  farAway->SetOrigin(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0);
  vtkNew<vtkImageData> overflowing;
  overflowing->DeepCopy(image);
  overflowing->SetSpacing(1e300, 1.0, 1.0);
  struct Case
  {
    const char* What;
    vtkImageData* Input;
    vtkSmartPointer<vtkLight> Light;
    const char* Message;
  };
  const std::vector<Case> cases = {
    { "intensity 1e10", image, bright, "too bright" },
    { "one scalar less than points", shortScalars, DirectionalLight(0, 0, -1), "inconsistent" },
    { "NaN origin", farAway, DirectionalLight(0, 0, -1), "bounds" },
    { "spacing 1e300", overflowing, DirectionalLight(0, 0, -1), "bounds" },
    { "directional light at its focal point", image, Light(false, { { 5, 5, 5 } }, { { 5, 5, 5 } }),
      "no direction" },
    { "spot light aimed at itself", image, Light(true, { { -5, 5, 5 } }, { { -5, 5, 5 } }, 30.0),
      "no direction" },
    { "negative cone angle", image, Light(true, { { -5, 5, 5 } }, { { 5, 5, 5 } }, -10.0),
      "cone angle" },
    { "spot light of cone angle 0", image, Light(true, { { -5, 5, 5 } }, { { 5, 5, 5 } }, 0.0),
      "cone angle" },
  };
  for (const Case& k : cases)
  {
    for (auto& f : Filters(k.Input, { k.Light }))
    {
      vtkNew<ErrorCounter> errors;
      f->AddObserver(vtkCommand::ErrorEvent, errors);
      f->Update();
      EXPECT_EQ(errors->Count, 1) << k.What << ", " << f->GetClassName();
      EXPECT_NE(errors->LastMessage.find(k.Message), std::string::npos)
        << k.What << ": " << errors->LastMessage;
      EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0) << k.What << ", " << f->GetClassName();
    }
  }
}

// A light that is off is not checked: ParaView's lights table adds rows of zeros (a
// directional light without a direction, switched off).
TEST(BadInput, LightsThatAreOffAreNotChecked)
{
  auto image = Spheres();
  auto off = Light(false, { { 0, 0, 0 } }, { { 0, 0, 0 } }, 0.0);
  off->SwitchOff();
  for (auto& f : Filters(image, { DirectionalLight(0, 0, -1), off }))
  {
    vtkNew<ErrorCounter> errors;
    f->AddObserver(vtkCommand::ErrorEvent, errors);
    f->Update();
    EXPECT_EQ(errors->Count, 0) << f->GetClassName() << ": " << errors->LastMessage;
    EXPECT_GT(f->GetOutput()->GetNumberOfPoints(), 0) << f->GetClassName();
  }
}

TEST(BadInput, ExtremeButValidSettingsGiveFiniteIllumination)
{
  auto image = Spheres();
  vtkNew<vtkImageData> wide;
  wide->DeepCopy(image);
  wide->SetSpacing(1e30, 1e30, 1e30);
  struct Case
  {
    const char* What;
    vtkImageData* Input;
    double UnitDistance;
  };
  for (const Case& k :
    { Case{ "unit distance 1e-300", image, 1e-300 }, Case{ "spacing 1e30", wide, 1e30 } })
  {
    for (auto& f : Filters(k.Input, { DirectionalLight(0.3, -0.2, -1), DirectionalLight(0, 1, 0) }))
    {
      f->SetScalarOpacityUnitDistance(k.UnitDistance);
      vtkFloatArray* got = Illumination(f);
      ASSERT_NE(got, nullptr) << k.What << ", " << f->GetClassName();
      bool finite = true;
      double lo = 0.0, hi = 0.0;
      for (vtkIdType i = 0; i < got->GetNumberOfValues(); ++i)
      {
        finite = finite && std::isfinite(got->GetValue(i));
        lo = std::min(lo, static_cast<double>(got->GetValue(i)));
        hi = std::max(hi, static_cast<double>(got->GetValue(i)));
      }
      EXPECT_TRUE(finite) << k.What << ", " << f->GetClassName();
      EXPECT_GE(lo, -1e-6) << k.What << ", " << f->GetClassName();
      EXPECT_LE(hi, 2.0 + 1e-4) << k.What << ", " << f->GetClassName();
      std::cout << k.What << ", " << f->GetClassName() << ": illumination in [" << lo << ", " << hi
                << "]\n";
    }
  }
}

TEST(BadInput, NonFiniteSettingsAreRefusedAndTheOldValueKept)
{
  vtkNew<vtkFilteredVolumetricShadows> shadows;
  vtkNew<vtkRayMarchedIllumination> reference;
  vtkNew<ErrorCounter> errors;
  shadows->AddObserver(vtkCommand::ErrorEvent, errors);
  reference->AddObserver(vtkCommand::ErrorEvent, errors);
  shadows->SetFilterWidth(5.0);
  shadows->SetFilterWidth(std::nan(""));
  reference->SetStepFraction(std::numeric_limits<double>::infinity());
  EXPECT_EQ(errors->Count, 2);
  EXPECT_EQ(shadows->GetFilterWidth(), 5.0);
  EXPECT_EQ(reference->GetStepFraction(), 0.5);
  shadows->SetFilterWidth(1e9); // finite: clamped
  EXPECT_EQ(shadows->GetFilterWidth(), 1000.0);
}

// In a parallel run every process's errors and warnings are printed once, by the first
// process, with the processes that reported them (ParaView shows a client only the first
// server process's messages). The MPI test checks this on 2 processes; here the report's
// wording, and the round trip through the observers on a one-process controller.
TEST(BadInput, ParallelMessagesArePrintedOnceByTheFirstProcess)
{
  using Message = volillum::ParallelMessages::Message;
  const std::string none;
  const std::vector<std::string> collected = { std::string("Ea\0Wb\0", 6), std::string("Ea\0", 3),
    std::string("Ea\0", 3), none, none, std::string("Ea\0Ec\0", 6) };
  const std::vector<Message> report = volillum::ParallelMessages::Report(collected);
  ASSERT_EQ(report.size(), 3u);
  EXPECT_TRUE(report[0].Error);
  EXPECT_EQ(report[0].Text, "Processes 0-2, 5 of 6: a");
  EXPECT_FALSE(report[1].Error);
  EXPECT_EQ(report[1].Text, "Process 0 of 6: b");
  EXPECT_TRUE(report[2].Error);
  EXPECT_EQ(report[2].Text, "Process 5 of 6: c");

  vtkNew<vtkDummyController> controller;
  vtkNew<vtkRayMarchedIllumination> filter;
  vtkNew<ErrorCounter> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  {
    volillum::ParallelMessages messages(controller, filter);
    vtkErrorWithObjectMacro(filter, << "The same error.");
    vtkErrorWithObjectMacro(filter, << "The same error.");
  }
  EXPECT_EQ(errors->Count, 3); // both, then the report
  EXPECT_NE(errors->LastMessage.find(": Process 0 of 1: The same error.\n"), std::string::npos)
    << errors->LastMessage;
}
