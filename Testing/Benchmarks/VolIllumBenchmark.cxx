// volillum-benchmark: performance of the illumination filters and of lit rendering, as
// ratios measured in one run. Prints tables and writes everything as JSON.
//
//   volillum-benchmark [--smoke] [--only rendering|multilight|filtered] [--engine FILE] [--json
//   FILE] [--peak multilight|filtered]
//
// rendering:  reference illumination time; frame time of the illuminated mapper, a plain GPU
//             ray-cast frame, one with Shade on and VTK's built-in volumetric shadows
//             (GlobalIlluminationReach 0.5, VolumetricScatteringBlending 1) on the same view at
//             512x512.
// filtered:   a transfer-function change with three orthodirectional lights: filtered
//             shadows against the reference and the multi-light propagation, filter
//             width 11 against 3, the share of building the tables, Gaussian against box.
// multilight: full-update time per voxel for the first and each added light (directional,
//             point, spot) on a 256^3 volume; peak memory per voxel of both filters (each
//             measured in a run of its own, --peak NAME); a replica of Table 1 of the
//             selective-light-updates paper (sequential and
//             coherent full updates, one-light state change, on/off), a replica of its
//             Fig. 10 (1..40 lights from one direction), the speed-up over the reference at
//             equal resolution and the memory throughput of a full update.
// --smoke uses tiny sizes so that CI only checks that the benchmark runs.
#include "VolIllumBenchmark.h"

#include "vtkIlluminationPhantomSource.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkSMPTools.h"
#include "vtkXMLImageDataReader.h"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

using namespace volillum_benchmark;

namespace
{
struct BenchmarkOptions
{
  bool Smoke = false;
  std::string Only;
  std::string Engine = VOLILLUM_SHARED_DATA "/volumes/engine.vti";
  std::string JsonPath = "volillum-benchmark.json";
  std::string Peak;
};

// The options, or false after printing the usage.
bool ParseOptions(int argc, char* argv[], BenchmarkOptions& o)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--smoke")
      o.Smoke = true;
    else if (a == "--only" && i + 1 < argc)
      o.Only = argv[++i];
    else if (a == "--engine" && i + 1 < argc)
      o.Engine = argv[++i];
    else if (a == "--json" && i + 1 < argc)
      o.JsonPath = argv[++i];
    else if (a == "--peak" && i + 1 < argc)
      o.Peak = argv[++i];
    else
    {
      std::cerr << "usage: volillum-benchmark [--smoke] [--only rendering|multilight|filtered] "
                   "[--engine FILE] [--json FILE] [--peak multilight|filtered]\n";
      return false;
    }
  }
  return true;
}

// The engine and the engine resampled to 256^3 (smaller with --smoke), or the CT phantom
// where the engine is missing; the first one only for a peak-memory run, whose peak the
// second would raise.
std::vector<Volume> LoadVolumes(const BenchmarkOptions& o)
{
  std::vector<Volume> volumes;
  vtkNew<vtkXMLImageDataReader> reader;
  if (reader->CanReadFile(o.Engine.c_str()))
  {
    reader->SetFileName(o.Engine.c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    volumes.push_back(MakeVolume("engine", o.Smoke ? Resize(image, 32, 32, 16) : image));
    if (o.Peak.empty())
    {
      volumes.push_back(MakeVolume(
        "engine-256^3", o.Smoke ? Resize(image, 24, 24, 24) : Resize(image, 256, 256, 256)));
    }
    return volumes;
  }
  std::cout << "engine volume not found at " << o.Engine << "; using the phantom only\n";
  vtkNew<vtkIlluminationPhantomSource> phantom;
  phantom->SetScene(vtkIlluminationPhantomSource::CTPhantom);
  const int n = o.Smoke ? 32 : 256;
  phantom->SetDimensions(n, n, n);
  phantom->Update();
  volumes.push_back(MakeVolume("ct-phantom-" + std::to_string(n), phantom->GetOutput()));
  return volumes;
}
}

int main(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  BenchmarkOptions o;
  if (!ParseOptions(argc, argv, o))
  {
    return 2;
  }
  const std::vector<Volume> volumes = LoadVolumes(o);
  if (!o.Peak.empty())
  {
    std::cout << PeakBytesPerVoxel(volumes.front(), o.Peak) << std::endl;
    return 0;
  }
  json results;
  results["smoke"] = o.Smoke;
  if (o.Only.empty() || o.Only == "multilight")
  {
    results["per_voxel"] = PerVoxel(volumes.back());
    results["peak_bytes_per_voxel"] = PeakMemory(argv[0], o.Engine, o.Smoke);
    results["table1"] = Table1(volumes, o.Smoke);
    results["fig10"] = Fig10(volumes.back(), o.Smoke);
    results["against_reference"] = AgainstReference(volumes.front(), 0.5);
  }
  if (o.Only.empty() || o.Only == "filtered")
  {
    results["filtered"] = FilteredShadowsSuite(volumes.front(), o.Smoke);
  }
  if (o.Only.empty() || o.Only == "rendering")
  {
    results["rendering"] = RenderingSuite(volumes, o.Smoke);
  }
  std::ofstream out(o.JsonPath);
  out << results.dump(2) << "\n";
  std::cout << "wrote " << o.JsonPath << std::endl;
  return out ? 0 : 1;
}
