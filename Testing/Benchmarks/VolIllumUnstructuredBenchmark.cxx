// Benchmarks of the two-level unstructured-grid illumination (one run, ratios):
//   volillum-unstructured-benchmark [--smoke]
// 1. Scaling: level-0, level-1 and scattering times for tetrahedral meshes of 0.2 M to 5 M
//    tetrahedra (image grids split into five tetrahedra per cube), with a linear fit.
// 2. Table 2 replica (blunt fin): image RMS difference against the image lit with a
//    384^3 level-0 grid (the paper's reference size), for level-0 resolutions 16^3 to
//    256^3 (and the image without shadows).
// 3. Two-level solver vs resampling to a regular grid + Multi-Light Illumination Volume,
//    same data and lights: time and per-vertex RMS against a brute-force march.
// --smoke uses tiny sizes so that CI only checks that it runs.
#include "IlluminationLightList.h"
#include "IlluminationTestUtilities.h"
#include "vtkMultiLightIlluminationVolume.h"
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
#include "vtkProbeFilter.h"
#include "vtkProjectedTetrahedraMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkResampleToImage.h"
#include "vtkSMPTools.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLUnstructuredGridReader.h"

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

vtkSmartPointer<vtkPiecewiseFunction> Opacity(const double range[2])
{
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  const double w = range[1] - range[0];
  otf->AddPoint(range[0], 0.0);
  otf->AddPoint(range[0] + 0.15 * w, 0.02);
  otf->AddPoint(range[0] + 0.5 * w, 0.2);
  otf->AddPoint(range[1], 0.6);
  return otf;
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
    filter->SetOpacityFunction(Opacity(range));
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
  unlit->SetOpacityFunction(Opacity(range));
  unlit->SetScalarOpacityUnitDistance(unitDistance);
  unlit->SetAbsorption(0.0);
  unlit->SetLevel0Resolution(16, 16, 16);
  AddLights(unlit, bounds);
  unlit->Update();
  std::printf("%10s %12.5f\n", "no shadow",
    ImageRms(Render(window, unlit->GetOutput(), size, unitDistance), reference));
}

double VertexRms(vtkDataArray* got, const std::vector<double>& reference)
{
  double e = 0.0, norm = 0.0;
  for (size_t p = 0; p < reference.size(); ++p)
  {
    const double d = got->GetComponent(static_cast<vtkIdType>(p), 0) - reference[p];
    e += d * d;
    norm += reference[p] * reference[p];
  }
  return std::sqrt(e / norm);
}

void AgainstResampling(vtkUnstructuredGrid* grid, bool smoke)
{
  std::cout
    << "\n3. Two-level solver vs resample + Multi-Light Illumination Volume (blunt fin, one "
       "oblique light, per-vertex RMS vs a brute-force march)\n";
  double range[2], bounds[6];
  grid->GetPointData()->GetScalars()->GetRange(range);
  grid->GetBounds(bounds);
  // A thinner medium than the rendering's, so that most vertices see some light.
  const double unitDistance = (bounds[1] - bounds[0]) / 8.0;
  auto otf = Opacity(range);
  auto light = Directional(0.4, 0.3, -1, 1, 1, 1);
  const int resolution = smoke ? 24 : 128;

  vtkNew<vtkUnstructuredGridIllumination> twoLevel;
  twoLevel->SetInputData(grid);
  twoLevel->SetOpacityFunction(otf);
  twoLevel->SetScalarOpacityUnitDistance(unitDistance);
  twoLevel->SetLevel0Resolution(resolution, resolution, resolution);
  twoLevel->AddLight(light);
  double start = Now();
  twoLevel->Update();
  const double twoLevelSeconds = Now() - start;
  vtkNew<vtkUnstructuredGridIllumination> levelZero;
  levelZero->SetInputData(grid);
  levelZero->SetOpacityFunction(otf);
  levelZero->SetScalarOpacityUnitDistance(unitDistance);
  levelZero->SetLevel0Resolution(resolution, resolution, resolution);
  levelZero->SetLevel1Iterations(0);
  levelZero->AddLight(light);
  start = Now();
  levelZero->Update();
  const double level0Seconds = Now() - start;

  double times[3];
  start = Now();
  vtkNew<vtkResampleToImage> resample;
  resample->SetInputDataObject(grid);
  resample->SetSamplingDimensions(resolution, resolution, resolution);
  resample->Update();
  times[0] = Now() - start;
  vtkImageData* image = resample->GetOutput();
  image->GetPointData()->SetActiveScalars(grid->GetPointData()->GetScalars()->GetName());
  vtkNew<vtkMultiLightIlluminationVolume> propagation;
  propagation->SetInputData(image);
  propagation->SetOpacityFunction(otf);
  propagation->SetScalarOpacityUnitDistance(unitDistance);
  propagation->AddLight(light);
  start = Now();
  propagation->Update();
  times[1] = Now() - start;
  start = Now();
  vtkNew<vtkProbeFilter> probe;
  probe->SetInputData(grid);
  probe->SetSourceConnection(propagation->GetOutputPort());
  probe->Update();
  times[2] = Now() - start;
  const double resampleSeconds = times[0] + times[1] + times[2];

  std::vector<double> sigma(grid->GetNumberOfPoints());
  vtkDataArray* s = grid->GetPointData()->GetScalars();
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    const double a = std::min(otf->GetValue(s->GetTuple1(p)), 1.0 - 1e-6);
    sigma[p] = -std::log1p(-a) / unitDistance;
  }
  const auto reference = volillumtest::BruteForceTransmittance(
    grid, sigma, volillum::CaptureLight(light), (bounds[1] - bounds[0]) / (smoke ? 50 : 1000));
  const double twoLevelRms =
    VertexRms(twoLevel->GetOutput()->GetPointData()->GetArray("Illumination"), reference);
  const double level0Rms =
    VertexRms(levelZero->GetOutput()->GetPointData()->GetArray("Illumination"), reference);
  const double resampleRms =
    VertexRms(probe->GetOutput()->GetPointData()->GetArray("Illumination"), reference);
  std::printf("%28s %10s %12s\n", "method", "seconds", "RMS rel.");
  std::printf("%28s %10.3f %12.4f\n", "two-level", twoLevelSeconds, twoLevelRms);
  std::printf("%28s %10.3f %12.4f\n", "level 0 only", level0Seconds, level0Rms);
  std::printf("%28s %10.3f %12.4f\n", "resample + propagation", resampleSeconds, resampleRms);
  std::printf(
    "(resample %.3f s, propagation %.3f s, probe %.3f s)\n", times[0], times[1], times[2]);
  std::printf("time ratio resample/two-level %.2f, error ratio %.2f\n",
    resampleSeconds / twoLevelSeconds, resampleRms / twoLevelRms);
}
}

int main(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  const bool smoke = argc > 1 && std::string(argv[1]) == "--smoke";
  Scaling(smoke);
  const std::string path = std::string(VOLILLUM_SHARED_DATA) + "/tetmeshes/bluntfin_tets.vtu";
  if (!std::ifstream(path).good())
  {
    std::cout << "\n" << path << " not found: Table 2 and the comparison are skipped\n";
    return 0;
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  grid->GetPointData()->SetActiveScalars("Density");
  Table2(grid, smoke);
  AgainstResampling(grid, smoke);
  return 0;
}
