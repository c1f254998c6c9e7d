// Benchmarks of the two-level unstructured-grid illumination (one run, ratios):
//   volillum-unstructured-benchmark [--smoke] [--only scaling|table2|comparison] [--json FILE]
// 1. Scaling: level-0, level-1 and scattering times for tetrahedral meshes of 0.2 M to 5 M
//    tetrahedra (image grids split into five tetrahedra per cube), with a linear fit.
// 2. Table 2 replica (blunt fin): image RMS difference against the image lit with a
//    384^3 level-0 grid (the paper's reference size), for level-0 resolutions 16^3 to
//    256^3 (and the image without shadows).
// 3. Comparison on the blunt fin and disk_out_ref at level-0 resolutions 32^3, 64^3 and
//    128^3 (the default): the two-level solver, its level 0 alone and resampling to a
//    regular grid of the same resolution + Multi-Light Illumination Volume, same data and
//    light: time and per-vertex RMS against a brute-force march.
// --smoke uses tiny sizes so that CI only checks that it runs. --json writes the comparison's
// rows (for plot_benchmark.py).
#include "IlluminationLightList.h"
#include "IlluminationTestUtilities.h"
#include "vtkUnstructuredGridIllumination.h"

#include "vtkCamera.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkProjectedTetrahedraMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"

#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace
{
double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double Field(vtkUnstructuredGrid* grid, const char* name)
{
  return grid->GetFieldData()->GetArray(name)->GetTuple1(0);
}

vtkSmartPointer<vtkLight> Directional(double x, double y, double z, double r, double g, double b)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetPositional(false);
  light->SetPosition(0, 0, 0);
  light->SetFocalPoint(x, y, z);
  light->SetDiffuseColor(r, g, b);
  return light;
}

// A cube of n^3 points split into 5 (n-1)^3 tetrahedra, with a smooth density.
vtkSmartPointer<vtkUnstructuredGrid> CubeMesh(int n)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(n, n, n);
  image->SetSpacing(1.0 / (n - 1), 1.0 / (n - 1), 1.0 / (n - 1));
  vtkNew<vtkFloatArray> density;
  density->SetName("density");
  density->SetNumberOfTuples(image->GetNumberOfPoints());
  for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
  {
    double x[3];
    image->GetPoint(p, x);
    density->SetValue(
      p, static_cast<float>(1.0 + std::sin(9 * x[0]) * std::sin(7 * x[1]) * std::cos(5 * x[2])));
  }
  image->GetPointData()->SetScalars(density);
  vtkNew<vtkDataSetTriangleFilter> split;
  split->SetInputData(image);
  split->Update();
  return split->GetOutput();
}

void FitLine(const std::vector<double>& x, const std::vector<double>& y, double& slope,
  double& intercept, double& r2)
{
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < x.size(); ++i)
  {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
    syy += y[i] * y[i];
  }
  slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  intercept = (sy - slope * sx) / n;
  const double r = (n * sxy - sx * sy) / std::sqrt((n * sxx - sx * sx) * (n * syy - sy * sy));
  r2 = r * r;
}

void Scaling(bool smoke)
{
  std::cout << "\n1. Scaling (one directional light, level 0 128^3, 10 scattering iterations)\n";
  std::printf("%12s %10s %10s %10s %10s %10s %10s %10s\n", "tetrahedra", "vertices", "mesh s",
    "resample s", "level0 s", "level1 s", "scatter s", "total s");
  const std::vector<int> sizes =
    smoke ? std::vector<int>{ 6, 9 } : std::vector<int>{ 35, 51, 70, 101 };
  std::vector<double> tets, level1, scatter;
  for (int n : sizes)
  {
    auto mesh = CubeMesh(n);
    vtkNew<vtkUnstructuredGridIllumination> filter;
    filter->SetInputData(mesh);
    filter->AddLight(Directional(0.3, -0.2, -1, 1, 1, 1));
    filter->SetScatteringStrength(0.5, 0.5, 0.5);
    const double start = Now();
    filter->Update();
    const double total = Now() - start;
    vtkUnstructuredGrid* out = filter->GetOutput();
    tets.push_back(static_cast<double>(mesh->GetNumberOfCells()));
    level1.push_back(Field(out, "Level1Seconds"));
    scatter.push_back(Field(out, "ScatteringSeconds"));
    std::printf("%12lld %10lld %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f\n",
      static_cast<long long>(mesh->GetNumberOfCells()),
      static_cast<long long>(mesh->GetNumberOfPoints()), Field(out, "MeshSeconds"),
      Field(out, "ResampleSeconds"), Field(out, "Level0Seconds"), level1.back(), scatter.back(),
      total);
  }
  double slope, intercept, r2;
  FitLine(tets, level1, slope, intercept, r2);
  std::printf(
    "level 1 fit: %.3g s per million tetrahedra + %.3g s, R^2 %.4f\n", slope * 1e6, intercept, r2);
  FitLine(tets, scatter, slope, intercept, r2);
  std::printf("scattering fit: %.3g s per million tetrahedra + %.3g s, R^2 %.4f\n", slope * 1e6,
    intercept, r2);
}

void AddLights(vtkUnstructuredGridIllumination* filter, const double b[6])
{
  filter->AddLight(Directional(0, 0, -1, 1.0, 0.7, 0.3));
  auto point = vtkSmartPointer<vtkLight>::New();
  point->SetPositional(true);
  point->SetConeAngle(180);
  point->SetPosition(
    b[0] + 1.6 * (b[1] - b[0]), b[2] + 0.2 * (b[3] - b[2]), b[4] + 0.8 * (b[5] - b[4]));
  point->SetDiffuseColor(0.3, 0.5, 1.0);
  filter->AddLight(point);
}

// Renders the lit grid (LitColors on projected tetrahedra) in window and returns the RGB bytes.
std::vector<unsigned char> Render(
  vtkRenderWindow* window, vtkUnstructuredGrid* lit, int size, double unitDistance)
{
  vtkNew<vtkProjectedTetrahedraMapper> mapper;
  mapper->SetInputData(lit);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectScalarArray("LitColors");
  vtkNew<vtkVolumeProperty> property;
  property->IndependentComponentsOff();
  property->SetScalarOpacityUnitDistance(unitDistance);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(40);
  renderer->GetActiveCamera()->Elevation(25);
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->ResetCamera();
  window->SetSize(size, size);
  window->AddRenderer(renderer);
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  window->RemoveRenderer(renderer);
  auto* bytes = vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
  return std::vector<unsigned char>(
    bytes->GetPointer(0), bytes->GetPointer(0) + bytes->GetNumberOfValues());
}

double ImageRms(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b)
{
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
  {
    const double d = (static_cast<double>(a[i]) - b[i]) / 255.0;
    sum += d * d;
  }
  return std::sqrt(sum / a.size());
}

void Table2(vtkUnstructuredGrid* grid, bool smoke)
{
  std::cout << "\n2. Table 2 replica (blunt fin, two lights): image RMS vs level 0 at "
            << (smoke ? 32 : 384) << "^3\n";
  double range[2], bounds[6];
  grid->GetPointData()->GetScalars()->GetRange(range);
  grid->GetBounds(bounds);
  const double unitDistance = (bounds[1] - bounds[0]) / 128.0;
  const int size = smoke ? 64 : 512;
  // One window for every image: under a plain `xvfb-run -a` the X server resets when its last
  // client leaves, and a window opened just then finds no server.
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  const auto run = [&](int resolution, double& seconds)
  {
    vtkNew<vtkUnstructuredGridIllumination> filter;
    filter->SetInputData(grid);
    filter->SetOpacityFunction(volillumtest::RisingOpacity(range));
    filter->SetScalarOpacityUnitDistance(unitDistance);
    filter->SetLevel0Resolution(resolution, resolution, resolution);
    AddLights(filter, bounds);
    const double start = Now();
    filter->Update();
    seconds = Now() - start;
    return Render(window, filter->GetOutput(), size, unitDistance);
  };
  double seconds;
  const auto reference = run(smoke ? 32 : 384, seconds);
  std::printf("%10s %12s %10s\n", "level 0", "image RMS", "seconds");
  std::printf("%10s %12s %10.3f\n", smoke ? "32^3" : "384^3", "reference", seconds);
  for (int r : smoke ? std::vector<int>{ 8, 16 } : std::vector<int>{ 16, 32, 64, 128, 256 })
  {
    const auto image = run(r, seconds);
    std::printf("%7d^3 %12.5f %10.3f\n", r, ImageRms(image, reference), seconds);
  }
  // Without shadows: every light fully unoccluded (absorption 0 for the light only).
  vtkNew<vtkUnstructuredGridIllumination> unlit;
  unlit->SetInputData(grid);
  unlit->SetOpacityFunction(volillumtest::RisingOpacity(range));
  unlit->SetScalarOpacityUnitDistance(unitDistance);
  unlit->SetAbsorption(0.0);
  unlit->SetLevel0Resolution(16, 16, 16);
  AddLights(unlit, bounds);
  unlit->Update();
  std::printf("%10s %12.5f\n", "no shadow",
    ImageRms(Render(window, unlit->GetOutput(), size, unitDistance), reference));
}

// One comparison on the scene of a mesh at the given level-0 (and resampling) resolution: the
// two-level solver, its level 0 alone and resampling + propagation, timed and against the
// brute-force march.
void CompareAt(vtkUnstructuredGrid* grid, const volillumtest::MeshComparisonScene& scene,
  int resolution, const char* label, nlohmann::json& rows)
{
  const auto unstructured = [&](int iterations, double& seconds)
  {
    auto filter = volillumtest::SceneIllumination(grid, scene, resolution, iterations);
    const double start = Now();
    filter->Update();
    seconds = Now() - start;
    return volillumtest::Compare(
      filter->GetOutput()->GetPointData()->GetArray("Illumination"), scene.Reference)
      .Rms;
  };
  double twoLevelSeconds, level0Seconds;
  const double twoLevelRms = unstructured(-1, twoLevelSeconds);
  const double level0Rms = unstructured(0, level0Seconds);
  const double start = Now();
  vtkSmartPointer<vtkDataArray> resampled = volillumtest::ResampledIllumination(
    grid, scene.Opacity, scene.UnitDistance, scene.Light, resolution);
  const double resampleSeconds = Now() - start;
  const double resampleRms = volillumtest::Compare(resampled, scene.Reference).Rms;
  std::printf("%-14s %6d^3 %10.3f %8.4f %10.3f %8.4f %10.3f %8.4f\n", label, resolution,
    twoLevelSeconds, twoLevelRms, level0Seconds, level0Rms, resampleSeconds, resampleRms);
  rows.push_back({ { "mesh", label }, { "level0", resolution }, { "two_level_s", twoLevelSeconds },
    { "two_level_rms", twoLevelRms }, { "level0_only_s", level0Seconds },
    { "level0_only_rms", level0Rms }, { "resample_s", resampleSeconds },
    { "resample_rms", resampleRms } });
}

// The three ways of lighting an unstructured grid on one mesh, at the default level-0
// resolution (128^3) and coarser ones.
void AgainstResampling(
  const char* file, const char* scalars, const char* label, bool smoke, nlohmann::json& rows)
{
  auto grid =
    volillumtest::ReadUnstructuredGrid(std::string(VOLILLUM_SHARED_DATA) + "/tetmeshes/" + file);
  if (!grid)
  {
    std::cout << file << " not found: skipped\n";
    return;
  }
  grid->GetPointData()->SetActiveScalars(scalars);
  const auto scene = volillumtest::ComparisonScene(grid, smoke ? 50 : 1000);
  for (int resolution : smoke ? std::vector<int>{ 24 } : std::vector<int>{ 32, 64, 128 })
  {
    CompareAt(grid, scene, resolution, label, rows);
  }
}
}

int main(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  bool smoke = false;
  std::string only, jsonPath;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--smoke")
    {
      smoke = true;
    }
    else if (arg == "--only" && i + 1 < argc)
    {
      only = argv[++i];
    }
    else if (arg == "--json" && i + 1 < argc)
    {
      jsonPath = argv[++i];
    }
    else
    {
      std::cerr << "usage: volillum-unstructured-benchmark [--smoke] [--only "
                   "scaling|table2|comparison] [--json FILE]\n";
      return 1;
    }
  }
  const auto runs = [&](const char* part) { return only.empty() || only == part; };
  if (runs("scaling"))
  {
    Scaling(smoke);
  }
  if (runs("table2"))
  {
    const std::string path = std::string(VOLILLUM_SHARED_DATA) + "/tetmeshes/bluntfin_tets.vtu";
    if (auto bluntFin = volillumtest::ReadUnstructuredGrid(path))
    {
      bluntFin->GetPointData()->SetActiveScalars("Density");
      Table2(bluntFin, smoke);
    }
    else
    {
      std::cout << path << " not found: Table 2 skipped\n";
    }
  }
  if (runs("comparison"))
  {
    std::cout << "\n3. Two-level solver, its level 0 alone and resampling to a regular grid + "
                 "Multi-Light Illumination Volume at the same resolution (one oblique light; "
                 "seconds and per-vertex RMS relative to a brute-force march)\n";
    std::printf("%-14s %8s %10s %8s %10s %8s %10s %8s\n", "mesh", "level 0", "two-level", "RMS",
      "level 0", "RMS", "resample", "RMS");
    nlohmann::json rows = nlohmann::json::array();
    AgainstResampling("bluntfin_tets.vtu", "Density", "blunt fin", smoke, rows);
    AgainstResampling("disk_out_ref_tets.vtu", "Temp", "disk_out_ref", smoke, rows);
    if (!jsonPath.empty())
    {
      std::ofstream(jsonPath) << nlohmann::json{ { "unstructured_comparison", rows } }.dump(2)
                              << "\n";
    }
  }
  return 0;
}
