// Helpers shared by the C++ tests: scenes, lights and error capture.
#ifndef IlluminationTestUtilities_h
#define IlluminationTestUtilities_h

#include "IlluminationClassification.h"
#include "IlluminationLights.h"
#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkFloatArray.h"
#include "vtkGenericCell.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkProbeFilter.h"
#include "vtkResampleToImage.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnstructuredGridIllumination.h"
#include "vtkUnstructuredGridReader.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace volillumtest
{

/// Counts the ErrorEvents (vtkErrorMacro) an object raises, and keeps the last message.
class ErrorCounter : public vtkCommand
{
public:
  static ErrorCounter* New() { return new ErrorCounter; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    ++this->Count;
    this->LastMessage = data ? static_cast<const char*>(data) : "";
  }
  int Count = 0;
  std::string LastMessage;
};

/// Aborts the algorithm it observes (ProgressEvent) once progress passes one half.
class AbortHalfway : public vtkCommand
{
public:
  static AbortHalfway* New() { return new AbortHalfway; }
  void Execute(vtkObject* caller, unsigned long, void* data) override
  {
    if (this->Armed && *static_cast<double*>(data) > 0.5)
    {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
      this->Armed = false;
    }
  }
  bool Armed = false;
};

/// A copy of the point array "Illumination" of an updated filter's output.
inline vtkSmartPointer<vtkFloatArray> Result(vtkAlgorithm* filter)
{
  auto copy = vtkSmartPointer<vtkFloatArray>::New();
  copy->DeepCopy(vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0))
                   ->GetPointData()
                   ->GetArray("Illumination"));
  return copy;
}

/// Root-mean-square difference relative to the root-mean-square of the reference.
inline double RmsRelative(vtkFloatArray* got, vtkFloatArray* reference)
{
  double error = 0.0, norm = 0.0;
  for (vtkIdType i = 0; i < got->GetNumberOfValues(); ++i)
  {
    const double d = got->GetValue(i) - reference->GetValue(i);
    error += d * d;
    norm += reference->GetValue(i) * reference->GetValue(i);
  }
  return std::sqrt(error / norm);
}

/// What the mesh-validity tests check of a tetrahedral grid.
struct TetrahedraSummary
{
  bool AllTetrahedra = true;
  int Positive = 0; // tetrahedra with signed volume above 1e-12
  int Negative = 0; // the others (inverted or degenerate)
  double TotalVolume = 0.0;
  double LargestVolume = 0.0;
  int MostCellsPerFace = 0; // a conforming mesh has 1 (boundary) or 2 (interior)
  int BoundaryFaces = 0;
};

inline TetrahedraSummary SummarizeTetrahedra(vtkUnstructuredGrid* grid)
{
  TetrahedraSummary summary;
  std::map<std::array<vtkIdType, 3>, int> faces;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    summary.AllTetrahedra = summary.AllTetrahedra && grid->GetCellType(c) == VTK_TETRA;
    vtkIdType n;
    const vtkIdType* ids;
    grid->GetCellPoints(c, n, ids);
    double p[4][3];
    for (int i = 0; i < 4; ++i)
    {
      grid->GetPoint(ids[i], p[i]);
    }
    double a[3], b[3], d[3];
    for (int k = 0; k < 3; ++k)
    {
      a[k] = p[1][k] - p[0][k];
      b[k] = p[2][k] - p[0][k];
      d[k] = p[3][k] - p[0][k];
    }
    const double volume = (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
                            a[2] * (b[0] * d[1] - b[1] * d[0])) /
      6.0;
    (volume > 1e-12 ? summary.Positive : summary.Negative)++;
    summary.TotalVolume += std::abs(volume);
    summary.LargestVolume = std::max(summary.LargestVolume, std::abs(volume));
    for (int skip = 0; skip < 4; ++skip)
    {
      std::array<vtkIdType, 3> face;
      int k = 0;
      for (int i = 0; i < 4; ++i)
      {
        if (i != skip)
        {
          face[k++] = ids[i];
        }
      }
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
  }
  for (const auto& f : faces)
  {
    summary.MostCellsPerFace = std::max(summary.MostCellsPerFace, f.second);
    summary.BoundaryFaces += f.second == 1 ? 1 : 0;
  }
  return summary;
}

/// Read a .vtu or legacy .vtk unstructured grid; nullptr when the file is missing.
inline vtkSmartPointer<vtkUnstructuredGrid> ReadUnstructuredGrid(const std::string& path)
{
  if (!std::ifstream(path).good())
  {
    return nullptr;
  }
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".vtu") == 0)
  {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    return reader->GetOutput();
  }
  vtkNew<vtkUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

/**
 * Brute-force transmittance of one light at every vertex of a grid: march from the vertex
 * toward the light (to the light or the grid's bounding box) with steps of at most `step`,
 * the extinction interpolated in the cell a cell locator finds (0 outside every cell),
 * trapezoid rule. sigma holds the extinction of every point.
 */
inline std::vector<double> BruteForceTransmittance(vtkUnstructuredGrid* grid,
  const std::vector<double>& sigma, const volillum::LightState& light, double step)
{
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(grid);
  locator->BuildLocator();
  double bounds[6];
  grid->GetBounds(bounds);
  std::vector<double> t(grid->GetNumberOfPoints());
  vtkSMPTools::For(0, grid->GetNumberOfPoints(),
    [&](vtkIdType begin, vtkIdType end)
    {
      vtkNew<vtkGenericCell> cell;
      const auto sigmaAt = [&](double* x)
      {
        int subId;
        double pcoords[3], weights[8];
        const vtkIdType c = locator->FindCell(x, 1e-12, cell, subId, pcoords, weights);
        double s = 0.0;
        for (vtkIdType i = 0; c >= 0 && i < cell->GetNumberOfPoints(); ++i)
        {
          s += weights[i] * sigma[cell->GetPointId(i)];
        }
        return s;
      };
      for (vtkIdType p = begin; p < end; ++p)
      {
        double x[3];
        grid->GetPoint(p, x);
        const volillum::Incidence inc = volillum::ComputeIncidence(light, x);
        const double length =
          std::min(inc.Distance, volillum::DistanceToBoxExit(x, inc.ToLight.data(), bounds));
        const int n = std::max(1, static_cast<int>(std::ceil(length / step)));
        const double h = length / n;
        double depth = 0.0;
        double previous = sigmaAt(x);
        for (int k = 1; k <= n; ++k)
        {
          double q[3] = { x[0] + k * h * inc.ToLight[0], x[1] + k * h * inc.ToLight[1],
            x[2] + k * h * inc.ToLight[2] };
          const double s = sigmaAt(q);
          depth += 0.5 * h * (previous + s);
          previous = s;
        }
        t[p] = std::exp(-depth);
      }
    });
  return t;
}

/// A result's error against a reference per point (channel `channel` of got).
struct Errors
{
  double Rms = 0.0; // RMS difference relative to the RMS of the reference
  double Max = 0.0; // largest absolute difference
};

inline Errors Compare(vtkDataArray* got, const std::vector<double>& reference, int channel = 0)
{
  double error = 0.0, norm = 0.0;
  Errors e;
  for (size_t p = 0; p < reference.size(); ++p)
  {
    const double d = got->GetComponent(static_cast<vtkIdType>(p), channel) - reference[p];
    error += d * d;
    norm += reference[p] * reference[p];
    e.Max = std::max(e.Max, std::abs(d));
  }
  e.Rms = std::sqrt(error / norm);
  return e;
}

/// The extinction at every point of a grid as the filters classify its active scalars: the
/// opacity of a sample one unit distance thick, sigma = -ln(1 - opacity) / unitDistance.
inline std::vector<double> ExtinctionOfScalars(
  vtkDataSet* grid, vtkPiecewiseFunction* otf, double unitDistance)
{
  vtkDataArray* scalars = grid->GetPointData()->GetScalars();
  std::vector<double> sigma(grid->GetNumberOfPoints());
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    const double a = std::min(otf->GetValue(scalars->GetTuple1(p)), volillum::MaximumOpacity);
    sigma[p] = -std::log1p(-a) / unitDistance;
  }
  return sigma;
}

/// A phantom of the given scene (vtkIlluminationPhantomSource) with n points per axis.
inline vtkSmartPointer<vtkImageData> PhantomScene(int scene, int n)
{
  vtkNew<vtkIlluminationPhantomSource> source;
  source->SetScene(scene);
  source->SetDimensions(n, n, n);
  source->SetSlabBegin(n / 4);
  source->SetSlabEnd(3 * n / 4 - 1);
  source->Update();
  return source->GetOutput();
}

/// Opacity rising linearly from 0 to maximum over the image's scalar range.
inline vtkSmartPointer<vtkPiecewiseFunction> RampOpacity(vtkImageData* image, double maximum)
{
  double range[2];
  image->GetPointData()->GetScalars()->GetRange(range);
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  otf->AddPoint(range[0], 0.0);
  otf->AddPoint(range[1], maximum);
  return otf;
}

/// An image illumination filter of the given class on image with opacity otf.
template <typename Filter>
vtkSmartPointer<Filter> ImageFilter(vtkImageData* image, vtkPiecewiseFunction* otf)
{
  auto filter = vtkSmartPointer<Filter>::New();
  filter->SetInputData(image);
  filter->SetOpacityFunction(otf);
  return filter;
}

inline vtkSmartPointer<vtkLight> DirectionalLight(
  double dx, double dy, double dz, double r = 1, double g = 1, double b = 1)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetPositional(false);
  light->SetPosition(0, 0, 0);
  light->SetFocalPoint(dx, dy, dz);
  light->SetDiffuseColor(r, g, b);
  return light;
}

inline vtkSmartPointer<vtkLight> PointLight(
  double x, double y, double z, double r = 1, double g = 1, double b = 1)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetPositional(true);
  light->SetConeAngle(180);
  light->SetPosition(x, y, z);
  light->SetFocalPoint(32, 32, 32);
  light->SetDiffuseColor(r, g, b);
  return light;
}

/// An opacity over a scalar range: clear at its low end, 0.02 at 15 %, 0.2 at 50 %, 0.6 at
/// its top.
inline vtkSmartPointer<vtkPiecewiseFunction> RisingOpacity(const double range[2])
{
  auto otf = vtkSmartPointer<vtkPiecewiseFunction>::New();
  const double w = range[1] - range[0];
  otf->AddPoint(range[0], 0.0);
  otf->AddPoint(range[0] + 0.15 * w, 0.02);
  otf->AddPoint(range[0] + 0.5 * w, 0.2);
  otf->AddPoint(range[1], 0.6);
  return otf;
}

/// The scene volillum-unstructured-benchmark compares the ways of lighting an unstructured
/// grid in: RisingOpacity over its scalars, a unit distance of 1/8 of its largest extent
/// (a thin medium: most vertices see some light), one oblique directional light, and the
/// brute-force transmittance at every vertex (steps of `steps`-th of the largest extent).
struct MeshComparisonScene
{
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
  double UnitDistance = 1.0;
  vtkSmartPointer<vtkLight> Light;
  std::vector<double> Reference;
};

inline MeshComparisonScene ComparisonScene(vtkUnstructuredGrid* grid, int steps)
{
  MeshComparisonScene scene;
  double range[2], bounds[6];
  grid->GetPointData()->GetScalars()->GetRange(range);
  grid->GetBounds(bounds);
  const double extent =
    std::max(bounds[1] - bounds[0], std::max(bounds[3] - bounds[2], bounds[5] - bounds[4]));
  scene.Opacity = RisingOpacity(range);
  scene.UnitDistance = extent / 8.0;
  scene.Light = DirectionalLight(0.4, 0.3, -1);
  scene.Reference =
    BruteForceTransmittance(grid, ExtinctionOfScalars(grid, scene.Opacity, scene.UnitDistance),
      volillum::CaptureLight(scene.Light), extent / steps);
  return scene;
}

/// The other way to light an unstructured grid: resampled onto a regular grid of
/// resolution^3 points (vtkResampleToImage), lit there by vtkMultiLightIlluminationVolume
/// and probed back at the grid's points. Returns the probed Illumination.
inline vtkSmartPointer<vtkDataArray> ResampledIllumination(vtkUnstructuredGrid* grid,
  vtkPiecewiseFunction* otf, double unitDistance, vtkLight* light, int resolution)
{
  vtkNew<vtkResampleToImage> resample;
  resample->SetInputDataObject(grid);
  resample->SetSamplingDimensions(resolution, resolution, resolution);
  resample->Update();
  vtkImageData* image = resample->GetOutput();
  image->GetPointData()->SetActiveScalars(grid->GetPointData()->GetScalars()->GetName());
  vtkNew<vtkMultiLightIlluminationVolume> propagation;
  propagation->SetInputData(image);
  propagation->SetOpacityFunction(otf);
  propagation->SetScalarOpacityUnitDistance(unitDistance);
  propagation->AddLight(light);
  vtkNew<vtkProbeFilter> probe;
  probe->SetInputData(grid);
  probe->SetSourceConnection(propagation->GetOutputPort());
  probe->Update();
  return probe->GetOutput()->GetPointData()->GetArray("Illumination");
}

/// vtkUnstructuredGridIllumination lighting a grid's comparison scene (not updated yet): a
/// level-0 grid of resolution^3 points and Level1Iterations `iterations`.
inline vtkSmartPointer<vtkUnstructuredGridIllumination> SceneIllumination(
  vtkUnstructuredGrid* grid, const MeshComparisonScene& scene, int resolution, int iterations)
{
  auto filter = vtkSmartPointer<vtkUnstructuredGridIllumination>::New();
  filter->SetInputData(grid);
  filter->SetOpacityFunction(scene.Opacity);
  filter->SetScalarOpacityUnitDistance(scene.UnitDistance);
  filter->SetLevel0Resolution(resolution, resolution, resolution);
  filter->SetLevel1Iterations(iterations);
  filter->AddLight(scene.Light);
  return filter;
}

}

#endif
