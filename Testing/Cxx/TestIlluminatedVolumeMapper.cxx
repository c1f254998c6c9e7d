// TestIlluminatedVolumeMapper BASELINE.png OUTPUT_DIR
// vtkIlluminatedVolumeMapper without the CLI: the three-sphere phantom lit by a yellow point
// light and a blue directional light (Multi-Light Illumination Volume at scale 1/2), drawn at
// 200x200 and compared with its baseline by vtkImageDifference (VTK's regression measure,
// threshold RegressionThreshold). The same frame drawn without the illumination must differ
// from it by more than LitDifference, so an illumination the mapper ignored would fail.
// Writes OUTPUT_DIR/IlluminatedVolumeMapper.png.
#include "IlluminationTestUtilities.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkMultiLightIlluminationVolume.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkImageData.h"
#include "vtkImageDifference.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"

#include <iostream>
#include <string>

namespace
{
// Largest vtkImageDifference error against the baseline (as the CLI regression images).
constexpr double RegressionThreshold = 0.05;
// Smallest error between the lit and the unlit frame.
constexpr double LitDifference = 5.0;

vtkSmartPointer<vtkImageData> Grab(vtkRenderWindow* window)
{
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

double Difference(vtkImageData* a, vtkImageData* b)
{
  vtkNew<vtkImageDifference> difference;
  difference->SetInputData(a);
  difference->SetImageData(b);
  difference->Update();
  return difference->GetThresholdedError();
}

// The phantom's illumination by a yellow point light and a blue directional light (Multi-Light
// Illumination Volume at scale 1/2).
vtkSmartPointer<vtkImageData> Illuminate(
  vtkImageData* image, vtkColorTransferFunction* ctf, vtkPiecewiseFunction* otf)
{
  vtkNew<vtkMultiLightIlluminationVolume> illumination;
  illumination->SetInputData(image);
  illumination->SetColorTransferFunction(ctf);
  illumination->SetOpacityFunction(otf);
  illumination->SetResolutionScale(0.5);
  illumination->AddLight(volillumtest::PointLight(-30, 24, 70, 1.0, 0.85, 0.3));
  illumination->AddLight(volillumtest::DirectionalLight(-36, 64, -6, 0.3, 0.5, 1.0));
  illumination->Update();
  return illumination->GetOutput();
}
}

int main(int argc, char* argv[])
{
  if (argc != 3)
  {
    std::cerr << "usage: TestIlluminatedVolumeMapper BASELINE.png OUTPUT_DIR\n";
    return 2;
  }
  vtkSmartPointer<vtkImageData> image =
    volillumtest::PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 48);

  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0, 0.0, 0.0, 0.0);
  ctf->AddRGBPoint(200, 0.9, 0.9, 0.85);
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0, 0.0);
  otf->AddPoint(100, 0.0);
  otf->AddPoint(200, 0.6);

  vtkSmartPointer<vtkImageData> lighting = Illuminate(image, ctf, otf);
  vtkNew<vtkIlluminatedVolumeMapper> mapper;
  mapper->SetInputData(image);
  mapper->SetIlluminationData(lighting);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(ctf);
  property->SetScalarOpacity(otf);
  property->SetInterpolationTypeToLinear();
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(30);
  renderer->GetActiveCamera()->Elevation(20);
  renderer->GetActiveCamera()->Zoom(1.8);
  renderer->ResetCameraClippingRange();
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(200, 200);
  window->AddRenderer(renderer);
  vtkSmartPointer<vtkImageData> lit = Grab(window);

  const std::string output = std::string(argv[2]) + "/IlluminatedVolumeMapper.png";
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(output.c_str());
  writer->SetInputData(lit);
  writer->Write();

  mapper->SetIlluminationData(nullptr);
  vtkSmartPointer<vtkImageData> unlit = Grab(window);
  const double litDifference = Difference(lit, unlit);

  vtkNew<vtkPNGReader> baseline;
  if (!baseline->CanReadFile(argv[1]))
  {
    std::cerr << "cannot read the baseline " << argv[1] << " (this run wrote " << output << ")\n";
    return 1;
  }
  baseline->SetFileName(argv[1]);
  baseline->Update();
  const double error = Difference(lit, baseline->GetOutput());
  std::cout << "image error against the baseline " << error << " (threshold " << RegressionThreshold
            << "); lit against unlit " << litDifference << " (at least " << LitDifference << ")\n";
  return error <= RegressionThreshold && litDifference >= LitDifference ? 0 : 1;
}
