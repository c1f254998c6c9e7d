// volillum-benchmark: the rendering suite (frame-time ratios).
#include "VolIllumBenchmark.h"

#include "vtkCamera.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkRayMarchedIllumination.h"

#include "vtkNew.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <iomanip>
#include <iostream>

namespace volillum_benchmark
{

namespace
{
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
}

json Rendering(const Volume& v, bool smoke, vtkRenderWindow* window)
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
    window->SetSize(size, size);
    window->AddRenderer(renderer);
    const double seconds = TimeFrames(window, frames);
    window->RemoveRenderer(renderer);
    return seconds;
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

json RenderingSuite(const std::vector<Volume>& volumes, bool smoke)
{
  std::cout << "\nRendering (" << (smoke ? 64 : 512) << " pixels square; ratios of frame times)\n"
            << std::left << std::setw(20) << "volume" << std::right << std::setw(16)
            << "reference [s]" << std::setw(14) << "lit/plain" << std::setw(14) << "lit/shaded"
            << std::setw(16) << "shadows/plain" << std::setw(14) << "shadows/lit"
            << "\n";
  // One window for every frame of the suite: under a plain `xvfb-run -a` the X server resets
  // when its last client leaves, and a window opened just then finds no server.
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  json rows = json::array();
  for (const auto& v : volumes)
  {
    rows.push_back(Rendering(v, smoke, window));
  }
  return rows;
}

}
