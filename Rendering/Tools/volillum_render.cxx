// volillum-render: read a volume (or generate a phantom), compute its illumination volume
// with a chosen method, render it with vtkIlluminatedVolumeMapper and write a PNG.
//
//   volillum-render [options] [volume file]
//
// Run with --help for the options and the JSON format. Any failure prints one line that
// starts with "volillum-render: error:" and exits with status 1.
#include "VolIllumRender.h"

#include "vtkCamera.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkPointData.h"
#include "vtkRayMarchedIllumination.h"
#include "vtkUnstructuredGridIllumination.h"

#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkGPUVolumeRayCastMapper.h"
#include "vtkImageAppend.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkProjectedTetrahedraMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTimerLog.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

using namespace volillum_render;

namespace
{
// Bounds of the points whose opacity is above 0 (the data's bounds when there are none).
void ObjectBounds(vtkDataSet* data, vtkPiecewiseFunction* otf, double bounds[6])
{
  data->GetBounds(bounds);
  vtkDataArray* scalars = data->GetPointData()->GetScalars();
  double found[6] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MIN, VTK_DOUBLE_MAX, VTK_DOUBLE_MIN,
    VTK_DOUBLE_MAX, VTK_DOUBLE_MIN };
  bool any = false;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    const double v = scalars->GetComponent(i, 0);
    if (std::isfinite(v) && otf->GetValue(v) > 0.0)
    {
      double p[3];
      data->GetPoint(i, p);
      for (int a = 0; a < 3; ++a)
      {
        found[2 * a] = std::min(found[2 * a], p[a]);
        found[2 * a + 1] = std::max(found[2 * a + 1], p[a]);
      }
      any = true;
    }
  }
  if (any)
  {
    std::copy(found, found + 6, bounds);
  }
}

// The frame the render window shows now.
vtkSmartPointer<vtkImageData> Grab(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto frame = vtkSmartPointer<vtkImageData>::New();
  frame->DeepCopy(grab->GetOutput());
  return frame;
}

// The same view with local shading only: VTK's ray caster with gradient shading, lit by the
// same lights.
vtkSmartPointer<vtkImageData> RenderLocalShading(vtkImageData* image, vtkVolume* volume,
  vtkRenderer* renderer, vtkRenderWindow* window,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, vtkTextActor* label)
{
  label->SetInput("local shading");
  vtkNew<vtkGPUVolumeRayCastMapper> mapper;
  mapper->SetInputData(image);
  vtkNew<vtkVolumeProperty> property;
  property->DeepCopy(volume->GetProperty());
  property->ShadeOn();
  // The same ambient and diffuse terms as the lit frame's.
  auto lit = vtkIlluminatedVolumeMapper::SafeDownCast(volume->GetMapper());
  property->SetAmbient(lit->GetAmbient());
  property->SetDiffuse(lit->GetDiffuse());
  property->SetSpecular(0.0);
  vtkNew<vtkVolume> local;
  local->SetMapper(mapper);
  local->SetProperty(property);
  renderer->RemoveVolume(volume);
  renderer->AddVolume(local);
  renderer->AutomaticLightCreationOff();
  renderer->RemoveAllLights();
  for (const auto& l : lights)
  {
    vtkNew<vtkLight> copy;
    copy->DeepCopy(l);
    copy->SetLightTypeToSceneLight();
    renderer->AddLight(copy);
  }
  window->Render();
  auto frame = Grab(window);
  renderer->RemoveVolume(local);
  renderer->AddVolume(volume);
  return frame;
}
}

// Computes the illumination volume of an image and sets up the lit ray-cast mapper.
double LightImage(const json& config, const std::string& method, vtkImageData* image,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, vtkColorTransferFunction* ctf,
  vtkPiecewiseFunction* otf, double unitDistance, vtkVolume* volume)
{
  vtkSmartPointer<vtkIlluminationVolumeAlgorithm> illumination;
  if (method == "propagation")
  {
    illumination = vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
  }
  else if (method == "reference")
  {
    illumination = vtkSmartPointer<vtkRayMarchedIllumination>::New();
  }
  else if (method == "filtered")
  {
    auto filtered = vtkSmartPointer<vtkFilteredVolumetricShadows>::New();
    filtered->SetFilterWidth(Number(config, "filter_width", filtered->GetFilterWidth()));
    illumination = filtered;
  }
  else
  {
    Fail("unknown method '" + method + "' (available: propagation, filtered, reference)");
  }
  illumination->SetInputData(image);
  for (const auto& l : lights)
  {
    illumination->AddLight(l);
  }
  illumination->SetColorTransferFunction(ctf);
  illumination->SetOpacityFunction(otf);
  illumination->SetScalarOpacityUnitDistance(unitDistance);
  illumination->SetResolutionScale(
    Number(config, "resolution_scale", illumination->GetResolutionScale()));
  illumination->SetChromaticAttenuation(
    Flag(config, "chromatic_attenuation", illumination->GetChromaticAttenuation()));
  illumination->SetAmbientOcclusion(
    Number(config, "ambient_occlusion", illumination->GetAmbientOcclusion()));
  illumination->SetAmbientOcclusionRadius(
    Number(config, "ambient_occlusion_radius", illumination->GetAmbientOcclusionRadius()));
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  illumination->Update();
  timer->StopTimer();
  vtkImageData* lit = illumination->GetOutput();
  if (!lit || !lit->GetPointData()->GetArray("Illumination"))
  {
    Fail("the illumination could not be computed (see the message above)");
  }
  vtkNew<vtkIlluminatedVolumeMapper> mapper;
  mapper->SetInputData(image);
  mapper->SetIlluminationData(lit);
  mapper->SetAmbient(Number(config, "ambient", mapper->GetAmbient()));
  mapper->SetDiffuse(Number(config, "diffuse", mapper->GetDiffuse()));
  mapper->SetGradientShading(Flag(config, "gradient_shading", mapper->GetGradientShading()));
  volume->SetMapper(mapper);
  return timer->GetElapsedTime();
}

// Lights an unstructured grid with the two-level solver and sets up projected tetrahedra
// on its lit vertex colours (per-vertex lighting).
double LightGrid(const json& config, vtkUnstructuredGrid* grid,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, vtkColorTransferFunction* ctf,
  vtkPiecewiseFunction* otf, double unitDistance, vtkVolume* volume)
{
  // Projected tetrahedra draw tetrahedra only: split other cells first (the filter would
  // split them the same way, but its output keeps the input's cells).
  vtkSmartPointer<vtkUnstructuredGrid> tetrahedra = grid;
  if (!grid->IsHomogeneous() || (grid->GetNumberOfCells() > 0 && grid->GetCellType(0) != VTK_TETRA))
  {
    vtkNew<vtkDataSetTriangleFilter> split;
    split->TetrahedraOnlyOn();
    split->SetInputData(grid);
    split->Update();
    tetrahedra = split->GetOutput();
  }
  vtkNew<vtkUnstructuredGridIllumination> illumination;
  illumination->SetInputData(tetrahedra);
  for (const auto& l : lights)
  {
    illumination->AddLight(l);
  }
  illumination->SetColorTransferFunction(ctf);
  illumination->SetOpacityFunction(otf);
  illumination->SetScalarOpacityUnitDistance(unitDistance);
  illumination->SetChromaticAttenuation(
    Flag(config, "chromatic_attenuation", illumination->GetChromaticAttenuation()));
  const int resolution =
    static_cast<int>(Number(config, "level0_resolution", illumination->GetLevel0Resolution()[0]));
  illumination->SetLevel0Resolution(resolution, resolution, resolution);
  illumination->SetAbsorption(Number(config, "absorption", illumination->GetAbsorption()));
  if (config.contains("scattering"))
  {
    const auto s = Numbers(config["scattering"], 3, "scattering");
    illumination->SetScatteringStrength(s[0], s[1], s[2]);
  }
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  illumination->Update();
  timer->StopTimer();
  vtkUnstructuredGrid* lit = illumination->GetOutput();
  if (!lit || !lit->GetPointData()->GetArray("LitColors"))
  {
    Fail("the illumination could not be computed (see the message above)");
  }
  // The lit colours are direct RGBA: dependent components, no transfer-function lookup.
  vtkNew<vtkProjectedTetrahedraMapper> mapper;
  mapper->SetInputData(lit);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectScalarArray("LitColors");
  volume->SetMapper(mapper);
  volume->GetProperty()->IndependentComponentsOff();
  return timer->GetElapsedTime();
}

namespace
{
// Fails unless the output file can be written; checked before any work, as a bad value must
// not cost a whole render first (and VTK's PNG writer leaks when it cannot open its file).
void CheckWritable(const std::string& output)
{
  const bool existed = std::ifstream(output).good();
  if (!std::ofstream(output, std::ios::binary | std::ios::app))
  {
    Fail("cannot write " + output);
  }
  if (!existed)
  {
    std::remove(output.c_str());
  }
}

// The smallest spacing of a volume; for a grid, which has none, 1/128 of its diagonal (the
// default unit distance is derived from it).
double MinimumSpacing(vtkDataSet* data)
{
  if (auto image = vtkImageData::SafeDownCast(data))
  {
    double spacing[3];
    image->GetSpacing(spacing);
    return std::min(spacing[0], std::min(spacing[1], spacing[2]));
  }
  double bounds[6];
  data->GetBounds(bounds);
  return std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
           (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
           (bounds[5] - bounds[4]) * (bounds[5] - bounds[4])) /
    128.0;
}

// A renderer of the volume with the configured background and camera, framing the points
// whose opacity is above 0.
vtkSmartPointer<vtkRenderer> MakeRenderer(
  const json& config, vtkVolume* volume, vtkDataSet* data, vtkPiecewiseFunction* otf)
{
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  renderer->AddVolume(volume);
  const json background =
    config.contains("background") ? config["background"] : json::array({ 0.0, 0.0, 0.0 });
  const auto bg = Numbers(background, 3, "background");
  renderer->SetBackground(bg.data());
  renderer->ResetCamera();
  const json camera = config.contains("camera") ? config["camera"] : json::object();
  if (!camera.is_object())
  {
    Fail("'camera' must be a JSON object");
  }
  renderer->GetActiveCamera()->Azimuth(Number(camera, "azimuth", 30.0));
  renderer->GetActiveCamera()->Elevation(Number(camera, "elevation", 20.0));
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->GetActiveCamera()->Roll(Number(camera, "roll", 0.0));
  double object[6];
  ObjectBounds(data, otf, object);
  renderer->ResetCamera(object);
  renderer->GetActiveCamera()->Zoom(Number(camera, "zoom", 1.0));
  renderer->ResetCameraClippingRange();
  return renderer;
}

// Wall seconds of one render of the window.
double TimeFrame(vtkRenderWindow* window)
{
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  window->Render();
  timer->StopTimer();
  return timer->GetElapsedTime();
}

void WritePNG(vtkImageData* picture, const std::string& output)
{
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(output.c_str());
  writer->SetInputData(picture);
  writer->Write();
  if (writer->GetErrorCode() != 0)
  {
    Fail("cannot write " + output);
  }
}

// The volume drawn: coloured by the transfer functions, interpolated linearly and unshaded
// (the illumination lights it).
vtkSmartPointer<vtkVolume> MakeVolume(
  vtkColorTransferFunction* ctf, vtkPiecewiseFunction* otf, double unitDistance)
{
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(ctf);
  property->SetScalarOpacity(otf);
  property->SetScalarOpacityUnitDistance(unitDistance);
  property->SetInterpolationTypeToLinear();
  property->ShadeOff();
  vtkSmartPointer<vtkVolume> volume = vtkSmartPointer<vtkVolume>::New();
  volume->SetProperty(property);
  return volume;
}

// The image's width and height in pixels ("image_size", 16 to 8192 a side).
std::vector<double> ImageSize(const json& config)
{
  const json size =
    config.contains("image_size") ? config["image_size"] : json::array({ 512, 512 });
  const auto wh = Numbers(size, 2, "image_size");
  if (!(wh[0] >= 16 && wh[1] >= 16 && wh[0] <= 8192 && wh[1] <= 8192))
  {
    Fail("image_size must be between 16 and 8192 pixels per side");
  }
  return wh;
}

// The label of the globally illuminated half of a side-by-side image `height` pixels high.
void AddGlobalLabel(vtkTextActor* label, vtkRenderer* renderer, double height)
{
  label->SetInput("global illumination");
  label->GetTextProperty()->SetFontSize(std::max(12, static_cast<int>(height / 22)));
  label->GetTextProperty()->SetColor(1.0, 1.0, 1.0);
  label->GetTextProperty()->ShadowOn();
  label->SetDisplayPosition(static_cast<int>(height / 40), static_cast<int>(height / 40));
  renderer->AddActor2D(label);
}
}

int Run(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  const Options options = ParseArguments(argc, argv);
  const json& config = options.Config;
  const std::string output = Text(config, "output", "volillum.png");
  CheckWritable(output);

  // VTK's own warnings still reach stderr; its error pop-ups do not exist here.
  vtkSmartPointer<vtkDataSet> data = LoadData(options);
  double bounds[6], range[2];
  data->GetBounds(bounds);
  data->GetPointData()->GetScalars()->GetRange(range);
  auto image = vtkImageData::SafeDownCast(data);
  vtkNew<vtkColorTransferFunction> ctf;
  vtkNew<vtkPiecewiseFunction> otf;
  double unitDistance = 1.0;
  BuildTransferFunctions(config, data->GetPointData()->GetScalars(), range, ctf, otf, unitDistance,
    MinimumSpacing(data));
  const bool sideBySide = Flag(config, "side_by_side", false);
  if (sideBySide && !image)
  {
    Fail("'side_by_side' is available for volumes (image data), not for grids");
  }
  const auto lights = BuildLights(config, bounds);

  vtkSmartPointer<vtkVolume> volume = MakeVolume(ctf, otf, unitDistance);
  const std::string method = image ? Text(config, "method", "propagation") : "two-level";
  const double illuminationSeconds = image
    ? LightImage(config, method, image, lights, ctf, otf, unitDistance, volume)
    : LightGrid(
        config, vtkUnstructuredGrid::SafeDownCast(data), lights, ctf, otf, unitDistance, volume);

  const std::vector<double> wh = ImageSize(config);
  vtkSmartPointer<vtkRenderer> renderer = MakeRenderer(config, volume, data, otf);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(static_cast<int>(wh[0]), static_cast<int>(wh[1]));
  window->AddRenderer(renderer);
  // Side by side, each half says what it shows (the local half's label is set as it renders).
  vtkNew<vtkTextActor> label;
  if (sideBySide && Flag(config, "labels", true))
  {
    AddGlobalLabel(label, renderer, wh[1]);
  }
  // The image is taken from the very first frame: it must already be lit.
  const double firstFrameSeconds = TimeFrame(window);
  vtkSmartPointer<vtkImageData> picture = Grab(window);
  const double frameSeconds = TimeFrame(window);
  if (sideBySide)
  {
    vtkNew<vtkImageAppend> both;
    both->SetAppendAxis(0);
    both->AddInputData(RenderLocalShading(image, volume, renderer, window, lights, label));
    both->AddInputData(picture);
    both->Update();
    picture = both->GetOutput();
  }
  WritePNG(picture, output);
  std::cout << "illumination (" << method << ", " << lights.size()
            << " lights): " << illuminationSeconds << " s\n"
            << "first frame: " << firstFrameSeconds << " s\n"
            << "frame: " << frameSeconds << " s\n"
            << "wrote " << output << std::endl;
  return 0;
}

int main(int argc, char* argv[])
{
  // Every failure ends with one line and status 1, also the ones a library throws.
  std::string message;
  try
  {
    return Run(argc, argv);
  }
  catch (const Failure& e)
  {
    message = e.what();
  }
  catch (const json::exception& e)
  {
    message = std::string("invalid settings: ") + e.what();
  }
  catch (const std::bad_alloc&)
  {
    message = "out of memory";
  }
  catch (const std::exception& e)
  {
    message = e.what();
  }
  std::cerr << "volillum-render: error: " << message << std::endl;
  return 1;
}
