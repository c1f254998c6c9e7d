#include "vtkUnstructuredGridIllumination.h"

#include "DistributedMesh.h"
#include "IlluminationClassify.h"
#include "IlluminationFilterSupport.h"
#include "IlluminationLightingMacros.h"
#include "IlluminationTetrahedra.h"
#include "NeighborhoodGrid.h"
#include "ParallelCollectives.h"
#include "ParallelMessages.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLight.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>

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

// Why a piece's points cannot join the others' ("" when they can).
std::string BadCoordinate(vtkUnstructuredGrid* piece)
{
  const vtkIdType bad = volillum::FirstBadCoordinate(
    piece && piece->GetPoints() ? piece->GetPoints()->GetData() : nullptr,
    volillum::MaximumCoordinate);
  if (bad < 0)
  {
    return std::string();
  }
  std::ostringstream message;
  message << "Point " << bad << " of this process's piece has a coordinate that is not a "
          << "finite number within +-" << volillum::MaximumCoordinate << ".";
  return message.str();
}
}

//------------------------------------------------------------------------------
vtkUnstructuredGridIllumination::vtkUnstructuredGridIllumination()
  : Neighborhood(new volillum::NeighborhoodGrid)
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
vtkSmartPointer<vtkUnstructuredGrid> vtkUnstructuredGridIllumination::JoinedStructure(
  vtkUnstructuredGrid* input, vtkUnsignedCharArray* ghosts)
{
  // Copies of a point (a file of several pieces holds one per piece on a cut) are one point,
  // as the pieces of a parallel run are joined: the cells of every copy use the first, before
  // any cell is split (so that both sides of a cut split their faces alike). Ghost cells
  // (another piece's) are left out, as in a parallel run.
  this->FirstAtPlace = volillum::FirstPointsAtTheirPlaces(input);
  bool copies = false;
  for (vtkIdType p = 0; p < input->GetNumberOfPoints() && !copies; ++p)
  {
    copies = this->FirstAtPlace[p] != p;
  }
  if (!copies)
  {
    this->FirstAtPlace.clear();
  }
  auto structure = vtkSmartPointer<vtkUnstructuredGrid>::New();
  if (!copies && !ghosts)
  {
    structure->CopyStructure(input);
  }
  else
  {
    structure->SetPoints(input->GetPoints());
    structure->AllocateEstimate(input->GetNumberOfCells(), 4);
    vtkNew<vtkIdList> cell;
    for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
    {
      if (ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL))
      {
        continue;
      }
      const int type = input->GetCellType(c);
      volillum::CellWithMappedPoints(input, c, copies ? &this->FirstAtPlace : nullptr, cell);
      structure->InsertNextCell(type, cell);
    }
  }
  return structure;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::PrepareMesh(vtkUnstructuredGrid* input, vtkIdType own)
{
  // The mesh depends on the points, the cells, the point global ids (which copies of a point
  // are one) and the ghost cells (left out).
  vtkDataArray* globalIds = input->GetPointData()->GetGlobalIds();
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  const vtkMTimeType key = std::max({ input->GetPoints()->GetMTime(), input->GetCells()->GetMTime(),
    globalIds ? globalIds->GetMTime() : 0, ghosts ? ghosts->GetMTime() : 0 });
  if (key == this->MeshKey && this->Mesh.NumberOfPoints() == input->GetNumberOfPoints() &&
    this->MeshArrays[0] == globalIds && this->MeshArrays[1] == ghosts)
  {
    return true;
  }
  this->MeshArrays[0] = globalIds;
  this->MeshArrays[1] = ghosts;
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
  if (own < 0 && !volillum::HasSolidCells(input))
  {
    vtkErrorMacro("The input has no 3D cells to light.");
    return false;
  }
  vtkSmartPointer<vtkUnstructuredGrid> structure = this->JoinedStructure(input, ghosts);
  std::string error;
  vtkSmartPointer<vtkUnstructuredGrid> tetrahedra = volillum::SplitIntoTetrahedra(structure, error);
  if (!tetrahedra)
  {
    vtkErrorMacro(<< error);
    return false;
  }

  std::vector<double> points(3 * static_cast<size_t>(input->GetNumberOfPoints()));
  for (vtkIdType p = 0; p < input->GetNumberOfPoints(); ++p)
  {
    input->GetPoint(p, points.data() + 3 * p);
  }
  const std::vector<long long> tets = volillum::TetrahedronPointIds(tetrahedra);
  if (!volillum::BuildTetrahedralMesh(std::move(points), tets, this->Mesh, error, own))
  {
    vtkErrorMacro("Cannot light the grid: " << error << ".");
    return false;
  }
  if (own < 0)
  {
    this->Coloring = volillum::ColorVertices(this->Mesh);
  }
  this->MeshKey = key;
  return true;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::PrepareDistributedMesh(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* input)
{
  // This piece's tetrahedra with the arrays that light them. Pieces whose coordinates or
  // arrays cannot join the others' are refused before any cell travels.
  std::string error;
  vtkSmartPointer<vtkUnstructuredGrid> own = volillum::PieceTetrahedra(
    volillum::PieceWithoutGhostCells(volillum::LitArrayName(this), input), error);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
  }
  if (!volillum::AllOk(controller, error.empty()))
  {
    return false;
  }
  error = BadCoordinate(own);
  if (!volillum::PiecesCanJoin(controller, own, error))
  {
    if (!error.empty())
    {
      vtkErrorMacro(<< error);
    }
    this->Neighborhood->Reset();
    this->MeshKey = 0;
    return false;
  }
  // How deep the cells of other pieces are needed: the level-1 walk from a point of the piece
  // (Level1Length), and at least a mean edge (the scattering's neighbours).
  const std::array<int, 3> dims = this->Level0Dimensions();
  const auto reach = [&](const volillum::TetrahedralMesh& mesh)
  {
    const double walk = volillum::Level1Length(
      mesh, volillum::Level0Geometry(mesh.Bounds, dims), this->Level1Iterations);
    return 1.01 * std::max(walk, mesh.MeanEdgeLength);
  };
  if (!this->Neighborhood->Changed(controller, own) && this->MeshKey != 0 &&
    reach(this->Mesh) <= this->NeighborhoodDepth)
  {
    return true; // no piece changed and the walk stays inside: the mesh and its colours stand
  }

  // Estimated from the tetrahedra's edges and the pieces' bounds, checked below with the
  // whole mesh's mean edge.
  volillum::TetrahedralMesh estimate;
  estimate.MeanEdgeLength = volillum::MeanTetrahedronEdge(controller, own);
  if (estimate.MeanEdgeLength < 0.0)
  {
    vtkErrorMacro("The input has no 3D cells to light.");
    return false;
  }
  volillum::UnionOfBounds(controller, own, estimate.Bounds);
  double depth = 1.1 * reach(estimate);
  for (;;)
  {
    vtkUnstructuredGrid* grid = this->Neighborhood->Build(controller, own, depth);
    if (!volillum::AllOk(
          controller, this->PrepareMesh(grid, this->Neighborhood->GetNumberOfPieceCells())) ||
      !volillum::AgreeOnWholeMesh(controller, this->Mesh, this->Neighborhood->GetOwned(), error))
    {
      if (!error.empty())
      {
        vtkErrorMacro(<< error);
      }
      this->Neighborhood->Reset();
      this->MeshKey = 0;
      return false;
    }
    if (reach(this->Mesh) > depth)
    {
      depth = 1.2 * reach(this->Mesh); // the estimate fell short: gather deeper
      continue;
    }
    this->NeighborhoodDepth = depth;
    // Colours as a single process gives them.
    if (!volillum::ColorDistributedVertices(
          controller, *this->Neighborhood, this->Mesh, this->Coloring, error))
    {
      vtkErrorMacro(<< error);
      this->Neighborhood->Reset();
      this->MeshKey = 0;
      return false;
    }
    return true;
  }
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::Classify(vtkDataArray* scalars, const double* range)
{
  volillum::ClassificationSettings settings;
  settings.Range = range;
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
  vtkDataArray* scalars, const std::vector<float>& rgb, vtkIdType points)
{
  double range[2];
  if (volillum::ParallelRun(this->Controller))
  {
    std::copy_n(this->WholeRange, 2, range);
  }
  else
  {
    scalars->GetRange(range);
  }
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetName("LitColors");
  colors->SetNumberOfComponents(4);
  colors->SetNumberOfTuples(points);
  const auto toByte = [](double v)
  { return static_cast<unsigned char>(std::lround(255.0 * std::min(std::max(v, 0.0), 1.0))); };
  for (vtkIdType p = 0; p < points; ++p)
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
      const double light = rgb[3 * p + c];
      const double shade = this->Exposure > 0 ? 1.0 - std::exp(-this->Exposure * light) : light;
      colors->SetTypedComponent(p, c, toByte(color[c] * shade));
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
  if (controller)
  {
    // Every process's errors reach the first process, which a client shows.
    volillum::ParallelMessages messages(controller, this);
    this->IlluminatePiece(controller, input, output);
  }
  else
  {
    this->Illuminate(input, output);
  }
  return 1;
}

//------------------------------------------------------------------------------
std::array<int, 3> vtkUnstructuredGridIllumination::Level0Dimensions() const
{
  return { { this->Level0Resolution[0], this->Level0Resolution[1], this->Level0Resolution[2] } };
}

//------------------------------------------------------------------------------
void vtkUnstructuredGridIllumination::Illuminate(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  const auto start = Clock::now();
  if (!this->CheckSettings() || !this->CheckInput(input))
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
  if (!this->PropagateChangedLights(lights, report, seconds, nullptr))
  {
    if (this->LastOutput)
    {
      output->ShallowCopy(this->LastOutput);
    }
    return;
  }
  std::vector<float> rgb = this->CombineAndScatter(lights, seconds, {});
  seconds.Update = SecondsSince(start);
  this->FillOutput(input, std::move(rgb), report, seconds, output);
  this->UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
void vtkUnstructuredGridIllumination::IlluminatePiece(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  const auto start = Clock::now();
  if (!volillum::AllOk(controller, this->CheckSettings()))
  {
    return;
  }
  PhaseSeconds seconds;
  if (!this->PrepareDistributedMesh(controller, input))
  {
    return;
  }
  seconds.Mesh = SecondsSince(start);
  vtkUnstructuredGrid* grid = this->Neighborhood->GetGrid();
  const bool lit = grid->GetNumberOfPoints() > 0;
  if (!lit)
  {
    this->Scalars = volillum::PointScalars();
  }
  if (!volillum::AllOk(controller, !lit || this->CheckInput(grid, false)))
  {
    return;
  }
  this->UpdateProgress(0.1);
  volillum::UpdateReport report;
  report.Mode = 1;
  const auto resampleStart = Clock::now();
  if (!this->UpdateLevel0Grid(report, controller))
  {
    return;
  }
  seconds.Resample = SecondsSince(resampleStart);

  // The lights placed for the bounds of the whole grid (of all pieces' points).
  volillum::UnionOfBounds(controller, input, this->WholeBounds);
  const std::vector<volillum::LightState> lights =
    volillum::ForBounds(this->Lights.States(), this->WholeBounds);
  this->PropagateChangedLights(lights, report, seconds, this->Neighborhood.get());
  // After each colour, the new values of this process's points go to those that read them.
  std::vector<float> rgb = this->CombineAndScatter(lights, seconds,
    [this](std::vector<float>& values) { this->Neighborhood->Exchange(values.data(), 3); });
  seconds.Update = SecondsSince(start);
  if (lit && input->GetNumberOfPoints() == this->Neighborhood->GetNumberOfPiecePoints())
  {
    this->FillOutput(input, std::move(rgb), report, seconds, output);
  }
  this->UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
std::vector<float> vtkUnstructuredGridIllumination::CombineAndScatter(
  const std::vector<volillum::LightState>& lights, PhaseSeconds& seconds,
  const std::function<void(std::vector<float>&)>& afterColor)
{
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
  std::function<void(int)> exchange;
  if (afterColor)
  {
    exchange = [&](int) { afterColor(rgb); };
  }
  volillum::Scatter(this->Mesh, this->Coloring,
    { { this->ScatteringStrength[0], this->ScatteringStrength[1], this->ScatteringStrength[2] } },
    this->ScatteringIterations, rgb, exchange);
  seconds.Scattering = SecondsSince(scatterStart);
  return rgb;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::CheckInput(vtkUnstructuredGrid* input, bool needCells)
{
  if (!input || input->GetNumberOfPoints() == 0 || (needCells && input->GetNumberOfCells() == 0))
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
  return true;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::CheckSettings()
{
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
bool vtkUnstructuredGridIllumination::UpdateLevel0Grid(
  volillum::UpdateReport& report, vtkMultiProcessController* controller)
{
  const std::vector<double> solutionKey = { static_cast<double>(this->MeshKey),
    static_cast<double>(this->Scalars.Time), static_cast<double>(this->ScalarComponent),
    static_cast<double>(this->ColorTransferFunction ? this->ColorTransferFunction->GetMTime() : 0),
    static_cast<double>(this->OpacityFunction ? this->OpacityFunction->GetMTime() : 0),
    this->ScalarOpacityUnitDistance, this->ChromaticAttenuation ? 1.0 : 0.0, this->Absorption,
    static_cast<double>(this->Level0Resolution[0]), static_cast<double>(this->Level0Resolution[1]),
    static_cast<double>(this->Level0Resolution[2]), static_cast<double>(this->Level1Iterations) };
  int changed = solutionKey != this->SolutionKey;
  if (controller)
  {
    int any = 0;
    controller->AllReduce(&changed, &any, 1, vtkCommunicator::LOGICAL_OR_OP);
    changed = any;
  }
  if (!changed)
  {
    return true;
  }
  this->SolutionKey.clear();
  this->Cache.clear();
  report.Mode = 0;
  const double* range = nullptr;
  if (controller)
  {
    // The transfer functions span the range of all pieces, as they do for the whole grid.
    const double huge = std::numeric_limits<double>::max();
    double local[2] = { huge, -huge };
    const int component = std::max(this->Scalars.Component, 0);
    if (this->Scalars.Array && !volillum::FiniteRange(this->Scalars.Array, component, local))
    {
      local[0] = huge;
      local[1] = -huge;
    }
    controller->AllReduce(local, this->WholeRange, 1, vtkCommunicator::MIN_OP);
    controller->AllReduce(local + 1, this->WholeRange + 1, 1, vtkCommunicator::MAX_OP);
    if (!(this->WholeRange[0] <= this->WholeRange[1]))
    {
      vtkErrorMacro("Cannot classify the input: the scalars have no finite values.");
      return false;
    }
    range = this->WholeRange;
  }
  const bool classified = !this->Scalars.Array || this->Classify(this->Scalars.Array, range);
  if (controller ? !volillum::AllOk(controller, classified) : !classified)
  {
    return false;
  }
  const std::array<int, 3> dims = this->Level0Dimensions();
  volillum::ResampleLevel0(this->Mesh, this->Extinction, this->Channels, dims, this->Level0);
  if (controller)
  {
    // Each process filled the points inside its own tetrahedra: the grid of the whole mesh
    // is the largest value at each point (a point on a face between pieces has the same
    // interpolated value on both sides, up to rounding).
    std::vector<float> extinction(this->Level0.Extinction.size());
    controller->AllReduce(this->Level0.Extinction.data(), extinction.data(),
      static_cast<vtkIdType>(extinction.size()), vtkCommunicator::MAX_OP);
    this->Level0.Extinction.swap(extinction);
    std::vector<unsigned char> inside(this->Level0.Inside.size());
    controller->AllReduce(this->Level0.Inside.data(), inside.data(),
      static_cast<vtkIdType>(inside.size()), vtkCommunicator::MAX_OP);
    this->Level0.Inside.swap(inside);
  }
  this->SolutionKey = solutionKey;
  return true;
}

//------------------------------------------------------------------------------
bool vtkUnstructuredGridIllumination::PropagateChangedLights(
  const std::vector<volillum::LightState>& lights, volillum::UpdateReport& report,
  PhaseSeconds& seconds, const volillum::NeighborhoodGrid* neighborhood)
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

  // One light at a time: level 0 and level 1 each run in parallel over the grid's points or
  // the mesh's vertices.
  const int iterations = this->Level1Iterations >= 0
    ? this->Level1Iterations
    : volillum::AutomaticLevel1Iterations(this->Mesh, this->Level0.Geometry);
  std::vector<float> level0;
  for (size_t s = 0; s < stale.size(); ++s)
  {
    this->UpdateProgress(0.1 + 0.8 * s / stale.size());
    // A parallel run does not stop: the other processes would wait for this one's values.
    if (!neighborhood && this->GetAbortExecute())
    {
      return false;
    }
    const volillum::LightState& light = lights[stale[s]];
    const auto level0Start = Clock::now();
    volillum::PropagateLevel0(this->Level0, light, level0);
    seconds.Level0 += SecondsSince(level0Start);
    const auto level1Start = Clock::now();
    LightCache& cache = this->Cache[stale[s]];
    cache.Valid = false;
    std::function<void(std::vector<float>&)> exchange;
    if (neighborhood)
    {
      exchange = [&](std::vector<float>& rho)
      { neighborhood->Exchange(rho.data(), this->Channels); };
    }
    volillum::PropagateLevel1(this->Mesh, this->Extinction, this->Level0, level0, light, 0.0,
      iterations, cache.Rho, exchange);
    cache.State = light;
    cache.Valid = true;
    seconds.Level1 += SecondsSince(level1Start);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkUnstructuredGridIllumination::FillOutput(vtkUnstructuredGrid* input, std::vector<float> rgb,
  const volillum::UpdateReport& report, const PhaseSeconds& seconds, vtkUnstructuredGrid* output)
{
  vtkNew<vtkFloatArray> illumination;
  illumination->SetName("Illumination");
  illumination->SetNumberOfComponents(3);
  illumination->SetNumberOfTuples(input->GetNumberOfPoints());
  // A copy of a point, in no cell of the mesh, has the first copy's light.
  for (vtkIdType p = 0;
       p < static_cast<vtkIdType>(this->FirstAtPlace.size()) && p < input->GetNumberOfPoints(); ++p)
  {
    std::copy_n(rgb.begin() + 3 * this->FirstAtPlace[p], 3, rgb.begin() + 3 * p);
  }
  std::copy_n(rgb.begin(), 3 * input->GetNumberOfPoints(), illumination->GetPointer(0));
  output->ShallowCopy(input);
  output->GetPointData()->AddArray(illumination);
  if (this->LitColors)
  {
    output->GetPointData()->AddArray(
      this->ShadeVertices(this->Scalars.Array, rgb, input->GetNumberOfPoints()));
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
  volillum::AddCountFieldData(output->GetFieldData(), "LitPoints", this->Mesh.NumberOfPoints());
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
  os << indent << "Exposure: " << this->Exposure << "\n";
}
