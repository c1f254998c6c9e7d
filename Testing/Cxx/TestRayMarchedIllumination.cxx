// Tests of the reference filter vtkRayMarchedIllumination against analytic transmittance,
// linearity in the lights, spot-cone geometry, resolution scales and bad input.
#include "IlluminationClassify.h"
#include "IlluminationTestUtilities.h"
#include "RayMarchKernel.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using volillumtest::DirectionalLight;
using volillumtest::ErrorCounter;
using volillumtest::PointLight;

namespace
{
constexpr int N = 64;
constexpr int SlabBegin = 16;
constexpr int SlabEnd = 47;
constexpr double SlabOpacity = 0.05; // opacity per unit distance inside the slab

vtkSmartPointer<vtkImageData> MakeScene(int scene)
{
  vtkNew<vtkIlluminationPhantomSource> source;
  source->SetScene(scene);
  source->SetDimensions(N, N, N);
  source->SetSlabBegin(SlabBegin);
  source->SetSlabEnd(SlabEnd);
  source->Update();
  return source->GetOutput();
}

// Opacity 0 outside, SlabOpacity inside; grey attenuation.
vtkSmartPointer<vtkRayMarchedIllumination> MakeSlabFilter(vtkImageData* slab)
{
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(1.0, SlabOpacity);
  auto filter = vtkSmartPointer<vtkRayMarchedIllumination>::New();
  filter->SetInputData(slab);
  filter->SetOpacityFunction(otf);
  filter->ChromaticAttenuationOff();
  filter->SetStepFraction(0.1);
  return filter;
}

// Integral of the linearly interpolated slab indicator over z in [a, b] (a <= b): the
// indicator is 1 on [SlabBegin, SlabEnd], 0 beyond one voxel outside, linear between.
double SlabIntegral(double a, double b)
{
  auto cumulative = [](double z)
  {
    // Antiderivative of the trapezoid profile from -infinity.
    const double z0 = SlabBegin - 1.0, z1 = SlabBegin, z2 = SlabEnd, z3 = SlabEnd + 1.0;
    if (z <= z0)
      return 0.0;
    if (z <= z1)
      return 0.5 * (z - z0) * (z - z0);
    if (z <= z2)
      return 0.5 + (z - z1);
    if (z <= z3)
      return 0.5 + (z2 - z1) + (z - z2) - 0.5 * (z - z2) * (z - z2);
    return 1.0 + (z2 - z1);
  };
  return cumulative(b) - cumulative(a);
}

// Analytic transmittance from point p along unit direction d over length tMax.
double AnalyticTransmittance(const double p[3], const double d[3], double tMax)
{
  const double sigma = -std::log(1.0 - SlabOpacity);
  if (std::abs(d[2]) < 1e-12)
  {
    const double inside = (p[2] >= SlabBegin && p[2] <= SlabEnd) ? 1.0 : 0.0;
    return std::exp(-sigma * inside * tMax);
  }
  const double zEnd = p[2] + tMax * d[2];
  const double integral = SlabIntegral(std::min(p[2], zEnd), std::max(p[2], zEnd));
  return std::exp(-sigma * integral / std::abs(d[2]));
}

double BoxExit(const double p[3], const double d[3])
{
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    if (d[a] > 0)
      t = std::min(t, (N - 1 - p[a]) / d[a]);
    else if (d[a] < 0)
      t = std::min(t, -p[a] / d[a]);
  }
  return t;
}

vtkFloatArray* Illumination(vtkRayMarchedIllumination* filter)
{
  return vtkFloatArray::SafeDownCast(filter->GetOutput()->GetPointData()->GetArray("Illumination"));
}

// Largest relative difference between the red channel and the analytic transmittance
// toward a light, over every point.
template <typename Direction>
double MaxRelativeError(vtkRayMarchedIllumination* filter, Direction towardLight)
{
  vtkFloatArray* result = Illumination(filter);
  double worst = 0.0;
  for (int k = 0; k < N; ++k)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i)
      {
        const double p[3] = { double(i), double(j), double(k) };
        double d[3], tMax;
        towardLight(p, d, tMax);
        const double expected = AnalyticTransmittance(p, d, tMax);
        const double got = result->GetTypedComponent(i + N * (j + N * k), 0);
        worst = std::max(worst, std::abs(got - expected) / expected);
      }
  return worst;
}
}

TEST(RayMarchedIllumination, SlabDirectionalLightMatchesAnalyticTransmittance)
{
  auto slab = MakeScene(vtkIlluminationPhantomSource::Slab);
  for (const auto& travel :
    { std::array<double, 3>{ 0, 0, -1 }, std::array<double, 3>{ 0.3, -0.2, -1 } })
  {
    auto filter = MakeSlabFilter(slab);
    filter->AddLight(DirectionalLight(travel[0], travel[1], travel[2]));
    filter->Update();
    double toLight[3] = { -travel[0], -travel[1], -travel[2] };
    vtkMath::Normalize(toLight);
    const double error = MaxRelativeError(filter,
      [&](const double p[3], double d[3], double& t)
      {
        std::copy(toLight, toLight + 3, d);
        t = BoxExit(p, d);
      });
    std::cout << "directional (" << travel[0] << "," << travel[1] << "," << travel[2]
              << ") max relative error " << error << std::endl;
    EXPECT_LE(error, 1e-3);
  }
}

TEST(RayMarchedIllumination, SlabPointLightMatchesAnalyticTransmittance)
{
  auto slab = MakeScene(vtkIlluminationPhantomSource::Slab);
  auto filter = MakeSlabFilter(slab);
  const double light[3] = { 20.0, 40.0, 110.0 };
  filter->AddLight(PointLight(light[0], light[1], light[2]));
  filter->Update();
  const double error = MaxRelativeError(filter,
    [&](const double p[3], double d[3], double& t)
    {
      for (int a = 0; a < 3; ++a)
        d[a] = light[a] - p[a];
      const double distance = vtkMath::Normalize(d);
      t = std::min(distance, BoxExit(p, d));
    });
  std::cout << "point light max relative error " << error << std::endl;
  EXPECT_LE(error, 1e-3);
}

TEST(RayMarchedIllumination, TwoLightsEqualTheSumOfEachAlone)
{
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  auto yellow = PointLight(-20, 32, 32, 1, 1, 0);
  auto blue = PointLight(90, 40, 30, 0, 0, 1);
  blue->SetIntensity(2.0);
  auto run = [&](std::initializer_list<vtkLight*> lights)
  {
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->SetInputData(spheres);
    for (auto* l : lights)
      filter->AddLight(l);
    filter->Update();
    auto out = vtkSmartPointer<vtkFloatArray>::New();
    out->DeepCopy(Illumination(filter));
    return out;
  };
  auto both = run({ yellow, blue });
  auto a = run({ yellow });
  auto b = run({ blue });
  double worst = 0.0, largest = 0.0;
  for (vtkIdType t = 0; t < both->GetNumberOfTuples(); ++t)
    for (int c = 0; c < 3; ++c)
    {
      const double sum = a->GetTypedComponent(t, c) + b->GetTypedComponent(t, c);
      worst = std::max(worst, std::abs(both->GetTypedComponent(t, c) - sum));
      largest = std::max(largest, sum);
    }
  EXPECT_GT(largest, 1.0); // both lights do reach the volume
  EXPECT_LE(worst / largest, 1e-5);
}

TEST(RayMarchedIllumination, SpotConeMasksPointsOutsideTheCone)
{
  auto slab = MakeScene(vtkIlluminationPhantomSource::Slab);
  const double position[3] = { 31.5, 31.5, 100.0 };
  const double coneAngle = 15.0, exponent = 2.0;
  auto spot = PointLight(position[0], position[1], position[2]);
  spot->SetFocalPoint(31.5, 31.5, 0.0);
  spot->SetConeAngle(coneAngle);
  spot->SetExponent(exponent);
  auto point = PointLight(position[0], position[1], position[2]);

  auto spotFilter = MakeSlabFilter(slab);
  spotFilter->AddLight(spot);
  spotFilter->Update();
  auto pointFilter = MakeSlabFilter(slab);
  pointFilter->AddLight(point);
  pointFilter->Update();
  vtkFloatArray* s = Illumination(spotFilter);
  vtkFloatArray* p = Illumination(pointFilter);
  int inside = 0, outside = 0;
  for (int k = 0; k < N; ++k)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i)
      {
        const vtkIdType id = i + N * (j + N * k);
        double v[3] = { i - position[0], j - position[1], k - position[2] };
        vtkMath::Normalize(v);
        const double cosine = -v[2]; // the cone axis points down -z
        const double angle = vtkMath::DegreesFromRadians(std::acos(cosine));
        if (std::abs(angle - coneAngle) < 0.01)
          continue; // on the cone boundary either answer is right
        const double expected =
          angle < coneAngle ? std::pow(cosine, exponent) * p->GetTypedComponent(id, 0) : 0.0;
        (angle < coneAngle ? inside : outside)++;
        EXPECT_NEAR(s->GetTypedComponent(id, 0), expected, 1e-6)
          << "point " << i << " " << j << " " << k;
      }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(RayMarchedIllumination, ResolutionScalesCoverTheSameBounds)
{
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  auto light = PointLight(-20, 32, 32);
  vtkNew<vtkRayMarchedIllumination> full;
  full->SetInputData(spheres);
  full->AddLight(light);
  full->Update();
  for (double scale : { 0.5, 0.25 })
  {
    vtkNew<vtkRayMarchedIllumination> coarse;
    coarse->SetInputData(spheres);
    coarse->AddLight(light);
    coarse->SetResolutionScale(scale);
    coarse->Update();
    vtkImageData* out = coarse->GetOutput();
    double inBounds[6], outBounds[6];
    spheres->GetBounds(inBounds);
    out->GetBounds(outBounds);
    for (int a = 0; a < 6; ++a)
      EXPECT_NEAR(outBounds[a], inBounds[a], 1e-9) << "scale " << scale;
    int dims[3];
    out->GetDimensions(dims);
    const int expected = static_cast<int>(std::lround((N - 1) * scale)) + 1;
    EXPECT_EQ(dims[0], expected);
    // Every coarse point that coincides with a full-resolution point has its value.
    const int stride = static_cast<int>(std::lround(1.0 / scale));
    if ((N - 1) % stride == 0)
    {
      vtkFloatArray* c = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray("Illumination"));
      vtkFloatArray* f = Illumination(full);
      for (int k = 0; k < dims[2]; k += 3)
        for (int j = 0; j < dims[1]; j += 3)
          for (int i = 0; i < dims[0]; ++i)
          {
            const vtkIdType fine = stride * i + N * (stride * j + N * stride * k);
            EXPECT_NEAR(c->GetTypedComponent(i + dims[0] * (j + dims[1] * k), 0),
              f->GetTypedComponent(fine, 0), 1e-5);
          }
    }
  }
}

TEST(RayMarchedIllumination, ReportsUpdateFieldData)
{
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  vtkNew<vtkRayMarchedIllumination> filter;
  filter->SetInputData(spheres);
  filter->AddLight(PointLight(-20, 32, 32));
  auto off = PointLight(90, 32, 32);
  off->SwitchOff();
  filter->AddLight(off);
  filter->AddLight(DirectionalLight(0, 0, -1));
  filter->Update();
  vtkFieldData* fd = filter->GetOutput()->GetFieldData();
  ASSERT_NE(fd->GetArray("UpdateMode"), nullptr);
  EXPECT_EQ(fd->GetArray("UpdateMode")->GetTuple1(0), 0);
  EXPECT_EQ(fd->GetArray("PropagationPasses")->GetTuple1(0), 2); // two lights are on
  EXPECT_GT(fd->GetArray("UpdateSeconds")->GetTuple1(0), 0.0);
}

// ---------------------------------------------------------------------------- bad input
namespace
{
// Runs the filter on input and returns the number of errors it reported.
int RunAndCountErrors(vtkRayMarchedIllumination* filter, vtkDataObject* input)
{
  vtkNew<ErrorCounter> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(input);
  filter->Update();
  return errors->Count;
}
}

TEST(RayMarchedIllumination, BadInputGivesAnErrorAndAnEmptyOutput)
{
  {
    vtkNew<vtkImageData> noScalars;
    noScalars->SetDimensions(8, 8, 8);
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->AddLight(DirectionalLight(0, 0, -1));
    EXPECT_EQ(RunAndCountErrors(filter, noScalars), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
  {
    vtkNew<vtkImageData> flat;
    flat->SetDimensions(8, 8, 1);
    flat->AllocateScalars(VTK_FLOAT, 1);
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->AddLight(DirectionalLight(0, 0, -1));
    EXPECT_EQ(RunAndCountErrors(filter, flat), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
  {
    vtkNew<vtkImageData> empty;
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->AddLight(DirectionalLight(0, 0, -1));
    EXPECT_GE(RunAndCountErrors(filter, empty), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
  {
    vtkNew<vtkImageData> strings;
    strings->SetDimensions(4, 4, 4);
    vtkNew<vtkStringArray> names;
    names->SetName("labels");
    names->SetNumberOfValues(64);
    strings->GetPointData()->AddArray(names);
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "labels");
    filter->AddLight(DirectionalLight(0, 0, -1));
    EXPECT_EQ(RunAndCountErrors(filter, strings), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  {
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->AddLight(DirectionalLight(0, 0, -1));
    filter->SetResolutionScale(0.3);
    EXPECT_EQ(RunAndCountErrors(filter, spheres), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
  {
    vtkNew<vtkRayMarchedIllumination> filter;
    auto light = PointLight(std::nan(""), 0, 0);
    filter->AddLight(light);
    EXPECT_EQ(RunAndCountErrors(filter, spheres), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
  {
    vtkNew<vtkRayMarchedIllumination> filter;
    filter->SetNumberOfLightParameters(13);
    vtkNew<ErrorCounter> errors;
    filter->AddObserver(vtkCommand::ErrorEvent, errors);
    filter->SetNumberOfLightParameters(13);
    EXPECT_EQ(errors->Count, 1);
    EXPECT_EQ(filter->GetNumberOfLights(), 0);
    // Updates refuse the list (an error, an empty output) until it is whole lights again.
    EXPECT_EQ(RunAndCountErrors(filter, spheres), 1);
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
    filter->SetNumberOfLightParameters(15);
    EXPECT_EQ(RunAndCountErrors(filter, spheres), 0);
    EXPECT_GT(filter->GetOutput()->GetNumberOfPoints(), 0);
  }
}

TEST(RayMarchedIllumination, ZeroLightsGiveDarkness)
{
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  vtkNew<vtkRayMarchedIllumination> filter;
  EXPECT_EQ(RunAndCountErrors(filter, spheres), 0);
  double range[2];
  Illumination(filter)->GetRange(range, -1);
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 0.0);
}

namespace
{
// Whether point id of the N^3 scene lies in the 8^3 region from (x0, 28, 28).
bool InRegion(vtkIdType id, int x0)
{
  const int i = id % N, j = (id / N) % N, k = id / (N * N);
  return k >= 28 && k < 36 && j >= 28 && j < 36 && i >= x0 && i < x0 + 8;
}

// The scene with its scalars as floats ("Density"), point id's value v made value(id, v).
vtkSmartPointer<vtkImageData> AsFloats(
  vtkImageData* scene, const std::function<double(vtkIdType, double)>& value)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->CopyStructure(scene);
  vtkNew<vtkFloatArray> values;
  values->SetName("Density");
  values->SetNumberOfTuples(scene->GetNumberOfPoints());
  for (vtkIdType id = 0; id < values->GetNumberOfTuples(); ++id)
  {
    values->SetValue(
      id, static_cast<float>(value(id, scene->GetPointData()->GetScalars()->GetTuple1(id))));
  }
  image->GetPointData()->SetScalars(values);
  return image;
}

// The illumination of a point light at (-20, 32, 32) on the image (with `opacity` when
// given), run without errors.
vtkSmartPointer<vtkFloatArray> LitByPointLight(
  vtkImageData* image, vtkPiecewiseFunction* opacity = nullptr)
{
  vtkNew<vtkRayMarchedIllumination> filter;
  if (opacity)
  {
    filter->SetOpacityFunction(opacity);
  }
  filter->AddLight(PointLight(-20, 32, 32));
  EXPECT_EQ(RunAndCountErrors(filter, image), 0);
  auto out = vtkSmartPointer<vtkFloatArray>::New();
  out->DeepCopy(Illumination(filter));
  return out;
}
}

TEST(RayMarchedIllumination, NaNScalarsAreEmptySpace)
{
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  // The same scene as floats, once with NaN and once with 0 where the first sphere's
  // centre region is.
  auto withNaN =
    AsFloats(spheres, [](vtkIdType id, double v) { return InRegion(id, 16) ? std::nan("") : v; });
  auto withZero =
    AsFloats(spheres, [](vtkIdType id, double v) { return InRegion(id, 16) ? 0.0 : v; });
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  otf->AddPoint(0, 0);
  otf->AddPoint(200, 0.3);
  auto a = LitByPointLight(withNaN, otf);
  auto b = LitByPointLight(withZero, otf);
  for (vtkIdType t = 0; t < a->GetNumberOfValues(); ++t)
  {
    ASSERT_TRUE(std::isfinite(a->GetValue(t)));
    ASSERT_NEAR(a->GetValue(t), b->GetValue(t), 1e-6);
  }
}

// Infinite scalars take the transfer functions' ends (the range is that of the finite values,
// as in every piece of a parallel run): the scene with +inf in one region and -inf in another
// lights as the scene with the largest and smallest finite values there.
TEST(RayMarchedIllumination, InfiniteScalarsTakeTheTransferFunctionsEnds)
{
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  vtkDataArray* original = spheres->GetPointData()->GetScalars();
  double low = VTK_DOUBLE_MAX, high = -VTK_DOUBLE_MAX; // of the points outside the regions
  for (vtkIdType id = 0; id < spheres->GetNumberOfPoints(); ++id)
  {
    if (!InRegion(id, 16) && !InRegion(id, 40))
    {
      low = std::min(low, original->GetTuple1(id));
      high = std::max(high, original->GetTuple1(id));
    }
  }
  const double infinity = std::numeric_limits<double>::infinity();
  auto a = LitByPointLight(AsFloats(spheres,
    [&](vtkIdType id, double v) {
      return InRegion(id, 16) ? infinity : InRegion(id, 40) ? -infinity : v;
    }));
  auto b = LitByPointLight(AsFloats(spheres,
    [&](vtkIdType id, double v) { return InRegion(id, 16) ? high
                                    : InRegion(id, 40)    ? low
                                                          : v; }));
  ASSERT_EQ(a->GetNumberOfValues(), b->GetNumberOfValues());
  ASSERT_GT(a->GetNumberOfValues(), 0);
  for (vtkIdType t = 0; t < a->GetNumberOfValues(); ++t)
  {
    ASSERT_TRUE(std::isfinite(a->GetValue(t)));
    ASSERT_EQ(a->GetValue(t), b->GetValue(t));
  }
}

TEST(RayMarchedIllumination, ClassificationKeepsEachChannelsValues)
{
  // Chromatic classification of scalars 0 to 99 and NaN under a light colour map (k_c =
  // 1 - colour at most 0.3): each channel is read back within 2^-11 of the transfer
  // functions' values, and a NaN point has sigma 0 and k_c exactly 1 (above every k_c the
  // map gives, which the channels' scales must still hold).
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfTuples(101);
  for (vtkIdType t = 0; t < 100; ++t)
  {
    scalars->SetValue(t, static_cast<float>(t));
  }
  scalars->SetValue(100, std::nanf(""));
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0.0);
  opacity->AddPoint(99, 0.8);
  vtkNew<vtkColorTransferFunction> colour;
  colour->AddRGBPoint(0, 1.0, 0.9, 0.8);
  colour->AddRGBPoint(99, 0.7, 0.9, 1.0);
  volillum::ClassificationSettings settings;
  settings.Opacity = opacity;
  settings.Color = colour;
  settings.Chromatic = true;
  volillum::GridGeometry geometry;
  geometry.Dimensions = { { 101, 1, 1 } };
  volillum::ClassifiedVolume classified;
  std::string error;
  ASSERT_TRUE(volillum::Classify(scalars, geometry, settings, classified, error));
  double worst = 0.0;
  for (int t = 0; t < 100; ++t)
  {
    double rgb[3];
    colour->GetColor(t, rgb);
    const double sigma = -std::log1p(-opacity->GetValue(t));
    // The transfer functions are tabulated (4096 entries): within 1e-4 of them.
    const double tolerance = std::exp2(-11.0) * sigma + 1e-4;
    EXPECT_NEAR(classified.Value(4 * t), sigma, tolerance) << t;
    for (int c = 0; c < 3; ++c)
    {
      const double k = classified.Value(4 * t + 1 + c);
      EXPECT_NEAR(k, 1.0 - rgb[c], std::exp2(-11.0) * (1.0 - rgb[c]) + 1e-4) << t;
      worst = std::max(worst, std::abs(k - (1.0 - rgb[c])));
    }
  }
  std::cout << "chromatic classification: largest k_c difference " << worst << std::endl;
  EXPECT_EQ(classified.Value(400), 0.0f);
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_EQ(classified.Value(401 + c), 1.0f) << c;
  }
}

TEST(RayMarchedIllumination, SkippingEmptyBlocksChangesNothing)
{
  // The filter skips samples in empty blocks; marching every sample must give the same.
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  otf->AddPoint(0, 0);
  otf->AddPoint(200, 0.3);
  vtkNew<vtkRayMarchedIllumination> filter;
  filter->SetOpacityFunction(otf);
  filter->AddLight(PointLight(-20, 40, 50));
  filter->AddLight(DirectionalLight(0.3, -0.5, -1));
  EXPECT_EQ(RunAndCountErrors(filter, spheres), 0);
  vtkFloatArray* skipped = Illumination(filter);

  volillum::ClassificationSettings settings;
  settings.Opacity = otf;
  settings.Chromatic = filter->GetChromaticAttenuation();
  volillum::GridGeometry geometry;
  spheres->GetDimensions(geometry.Dimensions.data());
  volillum::ClassifiedVolume classified;
  std::string error;
  ASSERT_TRUE(volillum::Classify(
    spheres->GetPointData()->GetScalars(), geometry, settings, classified, error));
  double bounds[6];
  geometry.GetBounds(bounds);
  const auto lights = volillum::ForBounds(filter->GetLightStates(), bounds);
  double worst = 0.0;
  for (vtkIdType id = 0; id < spheres->GetNumberOfPoints(); id += 7)
  {
    double p[3];
    spheres->GetPoint(id, p);
    const auto sum = volillum::RayMarchIlluminationAt(classified, lights, p, {});
    for (int c = 0; c < 3; ++c)
    {
      worst = std::max(worst, std::abs(sum[c] - skipped->GetValue(3 * id + c)));
    }
  }
  std::cout << "largest difference, empty blocks skipped vs every sample: " << worst << std::endl;
  EXPECT_LE(worst, 1e-6);
}

namespace
{
// The empty blocks of scalars on a grid of the given dimensions, the opacity ramping from 0
// at 0 to 0.3 at 200.
volillum::EmptyBlocks RampEmptyBlocks(vtkDataArray* scalars, const std::array<int, 3>& dimensions)
{
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  otf->AddPoint(0, 0);
  otf->AddPoint(200, 0.3);
  volillum::ClassificationSettings settings;
  settings.Opacity = otf;
  volillum::GridGeometry geometry;
  geometry.Dimensions = dimensions;
  volillum::ClassifiedVolume classified;
  std::string error;
  EXPECT_TRUE(volillum::Classify(scalars, geometry, settings, classified, error)) << error;
  return volillum::EmptyBlocks(classified);
}

// EmptyBlocks::ContainsCells answered one cell at a time.
bool CellsEmptyOneByOne(
  const volillum::EmptyBlocks& empty, int a, const int row[3], int first, int last)
{
  int cell[3] = { row[0], row[1], row[2] };
  for (cell[a] = first; cell[a] <= last; ++cell[a])
  {
    if (!empty.ContainsCell(cell))
    {
      return false;
    }
  }
  return true;
}
}

TEST(RayMarchedIllumination, EmptyRowQueriesEqualCellByCellLookups)
{
  // ContainsCells answers for a range of cells along x or y from two counts; every cell's
  // own lookup must agree, over all rows and ranges that start and end anywhere in a block.
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  std::array<int, 3> dimensions;
  spheres->GetDimensions(dimensions.data());
  const auto empty = RampEmptyBlocks(spheres->GetPointData()->GetScalars(), dimensions);
  long long answers[2] = { 0, 0 };
  for (int a = 0; a < 2; ++a)
  {
    const int cells = dimensions[a] - 1;
    for (int j = 0; j < dimensions[1 - a] - 1; j += 3)
    {
      for (int k = 0; k < dimensions[2] - 1; k += 2)
      {
        for (int first = 0; first < cells; first += 3)
        {
          for (int last = first; last < cells; last += 5)
          {
            int row[3] = { 0, 0, k };
            row[1 - a] = j;
            const bool expected = CellsEmptyOneByOne(empty, a, row, first, last);
            ASSERT_EQ(empty.ContainsCells(a, row, first, last), expected)
              << "axis " << a << " row " << j << " " << k << " cells " << first << "-" << last;
            answers[expected ? 1 : 0] += 1;
          }
        }
      }
    }
  }
  std::cout << "ranges with material " << answers[0] << ", empty " << answers[1] << std::endl;
  EXPECT_GT(answers[0], 1000);
  EXPECT_GT(answers[1], 1000);
}

TEST(RayMarchedIllumination, EmptyRowQueriesWalkRowsOfTwoToTheSixteenBlocks)
{
  // Rows of 2^16 blocks or more overflow the 16-bit counts: ContainsCells walks them block by
  // block. A thin grid 2^18 + 8 points long, material in every third stretch of 1,000 points.
  constexpr int Length = (1 << 18) + 8;
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfValues(4LL * Length);
  for (vtkIdType id = 0; id < scalars->GetNumberOfValues(); ++id)
  {
    scalars->SetValue(id, (id % Length) / 1000 % 3 == 0 ? 200.0f : 0.0f);
  }
  const auto empty = RampEmptyBlocks(scalars, { Length, 2, 2 });
  long long answers[2] = { 0, 0 };
  for (int first = 0; first < Length - 1; first += 997)
  {
    for (int last = first; last < std::min(Length - 1, first + 5000); last += 331)
    {
      const int row[3] = { 0, 0, 0 };
      const bool expected = CellsEmptyOneByOne(empty, 0, row, first, last);
      ASSERT_EQ(empty.ContainsCells(0, row, first, last), expected) << first << "-" << last;
      answers[expected ? 1 : 0] += 1;
    }
  }
  std::cout << "ranges with material " << answers[0] << ", empty " << answers[1] << std::endl;
  EXPECT_GT(answers[0], 100);
  EXPECT_GT(answers[1], 100);
}

TEST(RayMarchedIllumination, SegmentOpticalDepthIntegratesTheSlab)
{
  // Extinction sigma inside the slab (z in [SlabBegin, SlabEnd]), 0 outside, ramping
  // linearly over the cell on either side: a segment from z = 20 down to z = 10 holds sigma
  // over 4 cells and half of it over the ramp; one inside it sigma x length; one outside 0.
  auto slab = MakeScene(vtkIlluminationPhantomSource::Slab);
  auto filter = MakeSlabFilter(slab);
  volillum::ClassificationSettings settings;
  settings.Opacity = filter->GetOpacityFunction();
  settings.Chromatic = false;
  volillum::GridGeometry geometry;
  slab->GetDimensions(geometry.Dimensions.data());
  volillum::ClassifiedVolume classified;
  std::string error;
  ASSERT_TRUE(
    volillum::Classify(slab->GetPointData()->GetScalars(), geometry, settings, classified, error));
  const volillum::EmptyBlocks empty(classified);
  // The slab's extinction as classified (11 significant bits, PackedValue).
  const double sigma = classified.MaxExtinction();
  EXPECT_NEAR(sigma, -std::log(1.0 - SlabOpacity), std::exp2(-11.0) * sigma);
  const double down[3] = { 0.0, 0.0, -1.0 };
  const double oblique[3] = { 0.6, 0.0, 0.8 };
  struct Segment
  {
    double P[3];
    const double* D;
    double Length;
    double Expected;
  };
  const Segment segments[] = { { { 30.2, 20.7, 20.0 }, down, 10.0, 4.5 * sigma },
    { { 30.2, 20.7, 30.0 }, oblique, 10.0, 10.0 * sigma },
    { { 30.2, 20.7, 5.0 }, down, 4.0, 0.0 } };
  for (const auto& segment : segments)
  {
    for (const volillum::EmptyBlocks* skip :
      { static_cast<const volillum::EmptyBlocks*>(nullptr), &empty })
    {
      double depth[3];
      volillum::SegmentOpticalDepth(
        classified, segment.P, segment.D, segment.Length, 1, depth, skip);
      EXPECT_NEAR(depth[0], segment.Expected, 1e-6 * sigma) << "from z " << segment.P[2];
    }
  }
}

TEST(RayMarchedIllumination, RowSegmentsEqualSegmentBySegment)
{
  // Rows of points 1.7 cells apart, near segments toward an oblique direction, grey and
  // chromatic, with and without empty blocks: the row kernel against SegmentOpticalDepth at
  // every point alone (the same arithmetic, so the same values).
  auto spheres = MakeScene(vtkIlluminationPhantomSource::ThreeSpheres);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(1.0, 0.3);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1.0, 0.2, 0.1);
  color->AddRGBPoint(1.0, 0.1, 0.6, 1.0);
  volillum::GridGeometry geometry;
  spheres->GetDimensions(geometry.Dimensions.data());
  const double d[3] = { 0.36, -0.48, 0.8 };
  for (const bool chromatic : { false, true })
  {
    volillum::ClassificationSettings settings;
    settings.Opacity = opacity;
    settings.Color = color;
    settings.Chromatic = chromatic;
    volillum::ClassifiedVolume classified;
    std::string error;
    ASSERT_TRUE(volillum::Classify(
      spheres->GetPointData()->GetScalars(), geometry, settings, classified, error));
    const volillum::EmptyBlocks empty(classified);
    constexpr int Count = 30;
    std::vector<double> x(Count);
    for (int i = 0; i < Count; ++i)
    {
      x[i] = 3.2 + 1.7 * i;
    }
    double largest = 0.0, worst = 0.0;
    for (const volillum::EmptyBlocks* skip :
      { static_cast<const volillum::EmptyBlocks*>(nullptr), &empty })
    {
      for (const double yz : { 12.3, 31.0, 44.6 })
      {
        std::vector<double> row(3 * Count);
        volillum::RowSegmentOpticalDepths(
          classified, x.data(), Count, yz, yz - 4.0, d, 9.5, 3, row.data(), skip);
        for (int i = 0; i < Count; ++i)
        {
          const double p[3] = { x[i], yz, yz - 4.0 };
          double depth[3];
          volillum::SegmentOpticalDepth(classified, p, d, 9.5, 3, depth, skip);
          for (int c = 0; c < 3; ++c)
          {
            largest = std::max(largest, depth[c]);
            worst = std::max(worst, std::abs(depth[c] - row[3 * i + c]));
          }
        }
      }
    }
    std::cout << (chromatic ? "chromatic" : "grey") << ": largest depth " << largest
              << ", largest difference row vs point by point " << worst << std::endl;
    EXPECT_GT(largest, 1.0);
    EXPECT_LE(worst, 1e-6 * largest);
  }
}

TEST(RayMarchedIllumination, PointLightInsideTheVolume)
{
  auto slab = MakeScene(vtkIlluminationPhantomSource::Slab);
  auto filter = MakeSlabFilter(slab);
  const double light[3] = { 31.5, 30.5, 33.5 };
  filter->AddLight(PointLight(light[0], light[1], light[2]));
  EXPECT_EQ(RunAndCountErrors(filter, slab), 0);
  const double error = MaxRelativeError(filter,
    [&](const double p[3], double d[3], double& t)
    {
      for (int a = 0; a < 3; ++a)
        d[a] = light[a] - p[a];
      t = vtkMath::Normalize(d);
    });
  std::cout << "point light inside: max relative error " << error << std::endl;
  EXPECT_LE(error, 1e-3);
}
