// VolIllumImageCompare TEST.png BASELINE.png THRESHOLD
// Compares a rendered image with its baseline using vtkImageDifference (the measure of VTK's
// regression tests, tolerant of one-pixel shifts) and fails when the error exceeds
// THRESHOLD or the images differ in size.
#include "vtkImageData.h"
#include "vtkImageDifference.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"

#include <cstdlib>
#include <iostream>

int main(int argc, char* argv[])
{
  if (argc != 4)
  {
    std::cerr << "usage: VolIllumImageCompare TEST.png BASELINE.png THRESHOLD\n";
    return 2;
  }
  vtkNew<vtkPNGReader> test, baseline;
  test->SetFileName(argv[1]);
  baseline->SetFileName(argv[2]);
  for (vtkPNGReader* r : { test.Get(), baseline.Get() })
  {
    if (!r->CanReadFile(r->GetFileName()))
    {
      std::cerr << "cannot read " << r->GetFileName() << "\n";
      return 1;
    }
    r->Update();
  }
  int a[3], b[3];
  test->GetOutput()->GetDimensions(a);
  baseline->GetOutput()->GetDimensions(b);
  if (a[0] != b[0] || a[1] != b[1])
  {
    std::cerr << "size " << a[0] << "x" << a[1] << " differs from the baseline's " << b[0] << "x"
              << b[1] << "\n";
    return 1;
  }
  vtkNew<vtkImageDifference> difference;
  difference->SetInputConnection(test->GetOutputPort());
  difference->SetImageConnection(baseline->GetOutputPort());
  difference->Update();
  const double error = difference->GetThresholdedError();
  const double threshold = std::atof(argv[3]);
  std::cout << "image error " << error << " (threshold " << threshold << ")\n";
  return error <= threshold ? 0 : 1;
}
