#include "vtkIlluminationPhantomSource.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

vtkStandardNewMacro(vtkIlluminationPhantomSource);

namespace
{
// Smooth inside indicator of a sphere or ellipsoid: 1 inside, 0 outside, a linear ramp one
// voxel wide across the surface (distance d in voxels, signed, negative inside).
double Inside(double signedDistance)
{
  return std::min(1.0, std::max(0.0, 0.5 - signedDistance));
}

// Signed distance (approximate, in voxels) to an axis-aligned ellipsoid.
double EllipsoidDistance(const double p[3], const double c[3], const double r[3])
{
  double q = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double u = (p[a] - c[a]) / r[a];
    q += u * u;
  }
  const double rmin = std::min(r[0], std::min(r[1], r[2]));
  return (std::sqrt(q) - 1.0) * rmin;
}

bool ValidDimensions(const int dims[3])
{
  for (int a = 0; a < 3; ++a)
  {
    if (dims[a] < 2 || dims[a] > 1024)
    {
      return false;
    }
  }
  return true;
}

// The scenes at a point p (grid coordinates) of a grid spanning size, as values in [0, 1] of
// the scene's full scale.
double ThreeSpheresValue(const double p[3], const double size[3])
{
  static const double centres[3][3] = { { 0.32, 0.50, 0.50 }, { 0.62, 0.32, 0.46 },
    { 0.62, 0.68, 0.56 } };
  double v = 0.0;
  for (const auto& c : centres)
  {
    const double cc[3] = { c[0] * size[0], c[1] * size[1], c[2] * size[2] };
    const double rr = 0.16 * std::min(size[0], std::min(size[1], size[2]));
    const double r[3] = { rr, rr, rr };
    v = std::max(v, Inside(EllipsoidDistance(p, cc, r)));
  }
  return v;
}

double ChirpValue(const double p[3], const double size[3])
{
  if (p[2] <= 2.0)
  {
    return 1.0;
  }
  if (p[2] < 0.6 * size[2] || p[2] > 0.75 * size[2])
  {
    return 0.0;
  }
  // Frequency f(x) = f0 + (f1 - f0) x / L, phase = 2 pi (f0 x + (f1 - f0) x^2 / 2L).
  const double f0 = 1.0 / 40.0, f1 = 0.25, length = std::max(size[0], 1.0);
  const double phase = 2.0 * vtkMath::Pi() * (f0 * p[0] + 0.5 * (f1 - f0) * p[0] * p[0] / length);
  return 0.5 * (1.0 + std::cos(phase));
}

double CTPhantomValue(const double p[3], const double size[3])
{
  const double c[3] = { 0.5 * size[0], 0.5 * size[1], 0.5 * size[2] };
  const double head[3] = { 0.42 * size[0], 0.46 * size[1], 0.44 * size[2] };
  const double brain[3] = { 0.37 * size[0], 0.41 * size[1], 0.39 * size[2] };
  const double skin = Inside(EllipsoidDistance(p, c, head));
  const double inner = Inside(EllipsoidDistance(p, c, brain));
  // Skull between the brain and the skin, soft tissue inside.
  double v = 0.6 * (skin - inner) + 0.3 * inner;
  const double ventricle[3] = { 0.06 * size[0], 0.14 * size[1], 0.08 * size[2] };
  for (double side : { -1.0, 1.0 })
  {
    const double vc[3] = { c[0] + side * 0.09 * size[0], c[1] + 0.02 * size[1], c[2] };
    v -= 0.2 * Inside(EllipsoidDistance(p, vc, ventricle));
  }
  const double blobs[3][4] = { { 0.40, 0.30, 0.62, 0.05 }, { 0.62, 0.66, 0.40, 0.04 },
    { 0.52, 0.42, 0.30, 0.035 } };
  for (const auto& b : blobs)
  {
    const double bc[3] = { b[0] * size[0], b[1] * size[1], b[2] * size[2] };
    const double br[3] = { b[3] * size[0], b[3] * size[1], b[3] * size[2] };
    v = std::max(v, Inside(EllipsoidDistance(p, bc, br)));
  }
  return std::min(1.0, std::max(0.0, v));
}
}

//------------------------------------------------------------------------------
vtkIlluminationPhantomSource::vtkIlluminationPhantomSource()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
int vtkIlluminationPhantomSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int* d = this->Dimensions;
  int ext[6] = { 0, std::max(d[0], 1) - 1, 0, std::max(d[1], 1) - 1, 0, std::max(d[2], 1) - 1 };
  double spacing[3] = { 1.0, 1.0, 1.0 };
  double origin[3] = { 0.0, 0.0, 0.0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  return 1;
}

//------------------------------------------------------------------------------
int vtkIlluminationPhantomSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  if (!ValidDimensions(this->Dimensions))
  {
    vtkErrorMacro("Dimensions must be between 2 and 1024 along each axis.");
    return 1;
  }
  const int nx = this->Dimensions[0];
  const int ny = this->Dimensions[1];
  const int nz = this->Dimensions[2];
  output->SetDimensions(this->Dimensions);
  output->SetSpacing(1.0, 1.0, 1.0);
  output->SetOrigin(0.0, 0.0, 0.0);
  const vtkIdType n = static_cast<vtkIdType>(nx) * ny * nz;
  const double size[3] = { nx - 1.0, ny - 1.0, nz - 1.0 };

  // Evaluates the scene at a point as a value in [0, 1] of the scene's full scale.
  auto evaluate = [&](const double p[3]) -> double
  {
    switch (this->Scene)
    {
      case ThreeSpheres:
        return ThreeSpheresValue(p, size);
      case Slab:
        return (p[2] >= this->SlabBegin && p[2] <= this->SlabEnd) ? 1.0 : 0.0;
      case Chirp:
        return ChirpValue(p, size);
      default:
        return CTPhantomValue(p, size);
    }
  };

  auto fill = [&](auto* values, double fullScale)
  {
    vtkSMPTools::For(0, n,
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType id = begin; id < end; ++id)
        {
          const double p[3] = { static_cast<double>(id % nx), static_cast<double>((id / nx) % ny),
            static_cast<double>(id / (static_cast<vtkIdType>(nx) * ny)) };
          using ValueType = std::remove_pointer_t<decltype(values)>;
          const double v = evaluate(p) * fullScale;
          values[id] =
            static_cast<ValueType>(std::is_integral<ValueType>::value ? std::round(v) : v);
        }
      });
  };

  vtkSmartPointer<vtkDataArray> scalars;
  if (this->Scene == Slab || this->Scene == Chirp)
  {
    auto a = vtkSmartPointer<vtkFloatArray>::New();
    a->SetNumberOfTuples(n);
    fill(a->GetPointer(0), 1.0);
    scalars = a;
  }
  else if (this->Scene == ThreeSpheres)
  {
    auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
    a->SetNumberOfTuples(n);
    fill(a->GetPointer(0), 200.0);
    scalars = a;
  }
  else
  {
    auto a = vtkSmartPointer<vtkUnsignedShortArray>::New();
    a->SetNumberOfTuples(n);
    fill(a->GetPointer(0), 1000.0);
    scalars = a;
  }
  scalars->SetName("Density");
  output->GetPointData()->SetScalars(scalars);
  return 1;
}

//------------------------------------------------------------------------------
void vtkIlluminationPhantomSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scene: " << this->Scene << "\n";
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
  os << indent << "SlabBegin: " << this->SlabBegin << "\n";
  os << indent << "SlabEnd: " << this->SlabEnd << "\n";
}
