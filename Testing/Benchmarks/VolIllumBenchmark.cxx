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
#include "IlluminationClassify.h"
#include "IlluminationFidelity.h"
#include "IlluminationLightList.h"
#include "RayMarchKernel.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkImageResize.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkSMPTools.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkXMLImageDataReader.h"

#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

using json = nlohmann::json;

namespace
{
struct Volume
{
  std::string Name;
  vtkSmartPointer<vtkImageData> Image;
  vtkSmartPointer<vtkColorTransferFunction> Color;
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
};

Volume MakeVolume(const std::string& name, vtkImageData* image)
{
  Volume v{ name, image, vtkSmartPointer<vtkColorTransferFunction>::New(),
    vtkSmartPointer<vtkPiecewiseFunction>::New() };
  double range[2];
  image->GetPointData()->GetScalars()->GetRange(range);
  const double w = range[1] - range[0];
  v.Color->AddRGBPoint(range[0], 0, 0, 0);
  v.Color->AddRGBPoint(range[0] + 0.3 * w, 0.8, 0.4, 0.3);
  v.Color->AddRGBPoint(range[1], 1.0, 0.95, 0.8);
  v.Opacity->AddPoint(range[0], 0);
  v.Opacity->AddPoint(range[0] + 0.2 * w, 0);
  v.Opacity->AddPoint(range[1], 0.5);
  return v;
}

vtkSmartPointer<vtkImageData> Resize(vtkImageData* image, int x, int y, int z)
{
  vtkNew<vtkImageResize> resize;
  resize->SetInputData(image);
  resize->SetOutputDimensions(x, y, z);
  resize->Update();
  return resize->GetOutput();
}

template <typename F>
double Seconds(F&& work)
{
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  work();
  timer->StopTimer();
  return timer->GetElapsedTime();
}

void Configure(vtkIlluminationVolumeAlgorithm* filter, const Volume& v, double scale)
{
  filter->SetInputData(v.Image);
  filter->SetColorTransferFunction(v.Color);
  filter->SetOpacityFunction(v.Opacity);
  filter->SetResolutionScale(scale);
}

// The lights of Fig. 9: two directional lights from above, slightly from the left, and a
// point light above and to the left, all outside the volume. All three travel mostly down
// (-z, their closest propagation group) and then toward +x (the second closest), so they
// share both of their propagation groups.
std::vector<vtkSmartPointer<vtkLight>> Fig9Lights(int count, const double b[6])
{
  const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  const double size = std::max(b[1] - b[0], std::max(b[3] - b[2], b[5] - b[4]));
  std::vector<vtkSmartPointer<vtkLight>> lights;
  auto directional = [&](double dx, double dy, double dz, double r, double g, double bl)
  {
    auto l = vtkSmartPointer<vtkLight>::New();
    l->SetPositional(false);
    l->SetPosition(c[0] - dx, c[1] - dy, c[2] - dz);
    l->SetFocalPoint(c);
    l->SetDiffuseColor(r, g, bl);
    lights.push_back(l);
  };
  directional(0.3, -0.2, -1.0, 1.0, 1.0, 1.0);
  directional(0.2, 0.1, -1.0, 1.0, 1.0, 1.0);
  if (count > 2)
  {
    auto point = vtkSmartPointer<vtkLight>::New();
    point->SetPositional(true);
    point->SetConeAngle(180);
    point->SetPosition(c[0] - 0.5 * size, c[1] + 0.1 * size, c[2] + 1.5 * size);
    point->SetDiffuseColor(1.0, 0.9, 0.2);
    lights.push_back(point);
  }
  return lights;
}

int Passes(vtkImageAlgorithm* f)
{
  return static_cast<int>(
    f->GetOutput()->GetFieldData()->GetArray("PropagationPasses")->GetTuple1(0));
}

int Mode(vtkImageAlgorithm* f)
{
  return static_cast<int>(f->GetOutput()->GetFieldData()->GetArray("UpdateMode")->GetTuple1(0));
}

// Seconds of a full update of the lights, coherent or one light per pass.
double FullUpdate(const Volume& v, double scale,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, bool coherent, int* passes = nullptr,
  vtkSmartPointer<vtkMultiLightIlluminationVolume>* updated = nullptr)
{
  auto filter = vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
  Configure(filter, v, scale);
  filter->SetCoherentPropagation(coherent);
  filter->SetSelectiveUpdates(false);
  filter->Update(); // classification only: no lights yet
  for (const auto& l : lights)
  {
    filter->AddLight(l);
  }
  const double s = Seconds([&] { filter->Update(); });
  if (passes)
  {
    *passes = Passes(filter);
  }
  if (updated)
  {
    *updated = filter;
  }
  return s;
}

// Seconds of selective updates of light 0: a state change (it moves: its old state is
// removed and the new one added), a colour change (the same rays, so one propagation) and
// switching it off.
void SelectiveUpdates(
  const Volume& v, double scale, const std::vector<vtkSmartPointer<vtkLight>>& lights, json& row)
{
  vtkNew<vtkMultiLightIlluminationVolume> filter;
  Configure(filter, v, scale);
  for (const auto& l : lights)
  {
    filter->AddLight(l);
  }
  filter->Update();
  double position[3], color[3], bounds[6];
  v.Image->GetBounds(bounds);
  lights[0]->GetPosition(position);
  lights[0]->GetDiffuseColor(color);
  auto measure = [&](const char* name)
  {
    row[std::string(name) + "_s"] = Seconds([&] { filter->Update(); });
    row[std::string(name) + "_mode"] = Mode(filter);
    row[std::string(name) + "_passes"] = Passes(filter);
  };
  lights[0]->SetPosition(position[0] + 0.05 * (bounds[1] - bounds[0]), position[1], position[2]);
  measure("state_change");
  lights[0]->SetDiffuseColor(color[0], 0.5 * color[1], color[2]);
  measure("color_change");
  lights[0]->SwitchOff();
  measure("on_off");
  lights[0]->SwitchOn();
  lights[0]->SetDiffuseColor(color);
  lights[0]->SetPosition(position);
}

json Table1(const std::vector<Volume>& volumes, bool smoke)
{
  json rows = json::array();
  std::cout << "\nTable 1 replica (seconds; ratios)\n"
            << std::left << std::setw(20) << "volume" << std::setw(8) << "lights" << std::setw(7)
            << "scale" << std::right << std::setw(11) << "sequential" << std::setw(10) << "coherent"
            << std::setw(10) << "seq/coh" << std::setw(10) << "state" << std::setw(11)
            << "seq/state" << std::setw(10) << "on/off" << std::setw(13) << "state/onoff"
            << "\n";
  for (const auto& v : volumes)
  {
    double bounds[6];
    v.Image->GetBounds(bounds);
    for (int count : { 2, 3 })
    {
      for (double scale : { 1.0, 0.25 })
      {
        auto lights = Fig9Lights(count, bounds);
        json row;
        row["volume"] = v.Name;
        row["lights"] = count;
        row["scale"] = scale;
        int seqPasses = 0, cohPasses = 0;
        const double sequential = FullUpdate(v, scale, lights, false, &seqPasses);
        const double coherent = FullUpdate(v, scale, lights, true, &cohPasses);
        row["sequential_full_s"] = sequential;
        row["sequential_passes"] = seqPasses;
        row["coherent_full_s"] = coherent;
        row["coherent_passes"] = cohPasses;
        SelectiveUpdates(v, scale, lights, row);
        row["coherent_speedup"] = sequential / coherent;
        row["state_change_speedup"] = sequential / row["state_change_s"].get<double>();
        row["on_off_vs_state_change"] =
          row["state_change_s"].get<double>() / row["on_off_s"].get<double>();
        std::cout << std::left << std::setw(20) << v.Name << std::setw(8) << count << std::setw(7)
                  << scale << std::right << std::fixed << std::setprecision(3) << std::setw(11)
                  << sequential << std::setw(10) << coherent << std::setw(10)
                  << row["coherent_speedup"].get<double>() << std::setw(10)
                  << row["state_change_s"].get<double>() << std::setw(11)
                  << row["state_change_speedup"].get<double>() << std::setw(10)
                  << row["on_off_s"].get<double>() << std::setw(13)
                  << row["on_off_vs_state_change"].get<double>() << "\n"
                  << std::defaultfloat;
        rows.push_back(row);
      }
    }
  }
  (void)smoke;
  return rows;
}

// Least-squares slope of y over x.
double Slope(const std::vector<double>& x, const std::vector<double>& y)
{
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i)
  {
    mx += x[i] / x.size();
    my += y[i] / y.size();
  }
  double num = 0, den = 0;
  for (size_t i = 0; i < x.size(); ++i)
  {
    num += (x[i] - mx) * (y[i] - my);
    den += (x[i] - mx) * (x[i] - mx);
  }
  return num / den;
}

json Fig10(const Volume& v, bool smoke)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  const std::vector<int> counts =
    smoke ? std::vector<int>{ 1, 2, 4 } : std::vector<int>{ 1, 2, 5, 10, 20, 40 };
  json result;
  std::vector<double> x, coherent, sequential;
  std::vector<vtkSmartPointer<vtkLight>> lights;
  std::cout << "\nFig. 10 replica: lights from one direction (" << v.Name << ")\n"
            << std::setw(8) << "lights" << std::setw(14) << "coherent [s]" << std::setw(16)
            << "sequential [s]" << std::setw(16) << "state change [s]"
            << "\n";
  json rows = json::array();
  for (int n : counts)
  {
    while (static_cast<int>(lights.size()) < n)
    {
      auto l = vtkSmartPointer<vtkLight>::New();
      l->SetPositional(false);
      l->SetPosition(0.2, -0.1, 1.0);
      l->SetFocalPoint(0, 0, 0);
      const double hue = static_cast<double>(lights.size()) / 40.0;
      l->SetDiffuseColor(1.0 - hue, 0.5, hue);
      l->SetIntensity(1.0 / 40.0);
      lights.push_back(l);
    }
    const double c = FullUpdate(v, 1.0, lights, true);
    const double s = FullUpdate(v, 1.0, lights, false);
    json row;
    SelectiveUpdates(v, 1.0, lights, row);
    row["lights"] = n;
    row["coherent_full_s"] = c;
    row["sequential_full_s"] = s;
    row["state_change_speedup_over_sequential"] = s / row["state_change_s"].get<double>();
    std::cout << std::setw(8) << n << std::setw(14) << c << std::setw(16) << s << std::setw(16)
              << row["state_change_s"].get<double>() << "\n";
    rows.push_back(row);
    x.push_back(n);
    coherent.push_back(c);
    sequential.push_back(s);
  }
  result["rows"] = rows;
  result["coherent_seconds_per_light"] = Slope(x, coherent);
  result["sequential_seconds_per_light"] = Slope(x, sequential);
  result["coherent_over_sequential_per_light"] = Slope(x, coherent) / Slope(x, sequential);
  const double changeFew = rows.front()["state_change_s"].get<double>();
  const double changeMany = rows.back()["state_change_s"].get<double>();
  const int few = rows.size() > 1 ? 1 : 0;
  result["state_change_many_over_two"] = changeMany / rows[few]["state_change_s"].get<double>();
  (void)changeFew;
  std::cout << "cost per added light: coherent " << Slope(x, coherent) << " s, sequential "
            << Slope(x, sequential) << " s, ratio "
            << result["coherent_over_sequential_per_light"].get<double>() << "\n"
            << "one-light state change with " << counts.back() << " lights / with " << counts[few]
            << ": " << result["state_change_many_over_two"].get<double>() << "\n";
  return result;
}

// Oblique lights of one kind from `count` distinct directions around the volume.
std::vector<vtkSmartPointer<vtkLight>> ObliqueLights(
  const std::string& kind, int count, const double b[6])
{
  const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  const double size = std::max(b[1] - b[0], std::max(b[3] - b[2], b[5] - b[4]));
  std::vector<vtkSmartPointer<vtkLight>> lights;
  for (int i = 0; i < count; ++i)
  {
    const double angle = 0.7 + 1.3 * i;
    auto l = vtkSmartPointer<vtkLight>::New();
    l->SetPositional(kind != "directional");
    l->SetConeAngle(kind == "spot" ? 30.0 : 180.0);
    l->SetPosition(c[0] + 1.5 * size * std::cos(angle), c[1] + 1.5 * size * std::sin(angle),
      c[2] + (1.0 + 0.15 * i) * size);
    l->SetFocalPoint(c);
    lights.push_back(l);
  }
  return lights;
}

// Wall time per illumination point of a full update: the first light, and each further
// light from a direction of its own (1 and 4 lights), for each kind of light.
json PerVoxel(const Volume& v)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  const double points = static_cast<double>(v.Image->GetNumberOfPoints());
  std::cout << "\nFull update, " << v.Name << " at scale 1, oblique lights (ns per voxel)\n"
            << std::left << std::setw(14) << "light" << std::right << std::setw(14) << "first light"
            << std::setw(14) << "each added"
            << "\n";
  json rows = json::array();
  for (const std::string kind : { "directional", "point", "spot" })
  {
    const double one = FullUpdate(v, 1.0, ObliqueLights(kind, 1, bounds), true);
    const double four = FullUpdate(v, 1.0, ObliqueLights(kind, 4, bounds), true);
    json r;
    r["light"] = kind;
    r["first_light_ns_per_voxel"] = 1e9 * one / points;
    r["added_light_ns_per_voxel"] = 1e9 * (four - one) / 3.0 / points;
    std::cout << std::left << std::setw(14) << kind << std::right << std::setw(14)
              << r["first_light_ns_per_voxel"].get<double>() << std::setw(14)
              << r["added_light_ns_per_voxel"].get<double>() << "\n";
    rows.push_back(r);
  }
  return rows;
}

// Peak resident memory of one update of a filter at scale 1 with one light, in bytes per
// illumination point above what the process held before it (the input included). Run in a
// process of its own (--peak), as the peak only grows within one.
double PeakBytesPerVoxel(const Volume& v, const std::string& filterName)
{
  vtkSmartPointer<vtkIlluminationVolumeAlgorithm> filter;
  if (filterName == "filtered")
  {
    filter = vtkSmartPointer<vtkFilteredVolumetricShadows>::New();
  }
  else
  {
    filter = vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
  }
  Configure(filter, v, 1.0);
  double bounds[6];
  v.Image->GetBounds(bounds);
  filter->AddLight(ObliqueLights("directional", 1, bounds).front());
  // Resident now (not the peak so far, which reading the input may have raised).
  long long pages = 0, resident = 0;
  if (std::FILE* statm = std::fopen("/proc/self/statm", "r"))
  {
    if (std::fscanf(statm, "%lld %lld", &pages, &resident) != 2)
    {
      resident = 0;
    }
    std::fclose(statm);
  }
  const double before = static_cast<double>(resident) * static_cast<double>(getpagesize());
  filter->Update();
  rusage after;
  getrusage(RUSAGE_SELF, &after);
  return (1024.0 * static_cast<double>(after.ru_maxrss) - before) /
    static_cast<double>(filter->GetOutput()->GetNumberOfPoints());
}

// Peak bytes per voxel of both filters, each measured by this program run again (--peak).
json PeakMemory(const std::string& self, const std::string& engine, bool smoke)
{
  json r;
  std::cout << "\nPeak memory of an update at scale 1 (bytes per voxel above the input)\n";
  for (const std::string name : { "multilight", "filtered" })
  {
    const std::string command =
      "'" + self + "' --peak " + name + " --engine '" + engine + "'" + (smoke ? " --smoke" : "");
    double value = -1.0;
    if (FILE* pipe = popen(command.c_str(), "r"))
    {
      if (std::fscanf(pipe, "%lf", &value) != 1)
      {
        value = -1.0;
      }
      pclose(pipe);
    }
    r[name] = value;
    std::cout << std::left << std::setw(14) << name << std::right << std::setw(10) << value << "\n";
  }
  return r;
}

// Seconds of an update after a transfer-function change (the tables are rebuilt).
double AfterTransferFunctionChange(vtkIlluminationVolumeAlgorithm* filter, const Volume& v)
{
  double range[2];
  v.Image->GetPointData()->GetScalars()->GetRange(range);
  const double s = range[0] + 0.6 * (range[1] - range[0]);
  const int id = v.Opacity->AddPoint(s, v.Opacity->GetValue(s) * 1.01);
  const double seconds = Seconds([&] { filter->Update(); });
  v.Opacity->RemovePoint(s);
  (void)id;
  return seconds;
}

// Filtered shadows with three orthodirectional lights after a transfer-function change,
// against the reference (single scattering) and the multi-light propagation on the same
// lights, at the same output resolution.
json FilteredShadows(const Volume& v, double scale, bool large)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  std::vector<vtkSmartPointer<vtkLight>> lights;
  for (const auto& travel : { std::array<double, 3>{ 0, 0, -1 }, std::array<double, 3>{ 1, 0, 0 },
         std::array<double, 3>{ 0, -1, 0 } })
  {
    auto l = vtkSmartPointer<vtkLight>::New();
    l->SetPositional(false);
    l->SetPosition(0, 0, 0);
    l->SetFocalPoint(travel.data());
    lights.push_back(l);
  }
  auto filtered = [&](double width, int kernel)
  {
    vtkNew<vtkFilteredVolumetricShadows> f;
    Configure(f, v, scale);
    f->SetFilterWidth(width);
    f->SetFilterKernel(kernel);
    for (const auto& l : lights)
    {
      f->AddLight(l);
    }
    f->Update();
    json r;
    r["tf_change_s"] = AfterTransferFunctionChange(f, v);
    r["tables_built"] = Passes(f);
    lights[0]->SetDiffuseColor(1.0, 0.9, 0.8);
    r["color_change_s"] = Seconds([&] { f->Update(); });
    lights[0]->SetDiffuseColor(1.0, 1.0, 1.0);
    return r;
  };
  json r;
  r["volume"] = v.Name;
  r["scale"] = scale;
  const json box3 = filtered(3, vtkFilteredVolumetricShadows::Box);
  const json box11 = filtered(11, vtkFilteredVolumetricShadows::Box);
  // The Gaussian reads 25 cuboids a light and point: timed on the smaller volume only.
  const json gauss3 = large ? json() : filtered(3, vtkFilteredVolumetricShadows::Gaussian);
  const double t3 = box3["tf_change_s"].get<double>();
  r["filtered_width3_s"] = t3;
  r["filtered_width11_s"] = box11["tf_change_s"].get<double>();
  r["tables_built"] = box3["tables_built"];
  r["width11_over_width3"] = box11["tf_change_s"].get<double>() / t3;
  r["table_build_share"] = 1.0 - box3["color_change_s"].get<double>() / t3;
  r["gaussian_over_box"] = large ? 0.0 : gauss3["tf_change_s"].get<double>() / t3;

  vtkNew<vtkMultiLightIlluminationVolume> propagation;
  Configure(propagation, v, scale);
  for (const auto& l : lights)
  {
    propagation->AddLight(l);
  }
  propagation->Update();
  r["propagation_s"] = AfterTransferFunctionChange(propagation, v);
  r["propagation_over_filtered"] = r["propagation_s"].get<double>() / t3;

  // The reference marches every point to every light; where that would take too long it
  // is timed on a few slices of the output grid and scaled to the whole grid (its cost is
  // proportional to the number of points).
  vtkNew<vtkRayMarchedIllumination> reference;
  Configure(reference, v, scale);
  for (const auto& l : lights)
  {
    reference->AddLight(l);
  }
  double referenceSeconds = 0.0;
  if (!large)
  {
    reference->Update();
    referenceSeconds = AfterTransferFunctionChange(reference, v);
  }
  else
  {
    volillum::ClassificationSettings settings;
    settings.Color = v.Color;
    settings.Opacity = v.Opacity;
    volillum::GridGeometry data;
    int dims[3];
    v.Image->GetDimensions(dims);
    double spacing[3], origin[3];
    v.Image->GetSpacing(spacing);
    v.Image->GetOrigin(origin);
    for (int a = 0; a < 3; ++a)
    {
      data.Dimensions[a] = dims[a];
      data.Spacing[a] = spacing[a];
      data.Origin[a] = origin[a];
    }
    volillum::ClassifiedVolume classified;
    std::string error;
    const double classifySeconds = Seconds(
      [&] {
        volillum::Classify(
          v.Image->GetPointData()->GetScalars(), data, settings, classified, error);
      });
    volillum::GridGeometry full = volillum::ScaledGeometry(data, scale);
    volillum::GridGeometry part = full;
    part.Dimensions[2] = 4;
    part.Origin[2] = full.Origin[2] + 0.5 * full.Dimensions[2] * full.Spacing[2];
    std::vector<float> rgb(3 * static_cast<size_t>(part.NumberOfPoints()));
    std::vector<volillum::LightState> states;
    for (const auto& l : lights)
    {
      states.push_back(volillum::CaptureLight(l));
    }
    const double partSeconds = Seconds(
      [&]
      {
        volillum::RayMarchIllumination(
          classified, states, part, volillum::RayMarchSettings(), rgb.data(), nullptr);
      });
    referenceSeconds = classifySeconds + partSeconds * full.Dimensions[2] / part.Dimensions[2];
    r["reference_extrapolated_from_slices"] = part.Dimensions[2];
  }
  r["reference_s"] = referenceSeconds;
  r["filtered_speedup_over_reference"] = referenceSeconds / t3;
  std::cout << std::left << std::setw(16) << v.Name << std::setw(7) << scale << std::right
            << std::setw(12) << referenceSeconds << std::setw(11) << t3 << std::setw(11)
            << r["filtered_speedup_over_reference"].get<double>() << std::setw(10)
            << r["width11_over_width3"].get<double>() << std::setw(12)
            << r["table_build_share"].get<double>() << std::setw(12)
            << r["gaussian_over_box"].get<double>() << std::setw(12)
            << r["propagation_over_filtered"].get<double>() << "\n";
  return r;
}

// Speed-up over the reference at equal resolution, and bandwidth use of a full update.
json AgainstReference(const Volume& v, double scale)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  auto lights = Fig9Lights(3, bounds);
  vtkNew<vtkRayMarchedIllumination> reference;
  Configure(reference, v, scale);
  for (const auto& l : lights)
  {
    reference->AddLight(l);
  }
  const double referenceSeconds = Seconds([&] { reference->Update(); });
  int passes = 0;
  vtkSmartPointer<vtkMultiLightIlluminationVolume> propagated;
  const double propagation = FullUpdate(v, scale, lights, true, &passes, &propagated);
  // Fidelity where there is material, and over the whole volume.
  auto* got =
    vtkFloatArray::SafeDownCast(propagated->GetOutput()->GetPointData()->GetArray("Illumination"));
  auto* exact =
    vtkFloatArray::SafeDownCast(reference->GetOutput()->GetPointData()->GetArray("Illumination"));
  const double materialRms = volillumfidelity::MaterialRms(propagated, got, exact);
  const double wholeRms = volillumtest::RmsRelative(got, exact);

  // A sweep reads the classified grid (4 bytes a point, extinction only) and reads and
  // writes the fixed-point illumination (2 x 12 bytes); the conversion to float reads 12 and
  // writes 12.
  const double points = static_cast<double>(reference->GetOutput()->GetNumberOfPoints());
  const double bytes = points * (passes * (4.0 + 24.0) + 24.0);
  const size_t copyBytes = 256u << 20;
  std::vector<char> from(copyBytes, 1), to(copyBytes, 0);
  const double copySeconds = Seconds(
    [&]
    {
      for (int i = 0; i < 4; ++i)
      {
        std::memcpy(to.data(), from.data(), copyBytes);
        from[i] = to[copyBytes - 1 - i];
      }
    });
  const double copyBandwidth = 4.0 * 2.0 * copyBytes / copySeconds; // read + write
  json r;
  r["volume"] = v.Name;
  r["scale"] = scale;
  r["reference_s"] = referenceSeconds;
  r["propagation_s"] = propagation;
  r["speedup"] = referenceSeconds / propagation;
  r["material_rms"] = materialRms;
  r["whole_volume_rms"] = wholeRms;
  r["full_update_bandwidth_GBps"] = bytes / propagation / 1e9;
  r["memcpy_bandwidth_GBps"] = copyBandwidth / 1e9;
  r["bandwidth_fraction"] = (bytes / propagation) / copyBandwidth;
  std::cout << "\nreference vs propagation (" << v.Name << ", scale " << scale
            << "): " << referenceSeconds << " s vs " << propagation << " s, speed-up "
            << r["speedup"].get<double>() << "; relative RMS over material " << 100.0 * materialRms
            << " % (whole volume " << 100.0 * wholeRms << " %)\nfull update moves "
            << r["full_update_bandwidth_GBps"].get<double>() << " GB/s, "
            << 100.0 * r["bandwidth_fraction"].get<double>() << "% of memcpy's "
            << r["memcpy_bandwidth_GBps"].get<double>() << " GB/s\n";
  return r;
}

void AddLights(vtkRayMarchedIllumination* filter, const double b[6])
{
  for (const auto& l : Fig9Lights(3, b))
  {
    filter->AddLight(l);
  }
}

// Mean seconds per frame over a few frames after one warm-up frame (shader build, upload).
double TimeFrames(vtkRenderWindow* window, int frames)
{
  window->Render();
  return Seconds(
           [&]
           {
             for (int i = 0; i < frames; ++i)
             {
               window->GetRenderers()->GetFirstRenderer()->GetActiveCamera()->Azimuth(1.0);
               window->Render();
             }
           }) /
    frames;
}

json Rendering(const Volume& v, bool smoke)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  vtkNew<vtkRayMarchedIllumination> reference;
  Configure(reference, v, 0.5);
  AddLights(reference, bounds);
  const double referenceSeconds = Seconds([&] { reference->Update(); });

  const int size = smoke ? 64 : 512;
  const int frames = smoke ? 1 : 3;
  auto frame = [&](vtkOpenGLGPUVolumeRayCastMapper* mapper, bool shade)
  {
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(v.Color);
    property->SetScalarOpacity(v.Opacity);
    property->SetInterpolationTypeToLinear();
    property->SetShade(shade);
    vtkNew<vtkVolume> volume;
    mapper->SetInputData(v.Image);
    volume->SetMapper(mapper);
    volume->SetProperty(property);
    vtkNew<vtkRenderer> renderer;
    renderer->AddVolume(volume);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Azimuth(30);
    renderer->GetActiveCamera()->Elevation(20);
    renderer->ResetCamera();
    vtkNew<vtkRenderWindow> window;
    window->SetOffScreenRendering(1);
    window->SetSize(size, size);
    window->AddRenderer(renderer);
    return TimeFrames(window, frames);
  };
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> plain;
  const double plainFrame = frame(plain, false);
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> shaded;
  const double shadedFrame = frame(shaded, true);
  vtkNew<vtkIlluminatedVolumeMapper> lit;
  lit->SetIlluminationData(reference->GetOutput());
  const double litFrame = frame(lit, false);
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> shadows;
  shadows->SetGlobalIlluminationReach(0.5f);
  shadows->SetVolumetricScatteringBlending(1.0f);
  const double shadowFrame = frame(shadows, true);

  int dims[3];
  v.Image->GetDimensions(dims);
  json r;
  r["volume"] = v.Name;
  r["dimensions"] = { dims[0], dims[1], dims[2] };
  r["image_size"] = size;
  r["reference_resolution_scale"] = 0.5;
  r["reference_seconds"] = referenceSeconds;
  r["lit_over_plain_frame"] = litFrame / plainFrame;
  r["lit_over_shaded_frame"] = litFrame / shadedFrame;
  r["builtin_shadows_over_plain_frame"] = shadowFrame / plainFrame;
  r["builtin_shadows_over_lit_frame"] = shadowFrame / litFrame;
  std::cout << std::left << std::setw(20) << v.Name << std::right << std::setw(16)
            << referenceSeconds << std::setw(14) << litFrame / plainFrame << std::setw(14)
            << litFrame / shadedFrame << std::setw(16) << shadowFrame / plainFrame << std::setw(14)
            << shadowFrame / litFrame << "\n";
  return r;
}
}

int main(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  bool smoke = false;
  std::string only;
  std::string engine = VOLILLUM_SHARED_DATA "/volumes/engine.vti";
  std::string jsonPath = "volillum-benchmark.json";
  std::string peak;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--smoke")
      smoke = true;
    else if (a == "--only" && i + 1 < argc)
      only = argv[++i];
    else if (a == "--engine" && i + 1 < argc)
      engine = argv[++i];
    else if (a == "--json" && i + 1 < argc)
      jsonPath = argv[++i];
    else if (a == "--peak" && i + 1 < argc)
      peak = argv[++i];
    else
    {
      std::cerr << "usage: volillum-benchmark [--smoke] [--only rendering|multilight|filtered] "
                   "[--engine FILE] [--json FILE] [--peak multilight|filtered]\n";
      return 2;
    }
  }

  std::vector<Volume> volumes;
  vtkNew<vtkXMLImageDataReader> reader;
  if (reader->CanReadFile(engine.c_str()))
  {
    reader->SetFileName(engine.c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    if (!peak.empty())
    {
      std::cout << PeakBytesPerVoxel(
                     MakeVolume("engine", smoke ? Resize(image, 32, 32, 16) : image), peak)
                << std::endl;
      return 0;
    }
    volumes.push_back(MakeVolume("engine", smoke ? Resize(image, 32, 32, 16) : image));
    volumes.push_back(
      MakeVolume("engine-256^3", smoke ? Resize(image, 24, 24, 24) : Resize(image, 256, 256, 256)));
  }
  else
  {
    std::cout << "engine volume not found at " << engine << "; using the phantom only\n";
    vtkNew<vtkIlluminationPhantomSource> phantom;
    phantom->SetScene(vtkIlluminationPhantomSource::CTPhantom);
    const int n = smoke ? 32 : 256;
    phantom->SetDimensions(n, n, n);
    phantom->Update();
    volumes.push_back(MakeVolume("ct-phantom-" + std::to_string(n), phantom->GetOutput()));
  }

  if (!peak.empty())
  {
    std::cout << PeakBytesPerVoxel(volumes.front(), peak) << std::endl;
    return 0;
  }
  json results;
  results["smoke"] = smoke;
  if (only.empty() || only == "multilight")
  {
    results["per_voxel"] = PerVoxel(volumes.back());
    results["peak_bytes_per_voxel"] = PeakMemory(argv[0], engine, smoke);
    results["table1"] = Table1(volumes, smoke);
    results["fig10"] = Fig10(volumes.back(), smoke);
    results["against_reference"] = AgainstReference(volumes.front(), 0.5);
  }
  if (only.empty() || only == "filtered")
  {
    std::cout << "\nFiltered shadows after a transfer-function change, 3 orthodirectional lights\n"
              << std::left << std::setw(16) << "volume" << std::setw(7) << "scale" << std::right
              << std::setw(12) << "ref [s]" << std::setw(11) << "filt [s]" << std::setw(11)
              << "ref/filt" << std::setw(10) << "w11/w3" << std::setw(12) << "table share"
              << std::setw(12) << "gauss/box" << std::setw(12) << "prop/filt"
              << "\n";
    json rows = json::array();
    rows.push_back(FilteredShadows(volumes.front(), 0.5, false));
    if (!smoke && volumes.front().Name == "engine")
    {
      rows.push_back(FilteredShadows(
        MakeVolume("engine-512^3", Resize(volumes.front().Image, 512, 512, 512)), 0.5, true));
    }
    results["filtered"] = rows;
  }
  if (only.empty() || only == "rendering")
  {
    std::cout << "\nRendering (" << (smoke ? 64 : 512) << " pixels square; ratios of frame times)\n"
              << std::left << std::setw(20) << "volume" << std::right << std::setw(16)
              << "reference [s]" << std::setw(14) << "lit/plain" << std::setw(14) << "lit/shaded"
              << std::setw(16) << "shadows/plain" << std::setw(14) << "shadows/lit"
              << "\n";
    json rows = json::array();
    for (const auto& v : volumes)
    {
      rows.push_back(Rendering(v, smoke));
    }
    results["rendering"] = rows;
  }
  std::ofstream out(jsonPath);
  out << results.dump(2) << "\n";
  std::cout << "wrote " << jsonPath << std::endl;
  return out ? 0 : 1;
}
