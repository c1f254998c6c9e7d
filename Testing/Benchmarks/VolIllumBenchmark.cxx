// volillum-benchmark: times the reference illumination and compares rendered frame times of
// the illuminated mapper, a plain GPU ray-cast frame and VTK's built-in volumetric shadows
// (GlobalIlluminationReach 0.5, VolumetricScatteringBlending 1) on the same view and size.
// Prints a table of ratios measured in one run and writes them as JSON.
//
//   volillum-benchmark [--smoke] [--engine FILE] [--json FILE]
//
// --smoke uses tiny sizes so that CI only checks that the benchmark runs.
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
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

#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
struct Case
{
  std::string Name;
  vtkSmartPointer<vtkImageData> Image;
};

struct Result
{
  std::string Name;
  int Dimensions[3];
  double IlluminationScale;
  double IlluminationSeconds;
  double PlainFrame;
  double LitFrame;
  double ShadowFrame;
};

void AddLights(vtkRayMarchedIllumination* filter, const double b[6])
{
  const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  const double size = std::max(b[1] - b[0], std::max(b[3] - b[2], b[5] - b[4]));
  vtkNew<vtkLight> key, fill, rim;
  key->SetPositional(true);
  key->SetConeAngle(180);
  key->SetPosition(c[0] - size, c[1] + size, c[2] + size);
  key->SetDiffuseColor(1.0, 0.85, 0.6);
  fill->SetPositional(false);
  fill->SetPosition(c[0] + size, c[1], c[2]);
  fill->SetFocalPoint(c);
  fill->SetDiffuseColor(0.45, 0.6, 1.0);
  rim->SetPositional(false);
  rim->SetPosition(c[0], c[1] - size, c[2] - size);
  rim->SetFocalPoint(c);
  for (vtkLight* l : { key.Get(), fill.Get(), rim.Get() })
  {
    filter->AddLight(l);
  }
}

// Mean seconds per frame over a few frames after one warm-up frame (shader build, upload).
double TimeFrames(vtkRenderWindow* window, int frames)
{
  window->Render();
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  for (int i = 0; i < frames; ++i)
  {
    window->GetRenderers()->GetFirstRenderer()->GetActiveCamera()->Azimuth(1.0);
    window->Render();
  }
  timer->StopTimer();
  return timer->GetElapsedTime() / frames;
}

Result Run(const Case& c, bool smoke)
{
  Result r;
  r.Name = c.Name;
  c.Image->GetDimensions(r.Dimensions);
  double range[2], bounds[6];
  c.Image->GetPointData()->GetScalars()->GetRange(range);
  c.Image->GetBounds(bounds);
  const double w = range[1] - range[0];
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(range[0], 0, 0, 0);
  ctf->AddRGBPoint(range[0] + 0.3 * w, 0.8, 0.4, 0.3);
  ctf->AddRGBPoint(range[1], 1.0, 0.95, 0.8);
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(range[0], 0);
  otf->AddPoint(range[0] + 0.2 * w, 0);
  otf->AddPoint(range[1], 0.5);

  vtkNew<vtkRayMarchedIllumination> reference;
  reference->SetInputData(c.Image);
  reference->SetColorTransferFunction(ctf);
  reference->SetOpacityFunction(otf);
  reference->SetResolutionScale(0.5);
  AddLights(reference, bounds);
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  reference->Update();
  timer->StopTimer();
  r.IlluminationScale = 0.5;
  r.IlluminationSeconds = timer->GetElapsedTime();

  const int size = smoke ? 64 : 512;
  const int frames = smoke ? 1 : 3;
  auto frame = [&](vtkOpenGLGPUVolumeRayCastMapper* mapper, bool shade)
  {
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(ctf);
    property->SetScalarOpacity(otf);
    property->SetInterpolationTypeToLinear();
    property->SetShade(shade);
    vtkNew<vtkVolume> volume;
    mapper->SetInputData(c.Image);
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
  r.PlainFrame = frame(plain, false);
  vtkNew<vtkIlluminatedVolumeMapper> lit;
  lit->SetIlluminationData(reference->GetOutput());
  r.LitFrame = frame(lit, false);
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> shadows;
  shadows->SetGlobalIlluminationReach(0.5f);
  shadows->SetVolumetricScatteringBlending(1.0f);
  r.ShadowFrame = frame(shadows, true);
  return r;
}
}

int main(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  bool smoke = false;
  std::string engine = VOLILLUM_SHARED_DATA "/volumes/engine.vti";
  std::string jsonPath = "volillum-benchmark.json";
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--smoke")
      smoke = true;
    else if (a == "--engine" && i + 1 < argc)
      engine = argv[++i];
    else if (a == "--json" && i + 1 < argc)
      jsonPath = argv[++i];
    else
    {
      std::cerr << "usage: volillum-benchmark [--smoke] [--engine FILE] [--json FILE]\n";
      return 2;
    }
  }

  std::vector<Case> cases;
  vtkNew<vtkXMLImageDataReader> reader;
  if (reader->CanReadFile(engine.c_str()))
  {
    reader->SetFileName(engine.c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    if (smoke)
    {
      vtkNew<vtkImageResize> shrink;
      shrink->SetInputData(image);
      shrink->SetOutputDimensions(32, 32, 16);
      shrink->Update();
      image = shrink->GetOutput();
    }
    cases.push_back({ "engine", image });
  }
  else
  {
    std::cout << "engine volume not found at " << engine << "; skipping it\n";
  }
  vtkNew<vtkIlluminationPhantomSource> phantom;
  phantom->SetScene(vtkIlluminationPhantomSource::CTPhantom);
  const int n = smoke ? 32 : 256;
  phantom->SetDimensions(n, n, n);
  phantom->Update();
  cases.push_back({ "ct-phantom-" + std::to_string(n), phantom->GetOutput() });

  std::vector<Result> results;
  for (const auto& c : cases)
  {
    results.push_back(Run(c, smoke));
  }

  std::cout << "\n"
            << std::left << std::setw(18) << "volume" << std::setw(14) << "dims" << std::right
            << std::setw(16) << "reference [s]" << std::setw(14) << "lit/plain" << std::setw(16)
            << "shadows/plain" << std::setw(14) << "shadows/lit"
            << "\n";
  std::ostringstream json;
  json << "{\n  \"smoke\": " << (smoke ? "true" : "false") << ",\n  \"cases\": [\n";
  for (size_t i = 0; i < results.size(); ++i)
  {
    const Result& r = results[i];
    std::ostringstream dims;
    dims << r.Dimensions[0] << "x" << r.Dimensions[1] << "x" << r.Dimensions[2];
    std::cout << std::left << std::setw(18) << r.Name << std::setw(14) << dims.str() << std::right
              << std::setw(16) << std::setprecision(3) << r.IlluminationSeconds << std::setw(14)
              << r.LitFrame / r.PlainFrame << std::setw(16) << r.ShadowFrame / r.PlainFrame
              << std::setw(14) << r.ShadowFrame / r.LitFrame << "\n";
    json << "    {\"volume\": \"" << r.Name << "\", \"dimensions\": [" << r.Dimensions[0] << ", "
         << r.Dimensions[1] << ", " << r.Dimensions[2]
         << "], \"reference_resolution_scale\": " << r.IlluminationScale
         << ", \"reference_seconds\": " << r.IlluminationSeconds
         << ", \"lit_over_plain_frame\": " << r.LitFrame / r.PlainFrame
         << ", \"builtin_shadows_over_plain_frame\": " << r.ShadowFrame / r.PlainFrame
         << ", \"builtin_shadows_over_lit_frame\": " << r.ShadowFrame / r.LitFrame << "}"
         << (i + 1 < results.size() ? "," : "") << "\n";
  }
  json << "  ]\n}\n";
  std::ofstream out(jsonPath);
  out << json.str();
  std::cout << "wrote " << jsonPath << std::endl;
  return out ? 0 : 1;
}
