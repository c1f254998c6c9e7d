// volillum-benchmark: the multi-light suite (per-voxel cost, peak memory, Table 1, Fig. 10, against
// the reference).
#include "VolIllumBenchmark.h"

#include "IlluminationFidelity.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkPointData.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkLight.h"
#include "vtkNew.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

namespace volillum_benchmark
{

namespace
{
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

// Moves the light by 5 % of the volume's extent along x (Table 1's state change); returns
// where it was.
std::array<double, 3> MoveAside(const Volume& v, vtkLight* light)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  std::array<double, 3> position;
  light->GetPosition(position.data());
  light->SetPosition(position[0] + 0.05 * (bounds[1] - bounds[0]), position[1], position[2]);
  return position;
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
  double color[3];
  lights[0]->GetDiffuseColor(color);
  auto measure = [&](const char* name)
  {
    row[std::string(name) + "_s"] = Seconds([&] { filter->Update(); });
    row[std::string(name) + "_mode"] = Mode(filter);
    row[std::string(name) + "_passes"] = Passes(filter);
  };
  const auto position = MoveAside(v, lights[0]);
  measure("state_change");
  lights[0]->SetDiffuseColor(color[0], 0.5 * color[1], color[2]);
  measure("color_change");
  lights[0]->SwitchOff();
  measure("on_off");
  lights[0]->SwitchOn();
  lights[0]->SetDiffuseColor(color);
  lights[0]->SetPosition(position.data());
}

// Light 0's state change of SelectiveUpdates on a filter fresh from a full update of the
// lights, as the filter chooses (0), forced selective (1: ChangedLightFraction, as one light
// of two or three changes) or forced full (2): the least seconds of three runs (runs vary by
// up to 30 % here); the chosen filter's estimates of both updates, in seconds (estimates,
// when given).
double StateChange(const Volume& v, double scale,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, int how, double* estimates = nullptr)
{
  double least = 0.0;
  for (int run = 0; run < 3; ++run)
  {
    vtkNew<vtkMultiLightIlluminationVolume> filter;
    Configure(filter, v, scale);
    if (how == 1)
    {
      filter->SetCostEstimate(vtkMultiLightIlluminationVolume::ChangedLightFraction);
    }
    for (const auto& l : lights)
    {
      filter->AddLight(l);
    }
    filter->Update();
    const auto position = MoveAside(v, lights[0]);
    filter->SetSelectiveUpdates(how != 2);
    const double seconds = Seconds([&] { filter->Update(); });
    lights[0]->SetPosition(position.data());
    least = run == 0 ? seconds : std::min(least, seconds);
    if (estimates)
    {
      const double points = static_cast<double>(filter->GetOutput()->GetNumberOfPoints());
      estimates[0] = 1e-9 * points * filter->GetLastSelectiveCost();
      estimates[1] = 1e-9 * points * filter->GetLastFullCost();
    }
  }
  return least;
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
  // The state change's choice against both updates, and the cost model's estimates.
  std::cout << "\nOne-light state change: selective and full update against the chosen "
               "(least seconds of three runs; estimates of the propagation alone from "
               "PropagationCost)\n"
            << std::left << std::setw(20) << "volume" << std::setw(8) << "lights" << std::setw(7)
            << "scale" << std::right << std::setw(11) << "selective" << std::setw(10) << "full"
            << std::setw(10) << "chosen" << std::setw(6) << "mode" << std::setw(16)
            << "chosen/cheaper" << std::setw(12) << "est. sel." << std::setw(12) << "est. full"
            << "\n";
  for (auto& row : rows)
  {
    const Volume& v = *std::find_if(volumes.begin(), volumes.end(),
      [&](const Volume& candidate) { return candidate.Name == row["volume"].get<std::string>(); });
    double bounds[6];
    v.Image->GetBounds(bounds);
    const auto lights = Fig9Lights(row["lights"].get<int>(), bounds);
    const double scale = row["scale"].get<double>();
    double estimates[2];
    const double chosen = StateChange(v, scale, lights, 0, estimates);
    const double selective = StateChange(v, scale, lights, 1);
    const double full = StateChange(v, scale, lights, 2);
    row["state_change_chosen_s"] = chosen;
    row["state_change_selective_s"] = selective;
    row["state_change_full_s"] = full;
    row["chosen_over_cheaper"] = chosen / std::min(selective, full);
    row["estimated_selective_s"] = estimates[0];
    row["estimated_full_s"] = estimates[1];
    std::cout << std::left << std::setw(20) << v.Name << std::setw(8) << row["lights"].get<int>()
              << std::setw(7) << scale << std::right << std::fixed << std::setprecision(3)
              << std::setw(11) << selective << std::setw(10) << full << std::setw(10) << chosen
              << std::setw(6) << row["state_change_mode"].get<int>() << std::setw(16)
              << row["chosen_over_cheaper"].get<double>() << std::setw(12) << estimates[0]
              << std::setw(12) << estimates[1] << "\n"
              << std::defaultfloat;
  }
  (void)smoke;
  return rows;
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

// Wall time per illumination point of a full update: the first light, and each further
// light from a direction of its own (1 and 4 lights), for each kind of light.
json PerVoxel(const Volume& v)
{
  double bounds[6];
  v.Image->GetBounds(bounds);
  const double points = static_cast<double>(v.Image->GetNumberOfPoints());
  std::cout << "\nFull update, " << v.Name << " at scale 1, oblique lights (ns per voxel)\n"
            << std::left << std::setw(14) << "light" << std::right << std::setw(14) << "first light"
            << std::setw(14) << "each added" << std::setw(18) << "first / dir." << std::setw(16)
            << "added / dir."
            << "\n";
  json rows = json::array();
  double directional[2] = { 0.0, 0.0 };
  for (const std::string kind : { "directional", "point", "spot" })
  {
    const double one = FullUpdate(v, 1.0, ObliqueLights(kind, 1, bounds), true);
    const double four = FullUpdate(v, 1.0, ObliqueLights(kind, 4, bounds), true);
    json r;
    r["light"] = kind;
    const double first = 1e9 * one / points, added = 1e9 * (four - one) / 3.0 / points;
    if (kind == "directional")
    {
      directional[0] = first;
      directional[1] = added;
    }
    r["first_light_ns_per_voxel"] = first;
    r["added_light_ns_per_voxel"] = added;
    r["first_light_over_directional"] = first / directional[0];
    r["added_light_over_directional"] = added / directional[1];
    std::cout << std::left << std::setw(14) << kind << std::right << std::setw(14) << first
              << std::setw(14) << added << std::setw(18) << first / directional[0] << std::setw(16)
              << added / directional[1] << "\n";
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

  // A sweep reads the classified grid (2 bytes a point, extinction only) and reads and
  // writes the fixed-point illumination (2 x 12 bytes); the conversion to float reads 12 and
  // writes 12.
  const double points = static_cast<double>(reference->GetOutput()->GetNumberOfPoints());
  const double bytes = points * (passes * (2.0 + 24.0) + 24.0);
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

}
