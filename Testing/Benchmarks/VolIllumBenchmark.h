// Shared by the suites of volillum-benchmark (VolIllumBenchmark.cxx has main and the
// options): the volumes, timing, the filters' set-up and the suites.
#ifndef VolIllumBenchmark_h
#define VolIllumBenchmark_h

#include "vtkColorTransferFunction.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"

#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <string>
#include <vector>

class vtkIlluminationVolumeAlgorithm;
class vtkImageAlgorithm;
class vtkRenderWindow;

namespace volillum_benchmark
{
using json = nlohmann::json;

/// A volume with its transfer functions.
struct Volume
{
  std::string Name;
  vtkSmartPointer<vtkImageData> Image;
  vtkSmartPointer<vtkColorTransferFunction> Color;
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
};

/// The volume with transfer functions over its scalar range (opacity from 20 % of it).
Volume MakeVolume(const std::string& name, vtkImageData* image);
/// The image resampled to x x y x z points.
vtkSmartPointer<vtkImageData> Resize(vtkImageData* image, int x, int y, int z);
/// Wall seconds of work().
template <typename F>
double Seconds(F&& work)
{
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  work();
  timer->StopTimer();
  return timer->GetElapsedTime();
}
/// Set a filter's input, transfer functions and resolution scale.
void Configure(vtkIlluminationVolumeAlgorithm* filter, const Volume& v, double scale);
/// The lights of Fig. 9 of the selective-light-updates paper (count 2 or 3).
std::vector<vtkSmartPointer<vtkLight>> Fig9Lights(int count, const double b[6]);
/// PropagationPasses and UpdateMode of a filter's last update.
int Passes(vtkImageAlgorithm* f);
int Mode(vtkImageAlgorithm* f);
/// Seconds of an update after a small opacity change (the tables and volume are rebuilt).
double AfterTransferFunctionChange(vtkIlluminationVolumeAlgorithm* filter, const Volume& v);

/// Suites (BenchmarkMultiLight.cxx): ns per voxel per light, peak memory per voxel (each
/// filter in a process of its own), Table 1 and Fig. 10 of the selective-light-updates paper,
/// the speed-up over the reference.
json PerVoxel(const Volume& v);
double PeakBytesPerVoxel(const Volume& v, const std::string& filterName);
json PeakMemory(const std::string& self, const std::string& engine, bool smoke);
json Table1(const std::vector<Volume>& volumes, bool smoke);
json Fig10(const Volume& v, bool smoke);
json AgainstReference(const Volume& v, double scale);
/// Filtered shadows after a transfer-function change (BenchmarkFilteredShadows.cxx): the
/// volume at scale 1/2, and the engine resampled to 512^3 (not with --smoke).
json FilteredShadows(const Volume& v, double scale, bool large);
json FilteredShadowsSuite(const Volume& v, bool smoke);
/// Frame-time ratios of lit rendering (BenchmarkRendering.cxx), per volume, in window.
json Rendering(const Volume& v, bool smoke, vtkRenderWindow* window);
json RenderingSuite(const std::vector<Volume>& volumes, bool smoke);
}

#endif
