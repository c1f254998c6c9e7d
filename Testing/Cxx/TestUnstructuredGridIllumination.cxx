// Two-level unstructured-grid illumination against analytic and brute-force references.
#include "IlluminationLightList.h"
#include "IlluminationTestUtilities.h"
#include "TetrahedralLightKernel.h"
#include "vtkUnstructuredGridIllumination.h"

#include "vtkAppendFilter.h"
#include "vtkCellData.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkDoubleArray.h"
#include "vtkExtractCells.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkRectilinearGrid.h"
#include "vtkStaticCleanUnstructuredGrid.h"
#include "vtkStructuredGrid.h"
#include "vtkTetra.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGridAlgorithm.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <vector>

namespace
{
using volillumtest::DirectionalLight;
using volillumtest::PointLight;
using Field = std::function<double(const double*)>;

std::vector<double> Uniform(double lo, double hi, int n)
{
  std::vector<double> v(n);
  for (int i = 0; i < n; ++i)
  {
    v[i] = lo + (hi - lo) * i / (n - 1);
  }
  return v;
}

// Tetrahedral grid of a rectilinear box with the point array "density" = field(x)
// (hexahedra: its cells as they are).
vtkSmartPointer<vtkUnstructuredGrid> TetBox(const std::vector<double>& xs,
  const std::vector<double>& ys, const std::vector<double>& zs, const Field& field,
  bool hexahedra = false)
{
  vtkNew<vtkRectilinearGrid> grid;
  grid->SetDimensions(
    static_cast<int>(xs.size()), static_cast<int>(ys.size()), static_cast<int>(zs.size()));
  vtkNew<vtkDoubleArray> x, y, z;
  for (double v : xs)
  {
    x->InsertNextValue(v);
  }
  for (double v : ys)
  {
    y->InsertNextValue(v);
  }
  for (double v : zs)
  {
    z->InsertNextValue(v);
  }
  grid->SetXCoordinates(x);
  grid->SetYCoordinates(y);
  grid->SetZCoordinates(z);
  vtkNew<vtkDataSetTriangleFilter> split;
  split->TetrahedraOnlyOn();
  vtkNew<vtkAppendFilter> asIs;
  vtkUnstructuredGridAlgorithm* cells = hexahedra
    ? static_cast<vtkUnstructuredGridAlgorithm*>(asIs)
    : static_cast<vtkUnstructuredGridAlgorithm*>(split);
  cells->SetInputData(grid);
  cells->Update();
  auto mesh = vtkSmartPointer<vtkUnstructuredGrid>::New();
  mesh->DeepCopy(cells->GetOutput());
  vtkNew<vtkDoubleArray> density;
  density->SetName("density");
  density->SetNumberOfTuples(mesh->GetNumberOfPoints());
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    density->SetValue(p, field(mesh->GetPoint(p)));
  }
  mesh->GetPointData()->SetScalars(density);
  return mesh;
}

// Opacity function under which a density value is the extinction coefficient
// (unit distance 1): opacity = 1 - exp(-density), sampled finely over [0, maximum].
vtkSmartPointer<vtkPiecewiseFunction> ExtinctionOpacity(double maximum)
{
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  for (int i = 0; i <= 256; ++i)
  {
    const double s = maximum * i / 256.0;
    otf->AddPoint(s, 1.0 - std::exp(-s));
  }
  return otf;
}

vtkSmartPointer<vtkUnstructuredGridIllumination> MakeFilter(
  vtkUnstructuredGrid* mesh, double maximumDensity, int level0 = 64)
{
  auto filter = vtkSmartPointer<vtkUnstructuredGridIllumination>::New();
  filter->SetInputData(mesh);
  filter->SetOpacityFunction(ExtinctionOpacity(maximumDensity));
  filter->SetLevel0Resolution(level0, level0, level0);
  return filter;
}

vtkFloatArray* Illumination(vtkUnstructuredGridIllumination* filter)
{
  return vtkFloatArray::SafeDownCast(filter->GetOutput()->GetPointData()->GetArray("Illumination"));
}

// Brute-force transmittance with the "density" point array as the extinction.
std::vector<double> BruteForce(
  vtkUnstructuredGrid* mesh, const volillum::LightState& light, double step)
{
  vtkDataArray* density = mesh->GetPointData()->GetScalars();
  std::vector<double> sigma(mesh->GetNumberOfPoints());
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    sigma[p] = density->GetTuple1(p);
  }
  return volillumtest::BruteForceTransmittance(mesh, sigma, light, step);
}

using volillumtest::Compare;
using volillumtest::Errors;

int FieldInt(vtkUnstructuredGridIllumination* filter, const char* name)
{
  return static_cast<int>(filter->GetOutput()->GetFieldData()->GetArray(name)->GetTuple1(0));
}
}

TEST(UnstructuredGridIllumination, LevelZeroResamplingAndMask)
{
  // An L-shaped mesh (the unit cube minus the quarter x > 0.5, z > 0.5): the level-0 mask
  // covers 3/4 of the grid's cells, and a linear field is reproduced exactly inside.
  auto box = TetBox(Uniform(0, 1, 9), Uniform(0, 1, 9), Uniform(0, 1, 9),
    [](const double* x) { return 1.0 + 2.0 * x[0] - x[1] + 3.0 * x[2]; });
  std::vector<double> points(3 * box->GetNumberOfPoints());
  std::vector<float> extinction(box->GetNumberOfPoints());
  for (vtkIdType p = 0; p < box->GetNumberOfPoints(); ++p)
  {
    box->GetPoint(p, points.data() + 3 * p);
    extinction[p] = static_cast<float>(box->GetPointData()->GetScalars()->GetTuple1(p));
  }
  std::vector<long long> tets;
  for (vtkIdType c = 0; c < box->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    box->GetCellPoints(c, n, ids);
    double centre[3] = { 0, 0, 0 };
    for (int i = 0; i < 4; ++i)
    {
      for (int a = 0; a < 3; ++a)
      {
        centre[a] += 0.25 * points[3 * ids[i] + a];
      }
    }
    if (!(centre[0] > 0.5 && centre[2] > 0.5))
    {
      tets.insert(tets.end(), ids, ids + 4);
    }
  }
  volillum::TetrahedralMesh mesh;
  std::string error;
  ASSERT_TRUE(volillum::BuildTetrahedralMesh(points, tets, mesh, error)) << error;
  volillum::Level0Grid grid;
  volillum::ResampleLevel0(mesh, extinction, 1, { { 41, 41, 41 } }, grid);
  long long inside = 0;
  double worst = 0.0;
  for (int k = 0; k < 41; ++k)
  {
    for (int j = 0; j < 41; ++j)
    {
      for (int i = 0; i < 41; ++i)
      {
        const long long id = i + 41 * (j + 41LL * k);
        double x[3];
        grid.Geometry.PointPosition(i, j, k, x);
        const bool expected = !(x[0] > 0.5 + 1e-9 && x[2] > 0.5 + 1e-9);
        EXPECT_EQ(grid.Inside[id] != 0, expected) << x[0] << " " << x[1] << " " << x[2];
        if (expected)
        {
          ++inside;
          worst =
            std::max(worst, std::abs(grid.Extinction[id] - (1.0 + 2.0 * x[0] - x[1] + 3.0 * x[2])));
        }
        else
        {
          EXPECT_EQ(grid.Extinction[id], 0.0f); // blank: transparent
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_GT(inside, 41 * 41 * 41 * 3 / 4);
}

TEST(UnstructuredGridIllumination, HomogeneousMediumMatchesAnalyticTransmittance)
{
  // Extinction 2 in the unit cube: light travelling a distance d inside keeps exp(-2 d).
  auto mesh = TetBox(
    Uniform(0, 1, 17), Uniform(0, 1, 17), Uniform(0, 1, 17), [](const double*) { return 2.0; });
  const double bounds[6] = { 0, 1, 0, 1, 0, 1 };
  const std::vector<vtkSmartPointer<vtkLight>> lights = { DirectionalLight(0, 0, -1),
    DirectionalLight(0.3, -0.2, -1), PointLight(0.5, 0.4, 2.0), PointLight(0.3, 0.5, 0.6),
    PointLight(0.4, 0.5, 1.8) };
  lights[4]->SetFocalPoint(0.5, 0.5, 0.0); // a spot light: the cone factor applies on top
  lights[4]->SetConeAngle(25);
  lights[4]->SetExponent(2);
  const char* names[] = { "directional -z", "directional oblique", "point outside", "point inside",
    "spot" };
  // Level 0's error (the interpolation between its rays and grid points) shrinks with the
  // grid spacing, and level 1 keeps it (it refines the last level-0 cells of the path).
  for (size_t l = 0; l < lights.size(); ++l)
  {
    const volillum::LightState state = volillum::CaptureLight(lights[l]);
    std::vector<double> analytic(mesh->GetNumberOfPoints());
    for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
    {
      double x[3];
      mesh->GetPoint(p, x);
      const volillum::Incidence inc = volillum::ComputeIncidence(state, x);
      analytic[p] = inc.ConeFactor *
        std::exp(-2.0 *
          std::min(inc.Distance, volillum::DistanceToBoxExit(x, inc.ToLight.data(), bounds)));
    }
    Errors e[2];
    const int resolutions[2] = { 32, 128 };
    for (int r = 0; r < 2; ++r)
    {
      auto filter = MakeFilter(mesh, 4.0, resolutions[r]);
      filter->AddLight(lights[l]);
      filter->Update();
      e[r] = Compare(Illumination(filter), analytic);
      std::cout << names[l] << ", level 0 " << resolutions[r] << "^3: RMS relative " << e[r].Rms
                << ", max absolute " << e[r].Max << "\n";
    }
    EXPECT_LT(e[1].Rms, 0.002) << names[l];
    EXPECT_LT(e[1].Max, 0.01) << names[l];
    EXPECT_LT(e[1].Rms, 0.5 * e[0].Rms + 2e-3) << names[l];
  }
}

TEST(UnstructuredGridIllumination, LightCrossesTheGapOfANonConvexMesh)
{
  // A U: two arms x in [0,1] and [2,3] joined below z = 0.4; light travelling along +x
  // and slightly up crosses the left arm, the empty gap and then the right arm.
  auto box = TetBox(Uniform(0, 3, 31), Uniform(0, 1, 9), Uniform(0, 1, 11),
    [](const double* x) { return 1.0 + 0.5 * x[2]; });
  vtkNew<vtkIdList> keep;
  for (vtkIdType c = 0; c < box->GetNumberOfCells(); ++c)
  {
    double centre[3] = { 0, 0, 0 };
    vtkIdType n;
    const vtkIdType* ids;
    box->GetCellPoints(c, n, ids);
    for (vtkIdType i = 0; i < n; ++i)
    {
      const double* p = box->GetPoint(ids[i]);
      for (int a = 0; a < 3; ++a)
      {
        centre[a] += p[a] / n;
      }
    }
    if (!(centre[0] > 1 && centre[0] < 2 && centre[2] > 0.4))
    {
      keep->InsertNextId(c);
    }
  }
  vtkNew<vtkExtractCells> extract;
  extract->SetInputData(box);
  extract->SetCellList(keep);
  extract->Update();
  vtkUnstructuredGrid* u = extract->GetOutput();
  auto light = DirectionalLight(1, 0, 0.25);
  auto filter = MakeFilter(u, 2.0, 128);
  filter->AddLight(light);
  filter->Update();
  const auto reference = BruteForce(u, volillum::CaptureLight(light), 0.005);
  const Errors e = Compare(Illumination(filter), reference);
  std::cout << "U-shaped mesh: RMS relative " << e.Rms << ", max absolute " << e.Max << "\n";
  EXPECT_LT(e.Rms, 0.005);
  // The right arm's upper part is lit only through the gap, after the whole left arm.
  double rightArm = 0.0, leftArmFaceDepth = 0.0;
  int count = 0;
  for (vtkIdType p = 0; p < u->GetNumberOfPoints(); ++p)
  {
    const double* x = u->GetPoint(p);
    if (std::abs(x[0] - 2.0) < 1e-9 && x[2] > 0.75)
    {
      rightArm += Illumination(filter)->GetComponent(p, 0);
      leftArmFaceDepth += reference[p];
      ++count;
    }
  }
  ASSERT_GT(count, 0);
  EXPECT_NEAR(rightArm / count, leftArmFaceDepth / count, 0.03);
  EXPECT_LT(rightArm / count, 0.5); // shadowed by the left arm, not lit as if outside
  EXPECT_GT(rightArm / count, 0.1); // but light did cross the gap
}

TEST(UnstructuredGridIllumination, LitBoundaryOfAnOGridTakesTheLightOutside)
{
  // An O-grid around a post, laid out as the LOx post's CFD mesh: an annulus of hexahedra
  // (radius 0.25 to 1, graded toward the post, height 0.5) whose theta = 0 and 2 pi points
  // are copies (the seam), split into tetrahedra. Light crosses it sideways, entering
  // through the curved outer wall, which cuts the level-0 grid's cells anywhere.
  const int radial = 10, around = 48, layers = 6;
  vtkNew<vtkPoints> points;
  for (int k = 0; k < layers; ++k)
  {
    for (int j = 0; j <= around; ++j)
    {
      const double theta = 2.0 * vtkMath::Pi() * (j % around) / around;
      for (int i = 0; i < radial; ++i)
      {
        const double u = static_cast<double>(i) / (radial - 1);
        const double r = 0.25 + 0.75 * u * u;
        points->InsertNextPoint(r * std::cos(theta), r * std::sin(theta), 0.1 * k);
      }
    }
  }
  vtkNew<vtkStructuredGrid> ogrid;
  ogrid->SetDimensions(radial, around + 1, layers);
  ogrid->SetPoints(points);
  vtkNew<vtkDataSetTriangleFilter> split;
  split->SetInputData(ogrid);
  split->Update();
  vtkUnstructuredGrid* mesh = split->GetOutput();
  vtkNew<vtkDoubleArray> density;
  density->SetName("density");
  density->SetNumberOfTuples(mesh->GetNumberOfPoints());
  density->Fill(3.0);
  mesh->GetPointData()->SetScalars(density);

  const auto light = DirectionalLight(-1, -0.3, -0.2);
  auto filter = MakeFilter(mesh, 4.0, 32);
  filter->AddLight(light);
  filter->Update();
  const auto reference = BruteForce(mesh, volillum::CaptureLight(light), 0.002);
  vtkFloatArray* got = Illumination(filter);
  // The outer wall where the light enters (its outward normal toward the light) is lit as
  // if nothing stood before it. Level-0 grid points inside the wall mixed in darken it by up
  // to a cell of material, 1 - exp(-3 x 0.065 / cos), differently on every column of the
  // wall (0.22 at worst when they were). Beside the wall, the first-order upwind level 0 of
  // the paper diffused the light by 0.08 where the wall is oblique to it; with rays and a
  // level-1 walk of four level-0 cells 0.009 is left.
  const double origin[3] = { 0.0, 0.0, 0.0 };
  const volillum::Incidence inc = volillum::ComputeIncidence(volillum::CaptureLight(light), origin);
  double wallError = 0.0;
  int wallPoints = 0;
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    const double* x = mesh->GetPoint(p);
    const double r = std::hypot(x[0], x[1]);
    if (std::abs(r - 1.0) < 1e-5 && (x[0] * inc.ToLight[0] + x[1] * inc.ToLight[1]) / r > 0.2)
    {
      wallError = std::max(wallError, std::abs(got->GetComponent(p, 0) - reference[p]));
      ++wallPoints;
    }
  }
  const Errors e = Compare(got, reference);
  std::cout << "O-grid lit from the side: lit outer wall " << wallPoints
            << " points, max absolute error " << wallError << "; all points RMS relative " << e.Rms
            << ", max absolute " << e.Max << "\n";
  ASSERT_GT(wallPoints, 0);
  EXPECT_LT(wallError, 0.015);
  EXPECT_LT(e.Rms, 0.035);
}

TEST(UnstructuredGridIllumination, TwoLevelsBeatLevelZeroOnAnAdaptiveMesh)
{
  // A small dense blob inside a thin medium, the mesh graded to be fine around it and a
  // coarse level-0 grid (8^3) that cannot resolve it.
  std::vector<double> c;
  for (int i = 0; i <= 24; ++i)
  {
    const double u = -1.0 + 2.0 * i / 24.0;
    c.push_back(0.5 + 0.5 * u * std::abs(u)); // spacing shrinks toward the centre 0.5
  }
  const Field blob = [](const double* x)
  {
    const double r2 =
      (x[0] - 0.5) * (x[0] - 0.5) + (x[1] - 0.5) * (x[1] - 0.5) + (x[2] - 0.55) * (x[2] - 0.55);
    return 0.2 + 40.0 * std::exp(-r2 / (0.04 * 0.04));
  };
  auto mesh = TetBox(c, c, c, blob);
  auto light = DirectionalLight(0.1, 0.05, -1);
  const auto reference = BruteForce(mesh, volillum::CaptureLight(light), 0.004);
  double error[2];
  for (int levels = 0; levels < 2; ++levels)
  {
    auto filter = MakeFilter(mesh, 42.0, 8);
    filter->SetLevel1Iterations(levels == 0 ? 0 : -1);
    filter->AddLight(light);
    filter->Update();
    error[levels] = Compare(Illumination(filter), reference).Rms;
  }
  std::cout << "adaptive mesh, RMS relative to brute force: level 0 only " << error[0]
            << ", level 0 + level 1 " << error[1] << "\n";
  EXPECT_LT(error[1], error[0]);
}

TEST(UnstructuredGridIllumination, TwoLevelsBeatLevelZeroAndResamplingOnRealMeshes)
{
  // volillum-unstructured-benchmark's comparison at a coarse level 0 (32^3), where the ways
  // differ most, on two real meshes: per-vertex RMS against a brute-force march of the
  // two-level solver, its level 0 alone, and resampling to a 32^3 grid lit by
  // Multi-Light Illumination Volume.
  const std::string data = VOLILLUM_SHARED_DATA;
  for (const auto& mesh : { std::make_pair("bluntfin_tets.vtu", "Density"),
         std::make_pair("disk_out_ref_tets.vtu", "Temp") })
  {
    auto grid = volillumtest::ReadUnstructuredGrid(data + "/tetmeshes/" + mesh.first);
    if (!grid)
    {
      GTEST_SKIP() << "../shared/data is not beside the clone";
    }
    grid->GetPointData()->SetActiveScalars(mesh.second);
    const auto scene = volillumtest::ComparisonScene(grid, 300);
    double error[2];
    for (int levels = 0; levels < 2; ++levels)
    {
      auto filter = volillumtest::SceneIllumination(grid, scene, 32, levels == 0 ? 0 : -1);
      filter->Update();
      error[levels] = Compare(Illumination(filter), scene.Reference).Rms;
    }
    const double resampled = Compare(
      volillumtest::ResampledIllumination(grid, scene.Opacity, scene.UnitDistance, scene.Light, 32),
      scene.Reference)
                               .Rms;
    std::cout << mesh.first << ", RMS relative to brute force: two-level " << error[1]
              << ", level 0 only " << error[0] << ", resampled " << resampled << "\n";
    EXPECT_LT(error[1], 0.75 * error[0]) << mesh.first;
    EXPECT_LT(error[1], 0.75 * resampled) << mesh.first;
  }
}

TEST(UnstructuredGridIllumination, ScatteringKeepsTheEnergyWithoutAbsorption)
{
  auto mesh = TetBox(Uniform(0, 1, 15), Uniform(0, 1, 15), Uniform(0, 1, 15),
    [](const double* x) { return 1.0 + x[0]; });
  auto spot = PointLight(0.5, 0.5, 2.0);
  spot->SetFocalPoint(0.5, 0.5, 0.0);
  spot->SetConeAngle(10);
  auto filter = MakeFilter(mesh, 3.0);
  filter->SetAbsorption(0.0);
  filter->AddLight(spot);
  filter->Update();
  vtkNew<vtkFloatArray> before;
  before->DeepCopy(Illumination(filter));
  filter->SetScatteringStrength(2.0, 1.0, 0.5);
  filter->SetScatteringIterations(60);
  filter->Update();
  vtkFloatArray* after = Illumination(filter);
  for (int c = 0; c < 3; ++c)
  {
    double e0 = 0.0, e1 = 0.0, change = 0.0;
    for (vtkIdType p = 0; p < before->GetNumberOfTuples(); ++p)
    {
      e0 += before->GetComponent(p, c);
      e1 += after->GetComponent(p, c);
      change = std::max(change, std::abs(before->GetComponent(p, c) - after->GetComponent(p, c)));
    }
    std::cout << "channel " << c << ": energy " << e0 << " -> " << e1 << " ("
              << 100.0 * (e1 - e0) / e0 << " %), largest change " << change << "\n";
    EXPECT_LT(std::abs(e1 - e0) / e0, 0.01);
    EXPECT_GT(change, 0.05); // the light did spread out of the cone
  }
  EXPECT_EQ(FieldInt(filter, "PropagationPasses"), 0); // scattering alone propagates nothing
}

TEST(UnstructuredGridIllumination, OneChangedLightEqualsAFullRecompute)
{
  auto mesh = TetBox(Uniform(0, 1, 13), Uniform(0, 2, 17), Uniform(0, 1, 13),
    [](const double* x) { return 0.5 + 2.0 * x[1] * x[2]; });
  auto a = DirectionalLight(0, 0, -1, 1, 0.8, 0.2);
  auto b = PointLight(-0.5, 1.0, 0.5, 0.2, 0.4, 1.0);
  auto c = DirectionalLight(1, 1, 0, 0.5, 1, 0.5);
  auto selective = MakeFilter(mesh, 3.0, 48);
  selective->SetChromaticAttenuation(true);
  selective->SetScatteringStrength(0.3, 0.3, 0.3);
  for (auto* l : { a.Get(), b.Get(), c.Get() })
  {
    selective->AddLight(l);
  }
  selective->Update();
  EXPECT_EQ(FieldInt(selective, "UpdateMode"), 0);
  b->SetPosition(1.5, 0.5, 0.7);
  selective->Update();
  EXPECT_EQ(FieldInt(selective, "UpdateMode"), 1);
  EXPECT_EQ(FieldInt(selective, "PropagationPasses"), 1);
  a->SetDiffuseColor(0.1, 0.9, 0.3);
  selective->Update();
  EXPECT_EQ(FieldInt(selective, "PropagationPasses"), 0);

  auto full = MakeFilter(mesh, 3.0, 48);
  full->SetChromaticAttenuation(true);
  full->SetScatteringStrength(0.3, 0.3, 0.3);
  for (auto* l : { a.Get(), b.Get(), c.Get() })
  {
    full->AddLight(l);
  }
  full->Update();
  EXPECT_EQ(FieldInt(full, "PropagationPasses"), 3);
  vtkFloatArray* got = Illumination(selective);
  vtkFloatArray* want = Illumination(full);
  double worst = 0.0;
  for (vtkIdType i = 0; i < want->GetNumberOfValues(); ++i)
  {
    worst = std::max<double>(worst,
      std::abs(got->GetValue(i) - want->GetValue(i)) / std::max(1.0f, std::abs(want->GetValue(i))));
  }
  std::cout << "selective vs full recompute: largest difference " << worst << "\n";
  EXPECT_LE(worst, 1e-5);

  // A transfer-function change recomputes every light.
  selective->GetOpacityFunction()->AddPoint(1.51, 0.9);
  selective->Update();
  EXPECT_EQ(FieldInt(selective, "UpdateMode"), 0);
  EXPECT_EQ(FieldInt(selective, "PropagationPasses"), 3);
}

// A file of several pieces (a .pvtu written in parallel) read as one grid holds a copy of
// each point on a cut per piece. The copies are one point: the pieces light as the whole
// grid (before, the cuts were lit as boundaries: 8.6e-3 of the largest value apart in a
// user's trial), also when the pieces carry ghost cells (left out, as in parallel) and when
// they are hexahedra (split after the copies are joined, so both sides of a cut split a face
// alike). With point global
// ids that tell the copies apart they stay two (a seam), and the same filter notices when the ids
// come or go.
namespace
{
// The cells of mesh in three pieces cut obliquely, each with its own copies of its points
// and, with `ghosts`, the previous piece's cells as ghost cells (DUPLICATECELL), appended.
vtkSmartPointer<vtkUnstructuredGrid> PiecesOf(vtkUnstructuredGrid* mesh, bool ghosts)
{
  auto pieceOf = [&](vtkIdType c)
  {
    double centre[2] = { 0.0, 0.0 };
    vtkIdType n;
    const vtkIdType* ids;
    mesh->GetCellPoints(c, n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      const double* x = mesh->GetPoint(ids[k]);
      centre[0] += x[0] / n;
      centre[1] += x[1] / n;
    }
    const double key = centre[0] + 0.3 * centre[1];
    return key < 0.45 ? 0 : key < 0.9 ? 1 : 2;
  };
  vtkNew<vtkAppendFilter> pieces;
  for (int piece = 0; piece < 3; ++piece)
  {
    vtkNew<vtkIdList> cells;
    std::vector<unsigned char> flags;
    for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
    {
      const int of = pieceOf(c);
      if (of == piece || (ghosts && of == piece - 1))
      {
        cells->InsertNextId(c);
        flags.push_back(of == piece ? 0 : vtkDataSetAttributes::DUPLICATECELL);
      }
    }
    vtkNew<vtkExtractCells> extract;
    extract->SetInputData(mesh);
    extract->SetCellList(cells);
    extract->Update();
    auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
    copy->DeepCopy(extract->GetOutput());
    if (ghosts)
    {
      vtkNew<vtkUnsignedCharArray> ghost;
      ghost->SetName(vtkDataSetAttributes::GhostArrayName());
      ghost->SetNumberOfTuples(copy->GetNumberOfCells());
      std::copy(flags.begin(), flags.end(), ghost->GetPointer(0));
      copy->GetCellData()->AddArray(ghost);
    }
    pieces->AddInputData(copy);
  }
  pieces->Update();
  auto file = vtkSmartPointer<vtkUnstructuredGrid>::New();
  file->ShallowCopy(pieces->GetOutput());
  return file;
}

// The largest difference of the illumination of grid's points (`got`) from that of mesh's
// point at their place (`want`), over the largest of want.
double DifferenceAtPlaces(
  vtkUnstructuredGrid* mesh, vtkFloatArray* want, vtkUnstructuredGrid* grid, vtkFloatArray* got)
{
  std::map<std::array<double, 3>, vtkIdType> at;
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    const double* x = mesh->GetPoint(p);
    at[{ x[0], x[1], x[2] }] = p;
  }
  double worst = 0.0, largest = 0.0;
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    const double* x = grid->GetPoint(p);
    const vtkIdType q = at.at({ x[0], x[1], x[2] });
    for (int c = 0; c < 3; ++c)
    {
      worst = std::max<double>(worst, std::abs(got->GetComponent(p, c) - want->GetComponent(q, c)));
      largest = std::max<double>(largest, std::abs(want->GetComponent(q, c)));
    }
  }
  return worst / largest;
}
}

TEST(UnstructuredGridIllumination, PiecesOfAFileLightAsTheWholeGrid)
{
  const Field density = [](const double* x) { return 0.5 + 2.0 * x[1] * x[2]; };
  auto tetrahedra = TetBox(Uniform(0, 1, 13), Uniform(0, 2, 17), Uniform(0, 1, 13), density);
  auto hexahedra = TetBox(Uniform(0, 1, 13), Uniform(0, 2, 17), Uniform(0, 1, 13), density, true);

  auto lit = [](vtkUnstructuredGrid* grid)
  {
    auto filter = MakeFilter(grid, 3.0, 32);
    filter->SetScatteringStrength(0.3, 0.3, 0.3);
    filter->AddLight(DirectionalLight(0.3, 1, -1));
    filter->AddLight(PointLight(-0.5, 1.0, 0.5, 0.2, 0.4, 1.0));
    filter->Update();
    return filter;
  };
  for (vtkUnstructuredGrid* mesh : { tetrahedra.Get(), hexahedra.Get() })
  {
    for (bool ghosts : { false, true })
    {
      if (ghosts && mesh == hexahedra)
      {
        continue; // (the extra copies would number the hexahedra's points otherwise again)
      }
      auto file = PiecesOf(mesh, ghosts);
      ASSERT_GT(file->GetNumberOfPoints(), mesh->GetNumberOfPoints());
      auto pieces = lit(file);
      // Hexahedra split into tetrahedra by the order of their points' ids, which the file
      // numbers otherwise: the reference is the file with its copies merged
      // (vtkStaticCleanUnstructuredGrid keeps the first copies in their order).
      vtkSmartPointer<vtkUnstructuredGrid> reference = mesh;
      if (mesh == hexahedra)
      {
        vtkNew<vtkStaticCleanUnstructuredGrid> merge;
        merge->SetInputData(file);
        merge->Update();
        reference = merge->GetOutput();
        ASSERT_EQ(reference->GetNumberOfPoints(), mesh->GetNumberOfPoints());
      }
      auto whole = lit(reference);
      const double difference =
        DifferenceAtPlaces(reference, Illumination(whole), file, Illumination(pieces));
      std::cout << (mesh == tetrahedra ? "tetrahedra" : "hexahedra") << " in pieces"
                << (ghosts ? " with ghost cells" : "") << " against the whole grid: " << difference
                << "\n";
      EXPECT_LE(difference, 1e-6);
    }
  }

  // Copies told apart by point global ids stay a seam; the same filter, given the same points
  // and cells with ids and then without, lights each as a fresh filter does.
  auto file = PiecesOf(tetrahedra, false);
  vtkNew<vtkUnstructuredGrid> seams;
  seams->ShallowCopy(file);
  vtkNew<vtkIdTypeArray> ids;
  ids->SetNumberOfTuples(seams->GetNumberOfPoints());
  for (vtkIdType p = 0; p < seams->GetNumberOfPoints(); ++p)
  {
    ids->SetValue(p, p); // every copy its own id
  }
  seams->GetPointData()->SetGlobalIds(ids);
  auto whole = lit(tetrahedra);
  auto filter = lit(seams);
  const double seam =
    DifferenceAtPlaces(tetrahedra, Illumination(whole), seams, Illumination(filter));
  std::cout << "with the copies told apart (seams): " << seam << "\n";
  EXPECT_GT(seam, 1e-3);
  filter->SetInputData(file);
  filter->Update();
  EXPECT_LE(DifferenceAtPlaces(tetrahedra, Illumination(whole), file, Illumination(filter)), 1e-6);
}

TEST(UnstructuredGridIllumination, AbortKeepsThePreviousOutput)
{
  auto mesh = TetBox(Uniform(0, 1, 11), Uniform(0, 1, 11), Uniform(0, 1, 11),
    [](const double* x) { return 1.0 + x[1]; });
  std::vector<vtkSmartPointer<vtkLight>> lights = { DirectionalLight(0, 0, -1),
    DirectionalLight(1, 0, 0), PointLight(0.5, 0.5, 1.5) };
  auto filter = MakeFilter(mesh, 2.0, 32);
  for (auto& l : lights)
  {
    filter->AddLight(l);
  }
  filter->Update();
  vtkNew<vtkFloatArray> before;
  before->DeepCopy(Illumination(filter));
  vtkNew<volillumtest::AbortHalfway> abort;
  filter->AddObserver(vtkCommand::ProgressEvent, abort);
  abort->Armed = true;
  lights[0]->SetFocalPoint(0.3, 0, -1);
  lights[1]->SetFocalPoint(1, 0.2, 0);
  lights[2]->SetPosition(0.2, 0.5, 1.5);
  filter->Update();
  ASSERT_NE(Illumination(filter), nullptr);
  EXPECT_EQ(volillumtest::RmsRelative(Illumination(filter), before), 0.0);
  // The next update finishes the lights the aborted one did not reach.
  filter->SetAbortExecute(0);
  filter->Modified();
  filter->Update();
  EXPECT_EQ(FieldInt(filter, "UpdateMode"), 1);
  EXPECT_LT(FieldInt(filter, "PropagationPasses"), 3);
  auto fresh = MakeFilter(mesh, 2.0, 32);
  for (auto& l : lights)
  {
    fresh->AddLight(l);
  }
  fresh->Update();
  EXPECT_LE(volillumtest::RmsRelative(Illumination(filter), Illumination(fresh)), 1e-7);
}

TEST(UnstructuredGridIllumination, InvertedAndNonTetrahedralCellsGiveTheSameLight)
{
  auto mesh = TetBox(Uniform(0, 1, 11), Uniform(0, 1, 11), Uniform(0, 1, 11),
    [](const double* x) { return 1.0 + x[0] + x[2]; });
  // Every other tetrahedron listed with two vertices swapped (negative volume).
  vtkNew<vtkUnstructuredGrid> flipped;
  flipped->SetPoints(mesh->GetPoints());
  flipped->GetPointData()->ShallowCopy(mesh->GetPointData());
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    mesh->GetCellPoints(c, n, ids);
    vtkIdType v[4] = { ids[0], ids[1], ids[2], ids[3] };
    if (c % 2)
    {
      std::swap(v[0], v[1]);
    }
    flipped->InsertNextCell(VTK_TETRA, 4, v);
  }
  // The same box as voxels (hexahedral cells), split by the filter itself.
  vtkNew<vtkRectilinearGrid> rect;
  rect->SetDimensions(11, 11, 11);
  vtkNew<vtkDoubleArray> coords;
  for (double v : Uniform(0, 1, 11))
  {
    coords->InsertNextValue(v);
  }
  rect->SetXCoordinates(coords);
  rect->SetYCoordinates(coords);
  rect->SetZCoordinates(coords);
  vtkNew<vtkUnstructuredGrid> voxels;
  vtkNew<vtkPoints> points;
  for (vtkIdType p = 0; p < rect->GetNumberOfPoints(); ++p)
  {
    points->InsertNextPoint(rect->GetPoint(p));
  }
  voxels->SetPoints(points);
  vtkNew<vtkGenericCell> cell;
  for (vtkIdType c = 0; c < rect->GetNumberOfCells(); ++c)
  {
    rect->GetCell(c, cell);
    voxels->InsertNextCell(cell->GetCellType(), cell->GetPointIds());
  }
  vtkNew<vtkDoubleArray> density;
  density->SetName("density");
  for (vtkIdType p = 0; p < voxels->GetNumberOfPoints(); ++p)
  {
    const double* x = voxels->GetPoint(p);
    density->InsertNextValue(1.0 + x[0] + x[2]);
  }
  voxels->GetPointData()->SetScalars(density);

  auto light = DirectionalLight(0.2, 0.3, -1);
  vtkSmartPointer<vtkFloatArray> results[3];
  vtkUnstructuredGrid* inputs[3] = { mesh, flipped, voxels };
  for (int i = 0; i < 3; ++i)
  {
    auto filter = MakeFilter(inputs[i], 3.0, 128);
    filter->AddLight(light);
    filter->Update();
    results[i] = Illumination(filter);
    ASSERT_NE(results[i], nullptr);
  }
  EXPECT_LT(volillumtest::RmsRelative(results[1], results[0]), 1e-6);
  // The voxels are split differently from the rectilinear grid's tetrahedra, so the
  // light differs by the discretisation only; both agree with the brute-force march.
  const auto reference = BruteForce(mesh, volillum::CaptureLight(light), 0.005);
  const double voxelError = Compare(results[2], reference).Rms;
  const double tetError = Compare(results[0], reference).Rms;
  std::cout << "voxels " << voxelError << ", tetrahedra " << tetError << " RMS relative\n";
  EXPECT_LT(voxelError, 0.05);
  EXPECT_LT(tetError, 0.05);
}

TEST(UnstructuredGridIllumination, DegenerateAndMixedOrientationMeshesFromDisk)
{
  // 80 of tetraMesh.vtk's 160 tetrahedra are inverted; bluntfin has 77 of zero volume.
  const std::string data = VOLILLUM_SHARED_DATA;
  for (const char* name : { "/tetmeshes/tetraMesh.vtk", "/tetmeshes/bluntfin_tets.vtu" })
  {
    auto mesh = volillumtest::ReadUnstructuredGrid(data + name);
    if (!mesh)
    {
      GTEST_SKIP() << "../shared/data is not beside the clone";
    }
    auto filter = vtkSmartPointer<vtkUnstructuredGridIllumination>::New();
    filter->SetInputData(mesh);
    filter->SetLevel0Resolution(32, 32, 32);
    filter->AddLight(DirectionalLight(0.3, 0.2, -1));
    filter->Update();
    vtkFloatArray* light = Illumination(filter);
    ASSERT_NE(light, nullptr) << name;
    double lo = 1e30, hi = -1e30;
    for (vtkIdType i = 0; i < light->GetNumberOfValues(); ++i)
    {
      ASSERT_TRUE(std::isfinite(light->GetValue(i))) << name;
      lo = std::min<double>(lo, light->GetValue(i));
      hi = std::max<double>(hi, light->GetValue(i));
    }
    EXPECT_GE(lo, 0.0) << name;
    EXPECT_LE(hi, 1.0 + 1e-5) << name;
    EXPECT_LT(lo, hi) << name; // something casts a shadow
  }
}

TEST(UnstructuredGridIllumination, BadInputGivesAnErrorAndAnEmptyOutput)
{
  auto good =
    TetBox(Uniform(0, 1, 5), Uniform(0, 1, 5), Uniform(0, 1, 5), [](const double*) { return 1.0; });
  vtkNew<vtkUnstructuredGrid> empty;
  vtkNew<vtkUnstructuredGrid> triangles;
  triangles->SetPoints(good->GetPoints());
  triangles->GetPointData()->ShallowCopy(good->GetPointData());
  const vtkIdType tri[3] = { 0, 1, 2 };
  triangles->InsertNextCell(VTK_TRIANGLE, 3, tri);
  vtkNew<vtkUnstructuredGrid> noScalars;
  noScalars->ShallowCopy(good);
  noScalars->GetPointData()->Initialize();
  vtkNew<vtkUnstructuredGrid> flat; // tetrahedra of zero volume only
  flat->ShallowCopy(good);
  vtkNew<vtkPoints> flatPoints;
  for (vtkIdType p = 0; p < good->GetNumberOfPoints(); ++p)
  {
    const double* x = good->GetPoint(p);
    flatPoints->InsertNextPoint(x[0], x[1], 0.0);
  }
  flat->SetPoints(flatPoints);
  const auto withScalarCount = [&good](vtkIdType count)
  {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    grid->ShallowCopy(good);
    vtkNew<vtkFloatArray> values;
    values->SetName("values");
    values->SetNumberOfTuples(count);
    values->FillValue(1.0f);
    grid->GetPointData()->SetScalars(values);
    return grid;
  };
  auto moreScalars = withScalarCount(good->GetNumberOfPoints() + 1);
  auto fewerScalars = withScalarCount(good->GetNumberOfPoints() - 1);
  vtkNew<vtkUnstructuredGrid> nanPoint;
  nanPoint->DeepCopy(good);
  nanPoint->GetPoints()->SetPoint(7, 0.5, std::nan(""), 0.5);
  const auto withCell = [&good](int type, std::vector<vtkIdType> ids)
  {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    grid->DeepCopy(good);
    grid->InsertNextCell(type, static_cast<vtkIdType>(ids.size()), ids.data());
    return grid;
  };
  auto badTetra = withCell(VTK_TETRA, { 0, 1, 2, 99999 });
  auto badHexahedron = withCell(VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, -3 });

  struct Case
  {
    const char* What;
    vtkUnstructuredGrid* Input;
    std::function<void(vtkUnstructuredGridIllumination*)> Configure;
  };
  const std::vector<Case> cases = {
    { "empty grid", empty, [](vtkUnstructuredGridIllumination*) {} },
    { "2D cells only", triangles, [](vtkUnstructuredGridIllumination*) {} },
    { "no scalars", noScalars, [](vtkUnstructuredGridIllumination*) {} },
    { "zero-volume cells", flat, [](vtkUnstructuredGridIllumination*) {} },
    { "NaN light", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetLightParameter(1, std::nan("")); } },
    { "NaN absorption", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetAbsorption(std::nan("")); } },
    { "NaN scattering", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetScatteringStrength(0, std::nan(""), 0); } },
    { "light of intensity 1e10", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetLightParameter(10, 1e10); } },
    { "directional light at its focal point", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetLightParameter(3, 0.0); } },
    { "spot light aimed at itself", good,
      [](vtkUnstructuredGridIllumination* f)
      {
        f->SetLightParameter(0, 1.0);
        f->SetLightParameter(3, 0.0);
      } },
    { "negative cone angle", good,
      [](vtkUnstructuredGridIllumination* f)
      {
        f->SetLightParameter(0, 1.0);
        f->SetLightParameter(11, -10.0);
      } },
    { "one scalar more than points", moreScalars, [](vtkUnstructuredGridIllumination*) {} },
    { "one scalar less than points", fewerScalars, [](vtkUnstructuredGridIllumination*) {} },
    { "a NaN point coordinate", nanPoint, [](vtkUnstructuredGridIllumination*) {} },
    { "a tetrahedron with a point id beyond the points", badTetra,
      [](vtkUnstructuredGridIllumination*) {} },
    { "a hexahedron with a negative point id", badHexahedron,
      [](vtkUnstructuredGridIllumination*) {} },
    { "level-0 resolution 1", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetLevel0Resolution(1, 64, 64); } },
    { "level-0 resolution 5000", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetLevel0Resolution(5000, 5000, 5000); } },
    { "level-0 grid of 1024^3 points", good,
      [](vtkUnstructuredGridIllumination* f) { f->SetLevel0Resolution(1024, 1024, 1024); } },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkUnstructuredGridIllumination> filter;
    vtkNew<volillumtest::ErrorCounter> errors;
    filter->AddObserver(vtkCommand::ErrorEvent, errors);
    filter->SetInputData(c.Input);
    filter->SetNumberOfLightParameters(volillum::LightParameterCount);
    c.Configure(filter);
    filter->Update();
    EXPECT_GE(errors->Count, 1) << c.What;
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0) << c.What;
    std::cout << c.What << ": " << errors->LastMessage;
  }
}
