// volillum-benchmark: the filtered-shadows suite.
#include "VolIllumBenchmark.h"

#include "IlluminationClassify.h"
#include "IlluminationFidelity.h"
#include "IlluminationLightList.h"
#include "RayMarchKernel.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkLight.h"
#include "vtkNew.h"

#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

namespace volillum_benchmark
{

namespace
{
// Seconds of the reference (single scattering) after a transfer-function change. It marches
// every point to every light; where that would take too long (large) it is timed on a few
// slices of the output grid and scaled to the whole grid (its cost is proportional to the
// number of points), slices telling how many.
double ReferenceSeconds(const Volume& v, double scale, bool large,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, int& slices)
{
  slices = 0;
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
    slices = part.Dimensions[2];
  }
  return referenceSeconds;
}
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
  // radius: the lights' size (apparent diameter in degrees; 0: hard lights); ambient: the
  // ambient occlusion's strength (0: none; the default radius).
  auto filtered = [&](double width, int kernel, double radius, double ambient = 0.0)
  {
    vtkNew<vtkFilteredVolumetricShadows> f;
    Configure(f, v, scale);
    f->SetFilterWidth(width);
    f->SetFilterKernel(kernel);
    f->SetAmbientOcclusion(ambient);
    for (const auto& l : lights)
    {
      volillum::SetLightRadius(l, radius);
      f->AddLight(l);
    }
    f->Update();
    json r;
    r["tf_change_s"] = AfterTransferFunctionChange(f, v);
    r["tables_built"] = Passes(f);
    f->Update(); // the transfer function back as it was (a change of its own, not timed)
    // One light's size edited (2 degrees more): that light alone is shaded again, no table
    // built.
    volillum::SetLightRadius(lights[0], radius + 2.0);
    r["radius_edit_s"] = Seconds([&] { f->Update(); });
    for (const auto& l : lights)
    {
      volillum::SetLightRadius(l, 0.0);
    }
    return r;
  };
  json r;
  r["volume"] = v.Name;
  r["scale"] = scale;
  const json box3 = filtered(3, vtkFilteredVolumetricShadows::Box, 0.0);
  const json box11 = filtered(11, vtkFilteredVolumetricShadows::Box, 0.0);
  // Lights 5 degrees across: a cone of boxes a light and point.
  const json soft3 = filtered(3, vtkFilteredVolumetricShadows::Box, 5.0);
  // Ambient occlusion at its default radius (a twentieth of the diagonal), computed again
  // after a transfer-function change and kept when a light's colour changes.
  const json ambient3 = filtered(3, vtkFilteredVolumetricShadows::Box, 0.0, 1.0);
  // The Gaussian reads 25 cuboids a light and point: timed on the smaller volume only.
  const json gauss3 = large ? json() : filtered(3, vtkFilteredVolumetricShadows::Gaussian, 0.0);
  const double t3 = box3["tf_change_s"].get<double>();
  r["filtered_width3_s"] = t3;
  r["filtered_width11_s"] = box11["tf_change_s"].get<double>();
  r["tables_built"] = box3["tables_built"];
  r["width11_over_width3"] = box11["tf_change_s"].get<double>() / t3;
  // One of the three sized lights' size edited against all three after a transfer-function
  // change (tables and every light shaded).
  r["radius_edit_over_tf_change"] =
    soft3["radius_edit_s"].get<double>() / soft3["tf_change_s"].get<double>();
  r["gaussian_over_box"] = large ? 0.0 : gauss3["tf_change_s"].get<double>() / t3;
  r["radius5_over_hard"] = soft3["tf_change_s"].get<double>() / t3;
  r["ambient_over_none"] = ambient3["tf_change_s"].get<double>() / t3;
  r["ambient_radius_edit_over_none"] =
    ambient3["radius_edit_s"].get<double>() / box3["radius_edit_s"].get<double>();

  vtkNew<vtkMultiLightIlluminationVolume> propagation;
  Configure(propagation, v, scale);
  for (const auto& l : lights)
  {
    propagation->AddLight(l);
  }
  propagation->Update();
  r["propagation_s"] = AfterTransferFunctionChange(propagation, v);
  r["propagation_over_filtered"] = r["propagation_s"].get<double>() / t3;

  int slices = 0;
  const double referenceSeconds = ReferenceSeconds(v, scale, large, lights, slices);
  if (slices > 0)
  {
    r["reference_extrapolated_from_slices"] = slices;
  }
  r["reference_s"] = referenceSeconds;
  r["filtered_speedup_over_reference"] = referenceSeconds / t3;
  std::cout << std::left << std::setw(16) << v.Name << std::setw(7) << scale << std::right
            << std::setw(12) << referenceSeconds << std::setw(11) << t3 << std::setw(11)
            << r["filtered_speedup_over_reference"].get<double>() << std::setw(10)
            << r["width11_over_width3"].get<double>() << std::setw(12)
            << r["radius_edit_over_tf_change"].get<double>() << std::setw(12)
            << r["gaussian_over_box"].get<double>() << std::setw(11)
            << r["radius5_over_hard"].get<double>() << std::setw(10)
            << r["ambient_over_none"].get<double>() << std::setw(12)
            << r["propagation_over_filtered"].get<double>() << "\n";
  return r;
}

json FilteredShadowsSuite(const Volume& v, bool smoke)
{
  std::cout << "\nFiltered shadows after a transfer-function change, 3 orthodirectional lights\n"
            << std::left << std::setw(16) << "volume" << std::setw(7) << "scale" << std::right
            << std::setw(12) << "ref [s]" << std::setw(11) << "filt [s]" << std::setw(11)
            << "ref/filt" << std::setw(10) << "w11/w3" << std::setw(12) << "edit1/tf"
            << std::setw(12) << "gauss/box" << std::setw(11) << "r5/hard" << std::setw(10)
            << "ao/none" << std::setw(12) << "prop/filt"
            << "\n";
  json rows = json::array();
  rows.push_back(FilteredShadows(v, 0.5, false));
  if (!smoke && v.Name == "engine")
  {
    rows.push_back(
      FilteredShadows(MakeVolume("engine-512^3", Resize(v.Image, 512, 512, 512)), 0.5, true));
  }
  return rows;
}

}
