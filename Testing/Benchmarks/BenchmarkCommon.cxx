// volillum-benchmark: volumes, filter set-up and the lights of Fig. 9.
#include "VolIllumBenchmark.h"

#include "vtkColorTransferFunction.h"
#include "vtkFieldData.h"
#include "vtkIlluminationVolumeAlgorithm.h"
#include "vtkImageData.h"
#include "vtkImageResize.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"

#include <algorithm>
#include <string>
#include <vector>

namespace volillum_benchmark
{

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

}
