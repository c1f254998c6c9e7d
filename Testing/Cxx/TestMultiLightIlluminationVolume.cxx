// Tests of vtkMultiLightIlluminationVolume: accuracy against the ray-marched reference,
// selective updates against full recomputes, grouped against one-light-per-pass
// propagation, continuity across propagation groups, budgets, abort and bad input (the
// peak-memory test is TestPeakMemory.cxx, an executable of its own).
#include "IlluminationFidelity.h"
#include "IlluminationLightList.h"
#include "IlluminationTestUtilities.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMath.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <utility>

using volillumtest::DirectionalLight;
using volillumtest::ErrorCounter;
using volillumtest::ImageFilter;
using volillumtest::PhantomScene;
using volillumtest::PointLight;
using volillumtest::RampOpacity;
using volillumtest::Result;
using volillumtest::RmsRelative;

namespace
{
// Largest difference relative to the largest reference value.
double MaxRelative(vtkFloatArray* got, vtkFloatArray* reference)
{
  double worst = 0.0, largest = 0.0;
  for (vtkIdType i = 0; i < got->GetNumberOfValues(); ++i)
  {
    worst = std::max(worst, std::abs(double(got->GetValue(i)) - reference->GetValue(i)));
    largest = std::max(largest, std::abs(double(reference->GetValue(i))));
  }
  return worst / largest;
}

int Field(vtkImageAlgorithm* filter, const char* name)
{
  return static_cast<int>(filter->GetOutput()->GetFieldData()->GetArray(name)->GetTuple1(0));
}

}

TEST(MultiLightIlluminationVolume, ApproximatesTheRayMarchedReference)
{
  struct Case
  {
    const char* Name;
    int Scene;
    double Opacity;
    double Tolerance;
    double MaterialTolerance;
  };
  for (const Case& c : { Case{ "slab", vtkIlluminationPhantomSource::Slab, 0.05, 0.05, 0.03 },
         Case{ "three spheres", vtkIlluminationPhantomSource::ThreeSpheres, 0.3, 0.1, 0.05 } })
  {
    auto image = PhantomScene(c.Scene, 64);
    auto otf = RampOpacity(image, c.Opacity);
    auto reference = ImageFilter<vtkRayMarchedIllumination>(image, otf);
    auto propagated = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    auto point = PointLight(-64, 32, 51, 1, 1, 0);
    auto directional = DirectionalLight(-0.3, -0.2, -1, 0, 0.5, 1);
    for (vtkIlluminationVolumeAlgorithm* f :
      { static_cast<vtkIlluminationVolumeAlgorithm*>(reference),
        static_cast<vtkIlluminationVolumeAlgorithm*>(propagated) })
    {
      f->AddLight(point);
      f->AddLight(directional);
      f->Update();
    }
    const double rms = RmsRelative(Result(propagated), Result(reference));
    const double material =
      volillumfidelity::MaterialRms(propagated, Result(propagated), Result(reference));
    std::cout << c.Name << ": RMS relative difference to RayMarchedIllumination over material "
              << material << " (whole volume " << rms << ")" << std::endl;
    EXPECT_LE(material, c.MaterialTolerance) << c.Name;
    EXPECT_LE(rms, c.Tolerance) << c.Name;
  }
}

TEST(MultiLightIlluminationVolume, SelectiveUpdatesMatchAFullRecompute)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 24);
  auto otf = RampOpacity(image, 0.3);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  std::vector<vtkSmartPointer<vtkLight>> lights = { PointLight(-20, 12, 12, 1, 1, 0),
    PointLight(40, 10, 14, 0, 0, 1), DirectionalLight(0.2, -0.1, -1),
    DirectionalLight(1, 0.3, 0.1, 0.5, 1, 0.5), PointLight(12, 40, 5, 1, 0.3, 0.3) };
  for (auto& l : lights)
  {
    filter->AddLight(l);
  }
  filter->Update();
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(7);
  auto next = [&](double lo, double hi)
  {
    random->Next();
    return random->GetRangeValue(lo, hi);
  };
  int selective = 0;
  const int edits = 1000;
  for (int edit = 0; edit < edits; ++edit)
  {
    vtkLight* l = lights[static_cast<int>(next(0, lights.size() - 1e-9))];
    switch (static_cast<int>(next(0, 4 - 1e-9)))
    {
      case 0:
        l->SetPosition(next(-30, 50), next(-30, 50), next(-30, 50));
        break;
      case 1:
        l->SetDiffuseColor(next(0, 1), next(0, 1), next(0, 1));
        break;
      case 2:
        l->SetIntensity(next(0.1, 3));
        break;
      default:
        l->SetSwitch(!l->GetSwitch());
    }
    filter->Update();
    selective += Field(filter, "UpdateMode");
  }
  auto fresh = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  for (auto& l : lights)
  {
    fresh->AddLight(l);
  }
  fresh->Update();
  const double error = MaxRelative(Result(filter), Result(fresh));
  std::cout << edits << " random edits, " << selective << " selective; max relative difference "
            << error << std::endl;
  EXPECT_GT(selective, edits / 2);
  EXPECT_LE(error, 1e-4);
}

// A light changed alone is recorded; when it changes alone again (a drag) its old state
// leaves by subtracting the record, so the update propagates the new state only. Drags of a
// directional, a point, a spot and an inside light, with chromatic attenuation off and on,
// broken by changes of two lights at once: after every update the output equals a fresh
// filter's full recompute of the same lights exactly (the same fixed-point totals).
TEST(MultiLightIlluminationVolume, DraggedLightLeavesBySubtractingItsRecord)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 24);
  auto otf = RampOpacity(image, 0.3);
  double bounds[6];
  image->GetBounds(bounds);
  // Grey, chromatic, and grey with RecordEditedLight off (no record: every edit propagates).
  for (const auto& [chromatic, record] :
    { std::pair(false, true), std::pair(true, true), std::pair(false, false) })
  {
    auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    filter->SetChromaticAttenuation(chromatic);
    filter->SetRecordEditedLight(record);
    auto spot = PointLight(-20, 12, 30, 1, 0.5, 0.2);
    spot->SetConeAngle(25);
    const std::vector<vtkSmartPointer<vtkLight>> lights = { DirectionalLight(
                                                              0.3, -0.2, -1, 1, 0.9, 0.8),
      PointLight(40, 10, 14, 0.3, 0.5, 1), spot, PointLight(12, 11, 13, 0.5, 1, 0.5) };
    for (const auto& l : lights)
    {
      filter->AddLight(l);
    }
    filter->Update();
    const auto move = [&](int index, int edit)
    {
      vtkLight* l = lights[index];
      if (index == 0)
      {
        l->SetFocalPoint(0.3 - 0.07 * (edit + 1), -0.2 + 0.04 * (edit + 1), -1);
        return;
      }
      const double* p = l->GetPosition();
      l->SetPosition(p[0] + (edit % 2 ? 0.7 : -0.4), p[1] + 0.3, p[2] - 0.2);
    };
    int subtracted = 0;
    double worst = 0.0;
    for (int edit = 0; edit < 28; ++edit)
    {
      const int dragged = (edit / 6) % static_cast<int>(lights.size());
      const bool fromRecord = filter->GetRecordedLight() == dragged && edit % 6 != 5;
      move(dragged, edit);
      if (edit % 6 == 5)
      {
        move((dragged + 1) % static_cast<int>(lights.size()), edit); // two lights at once
      }
      filter->Update();
      if (fromRecord)
      {
        // Only the new state is propagated: its tasks, one per group of the light.
        const auto tasks =
          volillum::TasksForLight(volillum::CaptureLight(lights[dragged]), +1, bounds);
        EXPECT_EQ(Field(filter, "UpdateMode"), 1) << "edit " << edit;
        EXPECT_EQ(filter->GetLastLightPropagations(), static_cast<long long>(tasks.size()))
          << "edit " << edit;
        ++subtracted;
      }
      auto fresh = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
      fresh->SetChromaticAttenuation(chromatic);
      for (const auto& l : lights)
      {
        fresh->AddLight(l);
      }
      fresh->Update();
      worst = std::max(worst, MaxRelative(Result(filter), Result(fresh)));
    }
    std::cout << (chromatic ? "chromatic" : "grey") << (record ? "" : ", no record") << ": "
              << subtracted << " of 28 edits subtracted a record; largest difference to a "
              << "full recompute " << worst << std::endl;
    if (record)
    {
      EXPECT_GE(subtracted, 16);
    }
    else
    {
      EXPECT_EQ(subtracted, 0);
    }
    EXPECT_EQ(worst, 0.0);
  }
}

// The record through changes that keep it, move it or drop it, each followed by drags of
// light 0: two lights changed at once (the recorded one among them), another light changed
// alone, the light switched off and on alone, a transfer-function change, progressive
// updates (MaximumPassesPerUpdate), a light removed and a brightening beyond the fixed-point
// unit. After every update the output equals a
// fresh filter's full recompute exactly, and a drag subtracts a record only when the update
// before recorded that light.
TEST(MultiLightIlluminationVolume, RecordFollowsTheChangedLights)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 24);
  auto otf = RampOpacity(image, 0.3);
  double bounds[6];
  image->GetBounds(bounds);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  std::vector<vtkSmartPointer<vtkLight>> lights = { PointLight(-20, 12, 14, 1, 0.8, 0.6),
    DirectionalLight(0.2, -0.3, -1, 0.6, 0.8, 1), PointLight(40, 30, 10, 0.5, 1, 0.5) };
  const auto setLights = [&]()
  {
    filter->RemoveAllLights();
    for (const auto& l : lights)
    {
      filter->AddLight(l);
    }
  };
  setLights();
  filter->Update();
  int step = 0;
  const auto expectFresh = [&](const char* what)
  {
    auto fresh = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    for (const auto& l : lights)
    {
      fresh->AddLight(l);
    }
    fresh->Update();
    EXPECT_EQ(MaxRelative(Result(filter), Result(fresh)), 0.0) << what;
  };
  // Moves light 0 and updates; returns whether its old state left by subtraction (only its
  // new state's tasks propagated).
  const auto drag = [&](const char* what)
  {
    const bool recorded = filter->GetRecordedLight() == 0;
    const double* p = lights[0]->GetPosition();
    lights[0]->SetPosition(p[0] + 0.5, p[1] + 0.25 * (++step % 3), p[2] - 0.3);
    filter->Update();
    expectFresh(what);
    const auto tasks = volillum::TasksForLight(volillum::CaptureLight(lights[0]), +1, bounds);
    const bool subtracted =
      filter->GetLastLightPropagations() == static_cast<long long>(tasks.size());
    EXPECT_EQ(subtracted, recorded) << what;
    EXPECT_EQ(filter->GetRecordedLight(), 0) << what;
    return subtracted;
  };
  EXPECT_FALSE(drag("first drag"));
  EXPECT_TRUE(drag("second drag"));

  lights[0]->SetPosition(-22, 10, 15);
  lights[1]->SetFocalPoint(0.1, -0.3, -1);
  filter->Update();
  expectFresh("two lights at once, the recorded one among them");
  EXPECT_EQ(filter->GetRecordedLight(), 0);
  lights[1]->SetFocalPoint(0.1, -0.2, -1);
  filter->Update();
  expectFresh("another light alone");
  EXPECT_EQ(filter->GetRecordedLight(), 1);
  EXPECT_FALSE(drag("drag after another light"));
  EXPECT_TRUE(drag("drag again"));

  lights[0]->SwitchOff();
  filter->Update();
  expectFresh("switched off alone");
  lights[0]->SwitchOn();
  filter->Update();
  expectFresh("switched on alone");
  EXPECT_TRUE(drag("drag after off and on"));

  otf->AddPoint(0.5 * (otf->GetRange()[0] + otf->GetRange()[1]), 0.1);
  filter->Update();
  expectFresh("transfer function");
  EXPECT_EQ(filter->GetRecordedLight(), -1);
  EXPECT_FALSE(drag("drag after the transfer function"));

  filter->SetMaximumPassesPerUpdate(1);
  lights[0]->SetPosition(-20, -20, 30); // two groups of about equal weight: two passes
  filter->Update();
  EXPECT_GT(filter->GetNumberOfPendingPasses(), 0);
  EXPECT_EQ(filter->GetRecordedLight(), -1) << "work left for later";
  for (int more = 0; more < 20 && filter->GetNumberOfPendingPasses() > 0; ++more)
  {
    filter->Modified();
    filter->Update();
  }
  filter->SetMaximumPassesPerUpdate(0);
  expectFresh("progressive updates");
  EXPECT_FALSE(drag("drag after progressive updates"));

  lights.pop_back();
  setLights();
  filter->Update();
  expectFresh("last light removed");
  EXPECT_EQ(filter->GetRecordedLight(), 0); // light 0 did not change: its record is exact
  EXPECT_TRUE(drag("drag after a removal"));

  lights[0]->SetIntensity(5000);
  filter->Update();
  expectFresh("brightened beyond the unit");
  EXPECT_EQ(Field(filter, "UpdateMode"), 0);
  EXPECT_FALSE(drag("drag after the new unit"));
}

// The fixed-point scale is chosen from the lights' summed radiance: a light brightened far
// beyond the room the scale leaves, or dimmed far below the precision it keeps, must give a
// full update (with a new scale) equal to a fresh filter's, not totals that wrapped around
// or lost their precision; a light dimmed a little stays a selective update.
TEST(MultiLightIlluminationVolume, BrightenedLightsKeepTheFixedPointExact)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 24);
  auto otf = RampOpacity(image, 0.3);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  auto a = PointLight(-20, 12, 12, 1, 0.5, 0.2);
  auto b = DirectionalLight(0.2, -0.1, -1);
  filter->AddLight(a);
  filter->AddLight(b);
  filter->Update();
  const std::vector<std::pair<double, int>> edits = { { 1000.0, 0 }, { 1e5, 0 }, { 0.5, 0 },
    { 0.3, 1 } };
  for (const auto& edit : edits)
  {
    const double intensity = edit.first;
    a->SetIntensity(intensity);
    filter->Update();
    const int mode = Field(filter, "UpdateMode");
    auto fresh = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    fresh->AddLight(a);
    fresh->AddLight(b);
    fresh->Update();
    const double error = MaxRelative(Result(filter), Result(fresh));
    double range[2];
    Result(filter)->GetRange(range, 0);
    std::cout << "intensity " << intensity << ": update mode " << mode << ", red range ["
              << range[0] << ", " << range[1] << "], max relative difference to a fresh filter "
              << error << std::endl;
    EXPECT_EQ(mode, edit.second);
    EXPECT_GE(range[0], 0.0);
    EXPECT_LE(error, 1e-6);
  }
}

// The row kernels (a directional light's segments along a row of the illumination grid,
// sampled in cells found once per row, at the data's resolution a whole row summed at once;
// the steps of a point or spot light's rays and points along a row of a slice, summed a run
// of equal step counts at a time from the extinction interpolated once along the row, and
// the points' reads of the rays a run at a time) against every segment integrated and every
// point read on its own (the former formulation of point and spot lights): the same
// illumination to 1e-6 of its largest value, with and without chromatic attenuation, at the
// data's resolution and at half of it (the rays 39 / 19 = 2.05 data cells apart), with
// point lights outside (their rays entering through every side face) and one inside the
// volume and a spot light. The rows skip the empty blocks (bit for bit the rows that read
// everything), the segments read everything.
TEST(MultiLightIlluminationVolume, RowKernelsEqualSegmentBySegment)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 40);
  auto otf = RampOpacity(image, 0.4);
  const std::pair<double, bool> cases[] = { { 1.0, false }, { 1.0, true }, { 0.5, false },
    { 0.5, true } };
  for (const auto& [scale, chromatic] : cases)
  {
    auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    filter->SetChromaticAttenuation(chromatic);
    filter->SetResolutionScale(scale);
    filter->Update();
    volillum::ClassifiedVolume classified;
    volillum::GridGeometry target;
    ASSERT_TRUE(volillumfidelity::ClassifiedInput(filter, classified, target));
    ASSERT_EQ(scale == 1.0, target.NumberOfPoints() == classified.Geometry.NumberOfPoints());
    double bounds[6];
    target.GetBounds(bounds);
    std::vector<volillum::PropagationTask> tasks;
    auto spot = PointLight(60, -10, 25, 1, 0.6, 0.3);
    spot->SetConeAngle(30);
    for (const auto& light : { DirectionalLight(0.4, -0.3, -1), DirectionalLight(-1, 0.5, 0.3),
           DirectionalLight(0.2, 1, -0.6), PointLight(-30, 20, 60), PointLight(18, 22, 15),
           PointLight(25, -45, 70), spot })
    {
      const auto more = volillum::TasksForLight(volillum::CaptureLight(light), +1, bounds);
      tasks.insert(tasks.end(), more.begin(), more.end());
    }
    const volillum::EmptyBlocks empty(classified);
    auto propagate = [&](bool rowKernels, const volillum::EmptyBlocks* skipped)
    {
      volillum::FixedPointIllumination illumination;
      illumination.Reset(target.NumberOfPoints(), volillum::FixedPointIllumination::ScaleFor(4));
      std::vector<volillum::PropagationTask> remaining;
      volillum::PropagationStatistics statistics;
      volillum::PropagateTasks(classified, target, tasks, true, 0, illumination, remaining,
        statistics, nullptr, skipped, rowKernels);
      std::vector<float> rgb(3 * static_cast<size_t>(target.NumberOfPoints()));
      illumination.ToFloat(rgb.data());
      return rgb;
    };
    const auto rows = propagate(true, &empty);
    const auto single = propagate(false, nullptr);
    // Skipping empty blocks leaves the sums as they are, to the bit.
    EXPECT_EQ(rows, propagate(true, nullptr));
    double worst = 0.0, largest = 0.0, darkest = 1e30;
    for (size_t i = 0; i < rows.size(); ++i)
    {
      worst = std::max(worst, std::abs(double(rows[i]) - single[i]));
      largest = std::max(largest, std::abs(double(single[i])));
      darkest = std::min(darkest, double(single[i]));
    }
    std::cout << "scale " << scale << (chromatic ? ", chromatic" : ", grey")
              << ": row kernels vs segment by segment, max "
              << "difference " << worst << " of " << largest << " (darkest " << darkest << ")"
              << std::endl;
    EXPECT_GT(largest - darkest, 0.5); // shadows to compare
    EXPECT_LE(worst, 1e-6 * largest);
  }
}

// Sweeps shared out among processes (SweepShare, as a parallel run does): every process
// propagates its share into units of its own; the sums over the processes equal the
// single-process illumination bit for bit, after a full update, after a selective edit
// (the old state of a light removed and its new state added, each process its share of
// those sweeps) and with a limit on the sweeps per update (the same tasks left on every
// process).
TEST(MultiLightIlluminationVolume, SharedSweepsSumToTheSingleProcessIllumination)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.4);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  filter->Update();
  volillum::ClassifiedVolume classified;
  volillum::GridGeometry target;
  ASSERT_TRUE(volillumfidelity::ClassifiedInput(filter, classified, target));
  double bounds[6];
  target.GetBounds(bounds);
  auto spot = PointLight(50, -10, 20, 1, 0.6, 0.3);
  spot->SetConeAngle(30);
  const std::vector<vtkSmartPointer<vtkLight>> lights = { DirectionalLight(0.4, -0.3, -1),
    DirectionalLight(-1, 0.5, 0.3), PointLight(-30, 20, 50), spot };
  auto tasksOf = [&](vtkLight* light, int sign)
  { return volillum::TasksForLight(volillum::CaptureLight(light), sign, bounds); };
  std::vector<volillum::PropagationTask> full;
  for (const auto& light : lights)
  {
    const auto more = tasksOf(light, +1);
    full.insert(full.end(), more.begin(), more.end());
  }
  // The edit: the point light moves.
  std::vector<volillum::PropagationTask> edit = tasksOf(lights[2], -1);
  auto moved = PointLight(-25, 30, 45);
  const auto added = tasksOf(moved, +1);
  edit.insert(edit.end(), added.begin(), added.end());
  std::vector<volillum::PropagationTask> fresh;
  for (vtkLight* light : { lights[0].Get(), lights[1].Get(), moved.Get(), lights[3].Get() })
  {
    const auto more = tasksOf(light, +1);
    fresh.insert(fresh.end(), more.begin(), more.end());
  }
  const double scale = volillum::FixedPointIllumination::ScaleFor(8);
  // The units of each process after propagating `updates` in turn; remaining: the tasks a
  // limit of maxSweeps left (the same on every process).
  auto propagate = [&](const std::vector<std::vector<volillum::PropagationTask>>& updates,
                     int processes, int maxSweeps,
                     std::vector<std::vector<volillum::PropagationTask>>& remaining)
  {
    std::vector<volillum::FixedPointIllumination> units(processes);
    remaining.assign(processes, {});
    for (int p = 0; p < processes; ++p)
    {
      units[p].Reset(target.NumberOfPoints(), scale);
      for (const auto& tasks : updates)
      {
        volillum::PropagationStatistics statistics;
        volillum::SweepShare share;
        share.Process = p;
        share.Processes = processes;
        EXPECT_TRUE(volillum::PropagateTasks(classified, target, tasks, true, maxSweeps, units[p],
          remaining[p], statistics, nullptr, nullptr, true, share));
        EXPECT_EQ(statistics.Sweeps,
          std::min(volillum::CountSweeps(tasks, true), maxSweeps > 0 ? maxSweeps : 1000));
      }
    }
    return units;
  };
  auto sum = [](const std::vector<volillum::FixedPointIllumination>& units)
  {
    std::vector<std::uint32_t> total(units[0].Values.begin(), units[0].Values.end());
    for (size_t p = 1; p < units.size(); ++p)
    {
      for (size_t i = 0; i < total.size(); ++i)
      {
        total[i] += units[p].Values[i];
      }
    }
    return total;
  };
  std::vector<std::vector<volillum::PropagationTask>> left;
  const auto single = sum(propagate({ full }, 1, 0, left));
  const auto singleFresh = sum(propagate({ fresh }, 1, 0, left));
  ASSERT_GE(volillum::CountSweeps(full, true), 4);
  for (int processes : { 2, 3 })
  {
    const auto shared = propagate({ full }, processes, 0, left);
    EXPECT_TRUE(sum(shared) == single) << processes << " processes, full update";
    for (const auto& units : shared)
    {
      // Each process did part of the work: its units alone are not the illumination.
      EXPECT_FALSE(std::equal(units.Values.begin(), units.Values.end(), single.begin()));
    }
    EXPECT_TRUE(sum(propagate({ full, edit }, processes, 0, left)) == singleFresh)
      << processes << " processes, selective edit";
    propagate({ full }, processes, 2, left);
    EXPECT_FALSE(left[0].empty());
    for (int p = 1; p < processes; ++p)
    {
      ASSERT_EQ(left[p].size(), left[0].size());
    }
  }
  // Every sweep has one process, the costliest first onto the least loaded (costs 2, 2, 13,
  // 2 and 4).
  std::vector<std::vector<volillum::PropagationTask>> sweeps(5);
  for (int i = 0; i < 5; ++i)
  {
    volillum::PropagationTask task;
    task.Light.Kind = i == 2 ? volillum::LightKind::Point : volillum::LightKind::Directional;
    sweeps[i].assign(i == 4 ? 3 : 1, task);
  }
  EXPECT_EQ(volillum::AssignSweeps(sweeps, 2), (std::vector<int>{ 1, 1, 0, 1, 1 }));
  EXPECT_EQ(volillum::AssignSweeps(sweeps, 1), (std::vector<int>(5, 0)));
}

TEST(MultiLightIlluminationVolume, TogglingALightRestoresTheVolume)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.3);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  auto a = PointLight(-20, 16, 16, 1, 1, 0);
  auto b = PointLight(50, 16, 16, 0, 0, 1);
  auto c = DirectionalLight(0, 0.3, -1);
  filter->AddLight(a);
  filter->AddLight(b);
  filter->AddLight(c);
  filter->Update();
  auto before = Result(filter);
  b->SwitchOff();
  filter->Update();
  EXPECT_EQ(Field(filter, "UpdateMode"), 1);
  // Removing one light costs its own sweeps only (one per group it belongs to).
  double bounds[6];
  filter->GetOutput()->GetBounds(bounds);
  const int lightGroups =
    static_cast<int>(volillum::AssignPropagationGroups(volillum::CaptureLight(b), bounds).size());
  EXPECT_EQ(Field(filter, "PropagationPasses"), lightGroups);
  b->SwitchOn();
  filter->Update();
  EXPECT_EQ(Field(filter, "UpdateMode"), 1);
  EXPECT_LE(MaxRelative(Result(filter), before), 1e-6);
}

TEST(MultiLightIlluminationVolume, ALightsSizeIsNoChange)
{
  // The propagation treats every light as a point or a direction: a radius edit (for
  // Filtered Shadows) propagates nothing, while a position edit after it does.
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.3);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  auto a = PointLight(-20, 16, 16, 1, 1, 0);
  auto b = DirectionalLight(0, 0.3, -1);
  filter->AddLight(a);
  filter->AddLight(b);
  filter->Update();
  auto before = Result(filter);
  volillum::SetLightRadius(a, 4.0);
  filter->Update();
  EXPECT_EQ(Field(filter, "PropagationPasses"), 0);
  EXPECT_EQ(MaxRelative(Result(filter), before), 0.0);
  a->SetPosition(-20, 18, 16);
  filter->Update();
  EXPECT_GT(Field(filter, "PropagationPasses"), 0);
}

TEST(MultiLightIlluminationVolume, GroupedPropagationEqualsOneLightPerPass)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.3);
  auto coherent = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  auto sequential = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  sequential->CoherentPropagationOff();
  for (vtkMultiLightIlluminationVolume* f : { coherent.Get(), sequential.Get() })
  {
    f->AddLight(PointLight(-20, 16, 16, 1, 1, 0));
    f->AddLight(PointLight(-25, 10, 20, 1, 0, 0));
    f->AddLight(DirectionalLight(1, 0.1, 0.2));
    f->AddLight(DirectionalLight(0.2, 0.1, -1));
    f->AddLight(PointLight(16, 16, 60, 0, 1, 0));
    f->Update();
  }
  EXPECT_LT(Field(coherent, "PropagationPasses"), Field(sequential, "PropagationPasses"));
  EXPECT_LE(MaxRelative(Result(coherent), Result(sequential)), 1e-5);
}

TEST(MultiLightIlluminationVolume, RotatingLightChangesContinuouslyAcrossGroups)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.3);
  // A directional light turning through the boundary of the -z and -x groups (in the x-z
  // plane at 45 degrees) and through the swap of the second and third closest axes.
  auto check = [&](auto direction, double a0, double a1, const char* what)
  {
    auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    auto light = DirectionalLight(0, 0, -1);
    filter->AddLight(light);
    std::vector<vtkSmartPointer<vtkFloatArray>> results;
    const int steps = 8;
    for (int i = 0; i <= steps; ++i)
    {
      const auto d = direction(a0 + (a1 - a0) * i / steps);
      light->SetFocalPoint(d[0], d[1], d[2]);
      filter->Update();
      results.push_back(Result(filter));
    }
    // The step across the boundary (the middle one) changes the volume about as much as its
    // neighbours: a light that switched groups would jump there.
    std::vector<double> change;
    for (int i = 0; i < steps; ++i)
    {
      change.push_back(RmsRelative(results[i + 1], results[i]));
    }
    const double largest = *std::max_element(change.begin(), change.end());
    const double smallest = *std::min_element(change.begin(), change.end());
    std::cout << what << ": RMS change per step " << smallest << " .. " << largest << std::endl;
    EXPECT_LE(largest, 2.0 * smallest + 1e-6) << what;
    EXPECT_LE(largest, 0.02) << what;
  };
  check(
    [](double deg)
    {
      const double r = vtkMath::RadiansFromDegrees(deg);
      return std::array<double, 3>{ -std::sin(r), 0.0, -std::cos(r) };
    },
    43.0, 47.0, "first/second group swap");
  check(
    [](double e) {
      return std::array<double, 3>{ -0.8, -0.4 - e, -0.4 + e };
    },
    -0.02, 0.02, "second/third group swap");
}

TEST(MultiLightIlluminationVolume, PassBudgetContinuesOnTheNextUpdate)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.3);
  auto budgeted = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  auto complete = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  budgeted->SetMaximumPassesPerUpdate(1);
  for (vtkMultiLightIlluminationVolume* f : { budgeted.Get(), complete.Get() })
  {
    f->AddLight(DirectionalLight(0, 0, -1));
    f->AddLight(DirectionalLight(1, 0, 0));
    f->AddLight(DirectionalLight(0, -1, 0));
    f->Update();
  }
  EXPECT_EQ(Field(budgeted, "PropagationPasses"), 1);
  EXPECT_EQ(Field(budgeted, "PendingPasses"), 2);
  int updates = 1;
  while (budgeted->GetNumberOfPendingPasses() > 0 && updates < 10)
  {
    budgeted->Modified();
    budgeted->Update();
    ++updates;
  }
  EXPECT_EQ(updates, 3);
  EXPECT_EQ(Field(budgeted, "PendingPasses"), 0);
  EXPECT_LE(MaxRelative(Result(budgeted), Result(complete)), 1e-6);
}

TEST(MultiLightIlluminationVolume, AbortKeepsThePreviousOutput)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 32);
  auto otf = RampOpacity(image, 0.3);
  auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  auto light = PointLight(-20, 16, 16);
  filter->AddLight(light);
  filter->Update();
  auto before = Result(filter);
  vtkNew<volillumtest::AbortHalfway> abort;
  filter->AddObserver(vtkCommand::ProgressEvent, abort);
  abort->Armed = true;
  light->SetPosition(50, 16, 16);
  filter->Update();
  EXPECT_LE(MaxRelative(Result(filter), before), 0.0);
  // The next update recomputes fully and is right.
  filter->SetAbortExecute(0);
  filter->Modified();
  filter->Update();
  auto fresh = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  fresh->AddLight(light);
  fresh->Update();
  EXPECT_EQ(Field(filter, "UpdateMode"), 0);
  EXPECT_LE(MaxRelative(Result(filter), Result(fresh)), 1e-6);
}

TEST(MultiLightIlluminationVolume, CostEstimatesChooseTheUpdate)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 24);
  auto otf = RampOpacity(image, 0.3);
  for (int estimate : { vtkMultiLightIlluminationVolume::ChangedLightFraction,
         vtkMultiLightIlluminationVolume::PropagationPasses })
  {
    auto filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    filter->SetCostEstimate(estimate);
    std::vector<vtkSmartPointer<vtkLight>> lights;
    for (int i = 0; i < 4; ++i)
    {
      lights.push_back(DirectionalLight(0.1 * i, 0, -1));
      filter->AddLight(lights.back());
    }
    filter->Update();
    EXPECT_EQ(Field(filter, "UpdateMode"), 0);
    // One of four lights changes colour: selective by both estimates.
    lights[0]->SetDiffuseColor(1, 0, 0);
    filter->Update();
    EXPECT_EQ(Field(filter, "UpdateMode"), 1) << "estimate " << estimate;
    // Three of four change intensity: the fraction estimate recomputes all; the cost
    // estimate removes and adds them (the same rays: three light geometries propagated,
    // against the four of a full update).
    for (int i = 0; i < 3; ++i)
    {
      lights[i]->SetIntensity(2.0);
    }
    filter->Update();
    EXPECT_EQ(
      Field(filter, "UpdateMode"), estimate == vtkMultiLightIlluminationVolume::PropagationPasses)
      << "estimate " << estimate;
    // A transfer-function change always recomputes everything.
    otf->AddPoint(100, 0.1);
    filter->Update();
    EXPECT_EQ(Field(filter, "UpdateMode"), 0);
    otf->RemovePoint(100);
  }
}

// A one-light state change runs the update estimated to cost less (PropagationPasses), and
// either equals a full recompute exactly. Two directional lights: a light moved into the
// other light's groups is recomputed with it in two sweeps (removing and adding it takes
// three);
// moved across groups (Table 1's state change: three sweeps either way) it is recomputed
// too, as a selective update would also start a record. With a point light as well, the
// full update propagates its rays too: the moved light is removed and added. A light
// changed alone twice in a row (dragged) is recorded, and its next change only adds its new
// state.
TEST(MultiLightIlluminationVolume, OneLightStateChangeTakesTheCheaperUpdate)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 24);
  auto otf = RampOpacity(image, 0.3);
  double bounds[6];
  image->GetBounds(bounds);
  for (const bool withPoint : { false, true })
  {
    const std::string lit = withPoint ? "three lights, " : "two lights, ";
    std::vector<vtkSmartPointer<vtkLight>> lights;
    vtkSmartPointer<vtkMultiLightIlluminationVolume> filter;
    // A new filter with light 0 along (x0, -0.2, -1) (groups -z and +x or -x) and light 1
    // along (0.2, 0.1, -1) (-z, +x), after its first update.
    const auto start = [&](double x0)
    {
      lights = { DirectionalLight(x0, -0.2, -1), DirectionalLight(0.2, 0.1, -1) };
      if (withPoint)
      {
        lights.push_back(PointLight(-10, 14, 40, 1, 0.9, 0.3));
      }
      filter = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
      for (const auto& l : lights)
      {
        filter->AddLight(l);
      }
      filter->Update();
    };
    // Turns light 0 toward d and updates: the mode follows the estimates, the output a full
    // recompute's.
    const auto change = [&](double dx, double dy, double dz, const std::string& what)
    {
      lights[0]->SetFocalPoint(dx, dy, dz);
      filter->Update();
      auto fresh = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
      for (const auto& l : lights)
      {
        fresh->AddLight(l);
      }
      fresh->Update();
      EXPECT_EQ(MaxRelative(Result(filter), Result(fresh)), 0.0) << lit << what;
      std::cout << lit << what << ": update mode " << Field(filter, "UpdateMode") << ", "
                << Field(filter, "PropagationPasses") << " passes; estimated selective "
                << filter->GetLastSelectiveCost() << ", full " << filter->GetLastFullCost()
                << std::endl;
    };
    // From -x into the other light's groups (-z, +x): a full update sweeps twice, a
    // selective one three times (-x, +x, -z).
    start(-0.3);
    change(0.3, -0.2, -1, "into the other's groups");
    EXPECT_EQ(Field(filter, "UpdateMode"), withPoint ? 1 : 0) << lit;
    EXPECT_EQ(Field(filter, "PropagationPasses"), withPoint ? 3 : 2) << lit;
    // From the other light's groups across to -x, -z (Table 1's change): three sweeps
    // either way.
    start(0.3);
    change(-1, -0.2, -0.3, "across groups");
    EXPECT_EQ(Field(filter, "UpdateMode"), withPoint ? 1 : 0) << lit;
    EXPECT_EQ(Field(filter, "PropagationPasses"), 3) << lit;
    // Dragged on: recorded, then only its new state is propagated.
    change(-1, -0.25, -0.3, "dragged");
    EXPECT_EQ(Field(filter, "UpdateMode"), 1) << lit;
    EXPECT_EQ(filter->GetRecordedLight(), 0) << lit;
    change(-1, -0.3, -0.3, "dragged on");
    EXPECT_EQ(Field(filter, "UpdateMode"), 1) << lit;
    EXPECT_EQ(filter->GetLastLightPropagations(),
      static_cast<long long>(
        volillum::TasksForLight(volillum::CaptureLight(lights[0]), +1, bounds).size()))
      << lit;
  }
}

TEST(MultiLightIlluminationVolume, LightInsideTheVolumeAndSpotLights)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 48);
  auto otf = RampOpacity(image, 0.3);
  auto inside = PointLight(24, 24, 30, 1, 1, 1);
  auto spot = PointLight(24, 24, 90, 1, 0.5, 0);
  spot->SetFocalPoint(24, 24, 0);
  spot->SetConeAngle(20);
  for (vtkLight* light : { inside.Get(), spot.Get() })
  {
    auto reference = ImageFilter<vtkRayMarchedIllumination>(image, otf);
    auto propagated = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    reference->AddLight(light);
    propagated->AddLight(light);
    reference->Update();
    propagated->Update();
    const double rms = RmsRelative(Result(propagated), Result(reference));
    const double material =
      volillumfidelity::MaterialRms(propagated, Result(propagated), Result(reference));
    std::cout << (light == inside ? "point light inside" : "spot light")
              << ": RMS relative difference over material " << material << " (whole volume " << rms
              << "), passes " << Field(propagated, "PropagationPasses") << std::endl;
    EXPECT_LE(material, 0.045);
    EXPECT_LE(rms, 0.15);
  }
}

TEST(MultiLightIlluminationVolume, BadInputGivesAnErrorAndAnEmptyOutput)
{
  vtkNew<vtkImageData> noScalars;
  noScalars->SetDimensions(8, 8, 8);
  vtkNew<vtkMultiLightIlluminationVolume> filter;
  filter->AddLight(DirectionalLight(0, 0, -1));
  vtkNew<ErrorCounter> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(noScalars);
  filter->Update();
  EXPECT_EQ(errors->Count, 1);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
  vtkNew<vtkImageData> flat;
  flat->SetDimensions(8, 8, 1);
  flat->AllocateScalars(VTK_FLOAT, 1);
  filter->SetInputData(flat);
  filter->Update();
  EXPECT_EQ(errors->Count, 2);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(MultiLightIlluminationVolume, ResolutionScalesFollowTheReference)
{
  auto image = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 64);
  auto otf = RampOpacity(image, 0.3);
  double inBounds[6];
  image->GetBounds(inBounds);
  for (double scale : { 0.5, 0.25 })
  {
    auto reference = ImageFilter<vtkRayMarchedIllumination>(image, otf);
    auto propagated = ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    for (vtkIlluminationVolumeAlgorithm* f :
      { static_cast<vtkIlluminationVolumeAlgorithm*>(reference),
        static_cast<vtkIlluminationVolumeAlgorithm*>(propagated) })
    {
      f->SetResolutionScale(scale);
      f->AddLight(PointLight(-64, 32, 40, 1, 1, 0));
      f->AddLight(DirectionalLight(0.2, 0.1, -1, 0, 0.5, 1));
      f->Update();
    }
    double outBounds[6];
    propagated->GetOutput()->GetBounds(outBounds);
    for (int a = 0; a < 6; ++a)
    {
      EXPECT_NEAR(outBounds[a], inBounds[a], 1e-9);
    }
    const double rms = RmsRelative(Result(propagated), Result(reference));
    const double material =
      volillumfidelity::MaterialRms(propagated, Result(propagated), Result(reference));
    std::cout << "scale " << scale << ": RMS relative difference to the reference over material "
              << material << " (whole volume " << rms << ")" << std::endl;
    EXPECT_LE(material, scale == 0.5 ? 0.05 : 0.07);
    EXPECT_LE(rms, scale == 0.5 ? 0.1 : 0.15);
  }
}
