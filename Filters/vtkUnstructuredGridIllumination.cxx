#include "vtkUnstructuredGridIllumination.h"

#include "IlluminationClassify.h"
#include "IlluminationFilterSupport.h"
#include "IlluminationLightingMacros.h"
#include "IlluminationParallel.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLight.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <chrono>
#include <cmath>

vtkStandardNewMacro(vtkUnstructuredGridIllumination);
volillumLightingImplementationMacro(vtkUnstructuredGridIllumination);

namespace
{
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The transmittance of a light depends on where light comes from, not on its colour,
// intensity, switch or spot cone (the cone is applied when lights are combined).
bool SameGeometry(const volillum::LightState& a, const volillum::LightState& b)
{
  const bool positional = a.Kind != volillum::LightKind::Directional;
  if (positional != (b.Kind != volillum::LightKind::Directional))
  {
    return false;
  }
  return positional ? a.Position == b.Position : a.Direction() == b.Direction();
}

void AddSeconds(vtkFieldData* fieldData, const char* name, double seconds)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->InsertNextValue(seconds);
  fieldData->AddArray(array);
}
}

//------------------------------------------------------------------------------
vtkUnstructuredGridIllumination::vtkUnstructuredGridIllumination()
  : Distributed(new volillum::DistributedInput)
{
  this->SetController(vtkMultiProcessController::GetGlobalController());
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkUnstructuredGridIllumination::~vtkUnstructuredGridIllumination()
{
  this->SetColorTransferFunction(nullptr);
  this->SetOpacityFunction(nullptr);
  this->SetController(nullptr);
}

//------------------------------------------------------------------------------
vtkCxxSetObjectMacro(vtkUnstructuredGridIllumination, Controller, vtkMultiProcessController);

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::PrepareMesh(vtkUnstructuredGrid* input)
{
  const vtkMTimeType key = std::max(input->GetPoints()->GetMTime(), input->GetCells()->GetMTime());
  if (key == this->MeshKey && this->Mesh.NumberOfPoints() == input->GetNumberOfPoints())
  {
    return true;
  }
  this->MeshKey = 0;
  this->SolutionKey.clear();
  this->Cache.clear();

  // Point ids outside the grid would be read (and split) as if they were points.
  const std::string badIds = volillum::CheckPointIds(input);
  if (!badIds.empty())
  {
    vtkErrorMacro(<< badIds);
    return false;
  }

  vtkSmartPointer<vtkUnstructuredGrid> tetrahedra = input;
  bool onlyTetrahedra = true;
  for (vtkIdType c = 0; c < input->GetNumberOfCells() && onlyTetrahedra; ++c)
  {
    onlyTetrahedra = input->GetCellType(c) == VTK_TETRA;
  }
  if (!volillum::HasSolidCells(input))
  {
    vtkErrorMacro("The input has no 3D cells to light.");
    return false;
  }
  if (!onlyTetrahedra)
  {
    vtkNew<vtkUnstructuredGrid> copy;
    copy->CopyStructure(input);
    vtkNew<vtkDataSetTriangleFilter> split;
    split->TetrahedraOnlyOn();
    split->SetInputData(copy);
    split->Update();
    tetrahedra = split->GetOutput();
    if (tetrahedra->GetNumberOfPoints() != input->GetNumberOfPoints())
    {
      vtkErrorMacro("Splitting the cells into tetrahedra changed the points; cannot light "
                    "this grid.");
      return false;
    }
  }

  std::vector<double> points(3 * static_cast<size_t>(input->GetNumberOfPoints()));
  for (vtkIdType p = 0; p < input->GetNumberOfPoints(); ++p)
  {
    input->GetPoint(p, points.data() + 3 * p);
  }
  std::vector<long long> tets;
  tets.reserve(4 * static_cast<size_t>(tetrahedra->GetNumberOfCells()));
  auto cells = vtk::TakeSmartPointer(tetrahedra->GetCells()->NewIterator());
  vtkIdType c = 0;
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    cells->GetCurrentCell(n, ids);
    if (tetrahedra->GetCellType(c) == VTK_TETRA && n == 4)
    {
      tets.insert(tets.end(), ids, ids + 4);
    }
  }
  std::string error;
  if (!volillum::BuildTetrahedralMesh(std::move(points), tets, this->Mesh, error))
  {
    vtkErrorMacro("Cannot light the grid: " << error << ".");
    return false;
  }
  this->Coloring = volillum::ColorVertices(this->Mesh);
  this->MeshKey = key;
  return true;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::Classify(vtkDataArray* scalars)
{
  volillum::ClassificationSettings settings;
  settings.Color = this->ColorTransferFunction;
  settings.Opacity = this->OpacityFunction;
  settings.UnitDistance = this->ScalarOpacityUnitDistance;
  settings.Chromatic = this->ChromaticAttenuation;
  // One "grid point" per vertex: the classification is pointwise.
  volillum::GridGeometry vertices;
  vertices.Dimensions = { { static_cast<int>(scalars->GetNumberOfTuples()), 1, 1 } };
  volillum::ClassifiedVolume classified;
  std::string error;
  long long nans = 0;
  if (!volillum::Classify(scalars, vertices, settings, classified, error, &nans))
  {
    vtkErrorMacro("Cannot classify the input: " << error << ".");
    return false;
  }
  if (nans > 0)
  {
    vtkWarningMacro(<< nans << " scalar values are NaN; they are treated as empty space.");
  }
  const int nc = this->ChromaticAttenuation ? 3 : 1;
  const size_t np = static_cast<size_t>(scalars->GetNumberOfTuples());
  this->Channels = nc;
  this->Extinction.resize(np * nc);
  for (size_t p = 0; p < np; ++p)
  {
    const size_t first = classified.Channels * p;
    const double sigma = this->Absorption * classified.Value(first);
    for (int c = 0; c < nc; ++c)
    {
      const double absorb = nc == 3 ? classified.Value(first + 1 + c) : 1.0;
      this->Extinction[nc * p + c] = static_cast<float>(sigma * absorb);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnsignedCharArray> vtkUnstructuredGridIllumination::ShadeVertices(
  vtkDataArray* scalars, const std::vector<float>& rgb)
{
  double range[2];
  scalars->GetRange(range);
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetName("LitColors");
  colors->SetNumberOfComponents(4);
  colors->SetNumberOfTuples(scalars->GetNumberOfTuples());
  const auto toByte = [](double v)
  { return static_cast<unsigned char>(std::lround(255.0 * std::min(std::max(v, 0.0), 1.0))); };
  for (vtkIdType p = 0; p < scalars->GetNumberOfTuples(); ++p)
  {
    const double s = scalars->GetComponent(p, 0);
    double color[3];
    double opacity = 0.0;
    if (std::isnan(s))
    {
      color[0] = color[1] = color[2] = 0.0;
    }
    else if (this->ColorTransferFunction)
    {
      this->ColorTransferFunction->GetColor(s, color);
    }
    else
    {
      color[0] = color[1] = color[2] = (s - range[0]) / width; // the grey default ramp
    }
    if (!std::isnan(s))
    {
      opacity = this->OpacityFunction ? this->OpacityFunction->GetValue(s) : (s - range[0]) / width;
    }
    for (int c = 0; c < 3; ++c)
    {
      colors->SetTypedComponent(p, c, toByte(color[c] * rgb[3 * p + c]));
    }
    colors->SetTypedComponent(p, 3, toByte(opacity));
  }
  return colors;
}

//------------------------------------------------------------------------------
int vtkUnstructuredGridIllumination::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  output->Initialize();
  vtkMultiProcessController* controller = volillum::ParallelRun(this->Controller);
  if (!controller)
  {
    this->Illuminate(input, output);
    return 1;
  }
  // Light crosses every piece: light the whole grid, give this piece its points' values.
  vtkUnstructuredGrid* whole = this->Distributed->Grid(controller, this, input);
  vtkNew<vtkUnstructuredGrid> illuminated;
  this->Illuminate(whole, illuminated);
  if (!input || input->GetNumberOfPoints() == 0 || illuminated->GetNumberOfPoints() == 0)
  {
    return 1;
  }
  output->ShallowCopy(input);
  volillum::AddPointValues(
    illuminated, this->Distributed->PiecePoints(), { "Illumination", "LitColors" }, output);
  vtkNew<vtkFieldData> fieldData;
  fieldData->ShallowCopy(illuminated->GetFieldData());
  output->SetFieldData(fieldData);
  return 1;
}

//------------------------------------------------------------------------------
void vtkUnstructuredGridIllumination::Illuminate(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  const auto start = Clock::now();
  if (!this->CheckInput(input))
  {
    return;
  }
  PhaseSeconds seconds;
  const auto meshStart = Clock::now();
  if (!this->PrepareMesh(input))
  {
    return;
  }
  seconds.Mesh = SecondsSince(meshStart);
  this->UpdateProgress(0.1);
  volillum::UpdateReport report;
  report.Mode = 1;
  const auto resampleStart = Clock::now();
  if (!this->UpdateLevel0Grid(report))
  {
    return;
  }
  seconds.Resample = SecondsSince(resampleStart);

  const std::vector<volillum::LightState> lights =
    volillum::ForBounds(this->Lights.States(), input->GetBounds());
  if (!this->PropagateChangedLights(lights, report, seconds))
  {
    if (this->LastOutput)
    {
      output->ShallowCopy(this->LastOutput);
    }
    return;
  }
  std::vector<const std::vector<float>*> rho(lights.size(), nullptr);
  for (size_t l = 0; l < lights.size(); ++l)
  {
    if (lights[l].On)
    {
      rho[l] = &this->Cache[l].Rho;
    }
  }
  std::vector<float> rgb;
  volillum::CombineLights(this->Mesh, lights, rho, this->Channels, rgb);
  const auto scatterStart = Clock::now();
  volillum::Scatter(this->Mesh, this->Coloring,
    { { this->ScatteringStrength[0], this->ScatteringStrength[1], this->ScatteringStrength[2] } },
    this->ScatteringIterations, rgb);
  seconds.Scattering = SecondsSince(scatterStart);
  seconds.Update = SecondsSince(start);
  this->FillOutput(input, rgb, report, seconds, output);
  this->UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::CheckInput(vtkUnstructuredGrid* input)
{
  if (!input || input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0)
  {
    vtkErrorMacro("The input grid has no "
      << (input && input->GetNumberOfPoints() > 0 ? "cells" : "points") << ".");
    return false;
  }
  std::string error;
  this->Scalars = volillum::CheckScalarsAndLights(
    this, input, this->ScalarComponent, this->Scalars, this->Lights, error);
  if (!this->Scalars.Array)
  {
    vtkErrorMacro(<< error);
    return false;
  }
  if (!std::isfinite(this->Absorption) || !std::isfinite(this->ScatteringStrength[0]) ||
    !std::isfinite(this->ScatteringStrength[1]) || !std::isfinite(this->ScatteringStrength[2]))
  {
    vtkErrorMacro("Absorption and ScatteringStrength must be finite numbers.");
    return false;
  }
  // Each axis is checked before the product (three huge axes would overflow it).
  const int* r = this->Level0Resolution;
  const auto axisOk = [](int n) { return n >= 2 && n <= MaximumLevel0Axis; };
  if (!axisOk(r[0]) || !axisOk(r[1]) || !axisOk(r[2]) ||
    static_cast<long long>(r[0]) * r[1] * r[2] > MaximumLevel0Points)
  {
    vtkErrorMacro("Level0Resolution must be 2 to "
      << MaximumLevel0Axis << " points per axis and at most " << MaximumLevel0Points
      << " points in all; it is " << r[0] << " x " << r[1] << " x " << r[2] << ".");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::UpdateLevel0Grid(volillum::UpdateReport& report)
{
  const std::vector<double> solutionKey = { static_cast<double>(this->MeshKey),
    static_cast<double>(this->Scalars.Time), static_cast<double>(this->ScalarComponent),
    static_cast<double>(this->ColorTransferFunction ? this->ColorTransferFunction->GetMTime() : 0),
    static_cast<double>(this->OpacityFunction ? this->OpacityFunction->GetMTime() : 0),
    this->ScalarOpacityUnitDistance, this->ChromaticAttenuation ? 1.0 : 0.0, this->Absorption,
    static_cast<double>(this->Level0Resolution[0]), static_cast<double>(this->Level0Resolution[1]),
    static_cast<double>(this->Level0Resolution[2]), static_cast<double>(this->Level1Iterations) };
  if (solutionKey != this->SolutionKey)
  {
    this->SolutionKey.clear();
    this->Cache.clear();
    report.Mode = 0;
    if (!this->Classify(this->Scalars.Array))
    {
      return false;
    }
    const std::array<int, 3> dims = { { this->Level0Resolution[0], this->Level0Resolution[1],
      this->Level0Resolution[2] } };
    volillum::ResampleLevel0(this->Mesh, this->Extinction, this->Channels, dims, this->Level0);
    this->SolutionKey = solutionKey;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::PropagateChangedLights(
  const std::vector<volillum::LightState>& lights, volillum::UpdateReport& report,
  PhaseSeconds& seconds)
{
  // Lights whose transmittance is missing or was computed for another geometry.
  this->Cache.resize(lights.size());
  std::vector<int> stale;
  for (size_t l = 0; l < lights.size(); ++l)
  {
    LightCache& cache = this->Cache[l];
    if (lights[l].On && !(cache.Valid && SameGeometry(cache.State, lights[l])))
    {
      stale.push_back(static_cast<int>(l));
    }
  }
  if (stale.size() == lights.size())
  {
    report.Mode = 0;
  }
  report.Passes = static_cast<int>(stale.size());

  // Lights in batches of as many as there are threads: level 0 of a batch runs one light
  // per thread (the upwind pass of one light is sequential), then level 1 of each light
  // runs in parallel over its vertices. Batches bound the memory of level-0 solutions.
  const int iterations = this->Level1Iterations >= 0
    ? this->Level1Iterations
    : volillum::AutomaticLevel1Iterations(this->Mesh, this->Level0);
  const size_t batch = static_cast<size_t>(std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads()));
  std::vector<std::vector<float>> level0(batch);
  for (size_t first = 0; first < stale.size(); first += batch)
  {
    const int count = static_cast<int>(std::min(batch, stale.size() - first));
    const auto level0Start = Clock::now();
    vtkSMPTools::For(0, count,
      [&](int begin, int end)
      {
        for (int b = begin; b < end; ++b)
        {
          volillum::PropagateLevel0(this->Level0, lights[stale[first + b]], level0[b]);
        }
      });
    seconds.Level0 += SecondsSince(level0Start);
    const auto level1Start = Clock::now();
    for (int b = 0; b < count; ++b)
    {
      this->UpdateProgress(0.1 + 0.8 * (first + b) / stale.size());
      if (this->GetAbortExecute())
      {
        return false;
      }
      LightCache& cache = this->Cache[stale[first + b]];
      cache.Valid = false;
      volillum::PropagateLevel1(this->Mesh, this->Extinction, this->Level0, level0[b],
        lights[stale[first + b]], 0.0, iterations, cache.Rho);
      cache.State = lights[stale[first + b]];
      cache.Valid = true;
    }
    seconds.Level1 += SecondsSince(level1Start);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkUnstructuredGridIllumination::FillOutput(vtkUnstructuredGrid* input,
  const std::vector<float>& rgb, const volillum::UpdateReport& report, const PhaseSeconds& seconds,
  vtkUnstructuredGrid* output)
{
  vtkNew<vtkFloatArray> illumination;
  illumination->SetName("Illumination");
  illumination->SetNumberOfComponents(3);
  illumination->SetNumberOfTuples(input->GetNumberOfPoints());
  std::copy(rgb.begin(), rgb.end(), illumination->GetPointer(0));
  output->ShallowCopy(input);
  output->GetPointData()->AddArray(illumination);
  if (this->LitColors)
  {
    output->GetPointData()->AddArray(this->ShadeVertices(this->Scalars.Array, rgb));
  }
  vtkFieldData* fieldData = vtkFieldData::New();
  fieldData->ShallowCopy(input->GetFieldData());
  output->SetFieldData(fieldData);
  fieldData->Delete();
  volillum::AddUpdateFieldData(output->GetFieldData(), report, seconds.Update);
  AddSeconds(output->GetFieldData(), "MeshSeconds", seconds.Mesh);
  AddSeconds(output->GetFieldData(), "ResampleSeconds", seconds.Resample);
  AddSeconds(output->GetFieldData(), "Level0Seconds", seconds.Level0);
  AddSeconds(output->GetFieldData(), "Level1Seconds", seconds.Level1);
  AddSeconds(output->GetFieldData(), "ScatteringSeconds", seconds.Scattering);
  this->LastOutput = vtkSmartPointer<vtkUnstructuredGrid>::New();
  this->LastOutput->ShallowCopy(output);
}

//------------------------------------------------------------------------------
void vtkUnstructuredGridIllumination::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Lights: " << this->Lights.Size() << "\n";
  os << indent << "Level0Resolution: " << this->Level0Resolution[0] << " "
     << this->Level0Resolution[1] << " " << this->Level0Resolution[2] << "\n";
  os << indent << "ScalarComponent: " << this->ScalarComponent << "\n";
  os << indent << "Absorption: " << this->Absorption << "\n";
  os << indent << "Level1Iterations: " << this->Level1Iterations << "\n";
  os << indent << "ScatteringStrength: " << this->ScatteringStrength[0] << " "
     << this->ScatteringStrength[1] << " " << this->ScatteringStrength[2] << "\n";
  os << indent << "ScatteringIterations: " << this->ScatteringIterations << "\n";
  os << indent << "ScalarOpacityUnitDistance: " << this->ScalarOpacityUnitDistance << "\n";
  os << indent << "ChromaticAttenuation: " << this->ChromaticAttenuation << "\n";
  os << indent << "LitColors: " << this->LitColors << "\n";
}
