// Tests of the light contract: kinds read from vtkLight, the 14-number layout, change
// detection by parameters, and the illumination-volume geometry at resolution scales.
#include "IlluminationClassification.h"
#include "IlluminationLightList.h"

#include "vtkLight.h"
#include "vtkNew.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace volillum;

TEST(IlluminationLights, KindsFollowPositionalAndConeAngle)
{
  vtkNew<vtkLight> light;
  light->SetPositional(false);
  EXPECT_EQ(CaptureLight(light).Kind, LightKind::Directional);
  light->SetPositional(true);
  light->SetConeAngle(90);
  EXPECT_EQ(CaptureLight(light).Kind, LightKind::Point);
  light->SetConeAngle(89.9);
  EXPECT_EQ(CaptureLight(light).Kind, LightKind::Spot);
}

TEST(IlluminationLights, ParameterLayoutRoundTrips)
{
  const double p[LightParameterCount] = { 1, 1, 2, 3, 4, 5, 6, 0.1, 0.2, 0.3, 2.5, 40, 3, 0, 1.5 };
  vtkNew<vtkLight> light;
  ApplyLightParameters(light, p);
  double q[LightParameterCount];
  GetLightParameters(light, q);
  for (int i = 0; i < LightParameterCount; ++i)
  {
    EXPECT_DOUBLE_EQ(q[i], p[i]) << "parameter " << i;
  }
  const LightState s = CaptureLight(light);
  EXPECT_EQ(s.Kind, LightKind::Spot);
  EXPECT_FALSE(s.On);
  EXPECT_EQ(s.Radiance()[0], 0.0); // switched off
  EXPECT_EQ(s.Radius, 1.5);
  // The radius is a change of the light, and a light without one has radius 0.
  const vtkMTimeType before = light->GetMTime();
  SetLightRadius(light, 1.5);
  EXPECT_EQ(light->GetMTime(), before);
  SetLightRadius(light, 2.0);
  EXPECT_GT(light->GetMTime(), before);
  vtkNew<vtkLight> plain;
  EXPECT_EQ(CaptureLight(plain).Radius, 0.0);
}

TEST(IlluminationLights, ListsOfFourteenNumbersAreLightsWithoutRadius)
{
  EXPECT_EQ(LightParametersPerLight(15), 15);
  EXPECT_EQ(LightParametersPerLight(28), 14);
  EXPECT_EQ(LightParametersPerLight(210), 15); // whole lights both ways: the new layout
  EXPECT_EQ(LightParametersPerLight(17), 15);  // neither: refused as 15 a light
}

TEST(IlluminationLights, ChangeDetectionComparesParametersNotModificationTimes)
{
  vtkNew<vtkLight> a, b;
  LightChangeTracker tracker;
  std::vector<LightState> states{ CaptureLight(a), CaptureLight(b) };
  tracker.Commit(states);
  EXPECT_TRUE(tracker.ChangedLights(states).empty());

  // Touching a light without changing a value is no change.
  a->Modified();
  b->SetIntensity(b->GetIntensity());
  EXPECT_TRUE(tracker.ChangedLights({ CaptureLight(a), CaptureLight(b) }).empty());

  b->SetDiffuseColor(1, 0, 0);
  EXPECT_EQ(tracker.ChangedLights({ CaptureLight(a), CaptureLight(b) }), std::vector<int>{ 1 });

  // A light added or removed since the commit counts as changed.
  vtkNew<vtkLight> c;
  EXPECT_EQ(tracker.ChangedLights({ CaptureLight(a), CaptureLight(b), CaptureLight(c) }),
    (std::vector<int>{ 1, 2 }));
  EXPECT_EQ(tracker.ChangedLights({ CaptureLight(a) }), std::vector<int>{ 1 });
}

TEST(IlluminationLights, SpotConeFactor)
{
  LightState spot;
  spot.Kind = LightKind::Spot;
  spot.Position = { { 0, 0, 10 } };
  spot.FocalPoint = { { 0, 0, 0 } };
  spot.ConeAngle = 30;
  spot.Exponent = 2;
  const double onAxis[3] = { 0, 0, 0 };
  EXPECT_NEAR(ComputeIncidence(spot, onAxis).ConeFactor, 1.0, 1e-12);
  const double at20[3] = { 10 * std::tan(20 * 3.14159265358979 / 180), 0, 0 };
  EXPECT_NEAR(ComputeIncidence(spot, at20).ConeFactor,
    std::pow(std::cos(20 * 3.14159265358979 / 180), 2), 1e-9);
  const double at40[3] = { 10 * std::tan(40 * 3.14159265358979 / 180), 0, 0 };
  EXPECT_EQ(ComputeIncidence(spot, at40).ConeFactor, 0.0);
  const double bounds[6] = { -1, 1, -1, 1, -1, 1 };
  EXPECT_FALSE(IsLightInside(spot, bounds));
  spot.Position = { { 0.5, 0, 0 } };
  EXPECT_TRUE(IsLightInside(spot, bounds));
}

TEST(IlluminationGeometry, ScaledGridsKeepTheBounds)
{
  GridGeometry data;
  data.Dimensions = { { 256, 256, 128 } };
  data.Origin = { { -3, 2, 0.5 } };
  data.Spacing = { { 0.5, 0.5, 1.0 } };
  double expected[6];
  data.GetBounds(expected);
  for (double scale : { 1.0, 0.5, 0.25 })
  {
    const GridGeometry g = ScaledGeometry(data, scale);
    double bounds[6];
    g.GetBounds(bounds);
    for (int a = 0; a < 6; ++a)
    {
      EXPECT_NEAR(bounds[a], expected[a], 1e-12) << "scale " << scale;
    }
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_EQ(
        g.Dimensions[a], static_cast<int>(std::lround((data.Dimensions[a] - 1) * scale)) + 1);
    }
  }
}
