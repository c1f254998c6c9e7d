// Tests of the image filters' ambient occlusion: the ambient light adds AmbientOcclusion x
// the transmittance array to the lights' illumination under every method, and the
// transmittance is computed again only when the classification, the radius or the
// resolution change, not when a light or the strength does.
#include "IlluminationTestUtilities.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkColorTransferFunction.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using volillumtest::DirectionalLight;
using volillumtest::Result;

namespace
{
vtkSmartPointer<vtkFloatArray> Occlusion(vtkImageAlgorithm* filter)
{
  auto copy = vtkSmartPointer<vtkFloatArray>::New();
  vtkDataArray* array = filter->GetOutput()->GetPointData()->GetArray("AmbientOcclusion");
  if (array)
  {
    copy->DeepCopy(array);
  }
  return copy;
}

long long OcclusionPoints(vtkImageAlgorithm* filter)
{
  vtkDataArray* array = filter->GetOutput()->GetFieldData()->GetArray("AmbientOcclusionPoints");
  return array ? static_cast<long long>(array->GetTuple1(0)) : -1;
}

// Largest difference between two arrays of the same length, or infinity.
double LargestDifference(vtkFloatArray* a, vtkFloatArray* b)
{
  if (a->GetNumberOfValues() != b->GetNumberOfValues())
  {
    return HUGE_VAL;
  }
  double largest = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    largest = std::max(largest, std::abs(double(a->GetValue(i)) - b->GetValue(i)));
  }
  return largest;
}

template <typename Filter>
void CheckAmbientLight()
{
  vtkNew<vtkIlluminationPhantomSource> source;
  source->SetDimensions(32, 32, 32);
  source->Update();
  auto otf = volillumtest::RampOpacity(source->GetOutput(), 0.3);
  auto filter = volillumtest::ImageFilter<Filter>(source->GetOutput(), otf);
  auto light = DirectionalLight(0.3, 0.2, -1);
  filter->AddLight(light);
  filter->Update();
  auto lightsOnly = Result(filter);
  EXPECT_EQ(filter->GetOutput()->GetPointData()->GetArray("AmbientOcclusion"), nullptr);

  filter->SetAmbientOcclusion(0.5);
  filter->SetAmbientOcclusionRadius(6.0);
  filter->Update();
  const long long points = filter->GetOutput()->GetNumberOfPoints();
  EXPECT_EQ(OcclusionPoints(filter), points);
  auto occlusion = Occlusion(filter);
  ASSERT_EQ(occlusion->GetNumberOfValues(), 3 * points);
  auto lit = Result(filter);
  double darkest = 1.0, brightest = 0.0, largest = 0.0;
  for (vtkIdType i = 0; i < lit->GetNumberOfValues(); ++i)
  {
    const double t = occlusion->GetValue(i);
    darkest = std::min(darkest, t);
    brightest = std::max(brightest, t);
    largest = std::max(largest, std::abs(lit->GetValue(i) - lightsOnly->GetValue(i) - 0.5 * t));
  }
  EXPECT_LT(largest, 1e-6);
  EXPECT_LT(darkest, 0.5);    // inside the spheres
  EXPECT_GT(brightest, 0.99); // in the empty corners
  EXPECT_LE(brightest, 1.0);

  // A light edit keeps the transmittance; a strength edit only rescales it.
  light->SetFocalPoint(-0.2, 0.4, -1);
  filter->Update();
  EXPECT_EQ(OcclusionPoints(filter), 0);
  EXPECT_EQ(LargestDifference(Occlusion(filter), occlusion), 0.0);
  filter->SetAmbientOcclusion(1.0);
  filter->Update();
  EXPECT_EQ(OcclusionPoints(filter), 0);
  // The radius and the opacity make a new one, equal to a new filter's.
  filter->SetAmbientOcclusionRadius(3.0);
  filter->Update();
  EXPECT_EQ(OcclusionPoints(filter), points);
  EXPECT_GT(LargestDifference(Occlusion(filter), occlusion), 0.05);
  otf->AddPoint(100.0, 0.02);
  filter->Update();
  EXPECT_EQ(OcclusionPoints(filter), points);
  auto fresh = volillumtest::ImageFilter<Filter>(source->GetOutput(), otf);
  fresh->AddLight(light);
  fresh->SetAmbientOcclusion(1.0);
  fresh->SetAmbientOcclusionRadius(3.0);
  fresh->Update();
  EXPECT_EQ(LargestDifference(Occlusion(fresh), Occlusion(filter)), 0.0);
  EXPECT_EQ(LargestDifference(Result(fresh), Result(filter)), 0.0);
  // Off again: no array, and the lights alone.
  filter->SetAmbientOcclusion(0.0);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetPointData()->GetArray("AmbientOcclusion"), nullptr);
}
}

TEST(ImageAmbientOcclusion, FilteredShadowsAddTheAmbientLightAndKeepItAcrossLightEdits)
{
  CheckAmbientLight<vtkFilteredVolumetricShadows>();
}

TEST(ImageAmbientOcclusion, PropagationAddsTheAmbientLightAndKeepsItAcrossLightEdits)
{
  CheckAmbientLight<vtkMultiLightIlluminationVolume>();
}

TEST(ImageAmbientOcclusion, TheReferenceAddsTheAmbientLightAndKeepsItAcrossLightEdits)
{
  CheckAmbientLight<vtkRayMarchedIllumination>();
}

TEST(ImageAmbientOcclusion, ChromaticAttenuationColoursTheTransmittance)
{
  vtkNew<vtkIlluminationPhantomSource> source;
  source->SetDimensions(24, 24, 24);
  source->Update();
  auto otf = volillumtest::RampOpacity(source->GetOutput(), 0.3);
  auto filter = volillumtest::ImageFilter<vtkFilteredVolumetricShadows>(source->GetOutput(), otf);
  vtkNew<vtkColorTransferFunction> ctf;
  double range[2];
  source->GetOutput()->GetPointData()->GetScalars()->GetRange(range);
  ctf->AddRGBPoint(range[0], 1.0, 0.2, 0.2);
  ctf->AddRGBPoint(range[1], 1.0, 0.2, 0.2);
  filter->SetColorTransferFunction(ctf);
  filter->SetAmbientOcclusion(1.0);
  filter->Update();
  auto grey = Occlusion(filter);
  filter->SetChromaticAttenuation(true);
  filter->Update();
  auto red = Occlusion(filter);
  // Red material lets red through (k = 0): red is unoccluded, green and blue as before
  // within k = 0.8 of the extinction (brighter).
  double redDarkest = 1.0, greenBrighter = 0.0;
  for (vtkIdType p = 0; p < red->GetNumberOfTuples(); ++p)
  {
    redDarkest = std::min(redDarkest, double(red->GetComponent(p, 0)));
    greenBrighter =
      std::max(greenBrighter, double(red->GetComponent(p, 1) - grey->GetComponent(p, 1)));
    EXPECT_GE(red->GetComponent(p, 1) + 1e-6, grey->GetComponent(p, 1));
  }
  EXPECT_NEAR(redDarkest, 1.0, 1e-6);
  EXPECT_GT(greenBrighter, 0.01);
}
