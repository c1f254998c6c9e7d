#include "vtkIlluminationVolumeAlgorithm.h"

#include "AmbientOcclusionKernel.h"
#include "IlluminationClassify.h"
#include "IlluminationLightingMacros.h"
#include "ImageBlocks.h"
#include "ImageExtents.h"
#include "LargeArrays.h"
#include "ParallelCollectives.h"
#include "ParallelMessages.h"
#include "RayMarchKernel.h"

#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLight.h"
#include "vtkMatrix3x3.h"
#include "vtkMultiProcessController.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

volillumLightingImplementationMacro(vtkIlluminationVolumeAlgorithm);

namespace
{
// The output array: every update writes a new one, in memory for large arrays (LargeArrays.h).
vtkSmartPointer<vtkFloatArray> NewIlluminationArray(long long points)
{
  auto array = vtkSmartPointer<vtkFloatArray>::New();
  array->SetName("Illumination");
  array->SetNumberOfComponents(3);
  if (void* memory = volillum::AllocateHugePages(3 * sizeof(float) * static_cast<size_t>(points)))
  {
    array->SetArray(
      static_cast<float*>(memory), 3 * points, 0, vtkAbstractArray::VTK_DATA_ARRAY_FREE);
    return array;
  }
  array->SetNumberOfTuples(points);
  return array;
}
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::ClassificationKey::operator==(const ClassificationKey& o) const
{
  return this->Scalars == o.Scalars && this->Component == o.Component && this->Color == o.Color &&
    this->Opacity == o.Opacity && this->Scale == o.Scale && this->UnitDistance == o.UnitDistance &&
    this->Chromatic == o.Chromatic && this->HasRange == o.HasRange &&
    (!this->HasRange || (this->Range[0] == o.Range[0] && this->Range[1] == o.Range[1]));
}

//------------------------------------------------------------------------------
vtkIlluminationVolumeAlgorithm::vtkIlluminationVolumeAlgorithm()
  : Distributed(new volillum::DistributedInput)
  , BlockScalars(new volillum::BlockPointScalars)
  , Blocks(new volillum::BlockOfPieces)
{
  this->SetController(vtkMultiProcessController::GetGlobalController());
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkIlluminationVolumeAlgorithm::~vtkIlluminationVolumeAlgorithm()
{
  this->SetColorTransferFunction(nullptr);
  this->SetOpacityFunction(nullptr);
  this->SetController(nullptr);
}

//------------------------------------------------------------------------------
vtkCxxSetObjectMacro(vtkIlluminationVolumeAlgorithm, Controller, vtkMultiProcessController);

//------------------------------------------------------------------------------
std::vector<volillum::LightState> vtkIlluminationVolumeAlgorithm::GetLightStates() const
{
  std::vector<volillum::LightState> states = this->Lights.States();
  if (!this->UsesLightSize())
  {
    // A size this filter ignores is no change of the light (no update for a radius edit).
    for (auto& s : states)
    {
      s.Radius = 0.0;
    }
  }
  return states;
}

//------------------------------------------------------------------------------
int vtkIlluminationVolumeAlgorithm::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::ValidGeometry(
  vtkImageData* input, volillum::GridGeometry& data, volillum::GridGeometry& target)
{
  int dims[3];
  input->GetDimensions(dims);
  if (input->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro("The input image is empty.");
    return false;
  }
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    vtkErrorMacro("The input image must be 3D (at least 2 points along each axis); its "
                  "dimensions are "
      << dims[0] << " x " << dims[1] << " x " << dims[2] << ".");
    return false;
  }
  if (this->ResolutionScale != 1.0 && this->ResolutionScale != 0.5 && this->ResolutionScale != 0.25)
  {
    vtkErrorMacro("ResolutionScale must be 1, 0.5 or 0.25; it is " << this->ResolutionScale << ".");
    return false;
  }
  if (!std::isfinite(this->AmbientOcclusion) || !std::isfinite(this->AmbientOcclusionRadius))
  {
    vtkErrorMacro("AmbientOcclusion and AmbientOcclusionRadius must be finite; they are "
      << this->AmbientOcclusion << " and " << this->AmbientOcclusionRadius << ".");
    return false;
  }
  double spacing[3];
  input->GetSpacing(spacing);
  for (int a = 0; a < 3; ++a)
  {
    if (!(spacing[a] > 0.0) || !std::isfinite(spacing[a]))
    {
      vtkErrorMacro("The input spacing must be positive and finite.");
      return false;
    }
  }
  // The grid starts at the first point of the extent.
  double origin[3];
  input->GetOrigin(origin);
  const int* ext = input->GetExtent();
  for (int a = 0; a < 3; ++a)
  {
    data.Dimensions[a] = dims[a];
    data.Spacing[a] = spacing[a];
    data.Origin[a] = origin[a] + ext[2 * a] * spacing[a];
    const double last = data.Origin[a] + (dims[a] - 1) * spacing[a];
    if (!(std::abs(data.Origin[a]) <= MaximumCoordinate) || !(std::abs(last) <= MaximumCoordinate))
    {
      vtkErrorMacro("The input's bounds must lie within +-" << MaximumCoordinate
                                                            << " (check its origin and spacing).");
      return false;
    }
  }
  target = volillum::ScaledGeometry(data, this->ResolutionScale);
  if (target.NumberOfPoints() > MaximumOutputPoints)
  {
    vtkErrorMacro("The illumination volume would have "
      << target.NumberOfPoints() << " points, more than the limit of " << MaximumOutputPoints
      << "; lower ResolutionScale.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkIlluminationVolumeAlgorithm::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int ext[6];
  // (Resample To Image gives its origin and spacing with its data only.)
  double spacing[3] = { 1.0, 1.0, 1.0 }, origin[3] = { 0.0, 0.0, 0.0 };
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext);
  inInfo->Get(vtkDataObject::SPACING(), spacing);
  inInfo->Get(vtkDataObject::ORIGIN(), origin);
  volillum::GridGeometry data;
  for (int a = 0; a < 3; ++a)
  {
    data.Dimensions[a] = std::max(0, ext[2 * a + 1] - ext[2 * a] + 1);
    data.Spacing[a] = spacing[a];
    data.Origin[a] = origin[a] + ext[2 * a] * spacing[a];
  }
  const double scale = this->ResolutionScale;
  const bool validScale = scale == 1.0 || scale == 0.5 || scale == 0.25;
  const volillum::GridGeometry target = volillum::ScaledGeometry(data, validScale ? scale : 1.0);
  int outExt[6];
  for (int a = 0; a < 3; ++a)
  {
    outExt[2 * a] = 0;
    outExt[2 * a + 1] = target.Dimensions[a] - 1;
  }
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), outExt, 6);
  outInfo->Set(vtkDataObject::SPACING(), target.Spacing.data(), 3);
  outInfo->Set(vtkDataObject::ORIGIN(), target.Origin.data(), 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_FLOAT, 3);
  return 1;
}

//------------------------------------------------------------------------------
int vtkIlluminationVolumeAlgorithm::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Light crosses the whole volume: a serial run asks for all of the input. In a parallel
  // run process p of N asks for piece p of N of the whole extent, whatever piece its output
  // is asked for (its output is the illumination over block p of the data's extent). This is
  // the pipeline's own request for distributed images: a producer that can read sub-extents
  // gets block p (the executive's extent translator, block mode, as ProcessBlock), and one
  // that cannot (a reader of a single file, vtkPResampleToImage, which splits the whole
  // extent among the processes itself) makes its own pieces; RequestData lights the blocks
  // where they are (LightsDistributedPieces) or assembles them, and other pieces give each
  // block its part first (BlockOfPieces).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  int extent[6];
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  if (vtkMultiProcessController* controller = volillum::ParallelRun(this->Controller))
  {
    inInfo->Set(
      vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), controller->GetLocalProcessId());
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(),
      controller->GetNumberOfProcesses());
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent, 6);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::ReportProgress(double fraction)
{
  this->UpdateProgress(fraction);
  return !this->GetAbortExecute();
}

//------------------------------------------------------------------------------
const volillum::EmptyBlocks* vtkIlluminationVolumeAlgorithm::GetEmptyBlocks()
{
  if (!this->HasClassification)
  {
    return nullptr;
  }
  if (!this->Empty)
  {
    this->Empty = std::make_unique<const volillum::EmptyBlocks>(this->Classified);
  }
  return this->Empty.get();
}

//------------------------------------------------------------------------------
volillum::SweepShare vtkIlluminationVolumeAlgorithm::GetSweepShare() const
{
  volillum::SweepShare share;
  if (this->SharingController)
  {
    share.Process = this->SharingController->GetLocalProcessId();
    share.Processes = this->SharingController->GetNumberOfProcesses();
  }
  return share;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::OutputIllumination(
  const volillum::FixedPointIllumination& illumination, const volillum::GridGeometry& target,
  float* rgb)
{
  if (!this->SharingController)
  {
    illumination.ToFloat(rgb);
    return;
  }
  std::vector<std::uint32_t> own;
  volillum::SumOverPieces(this->SharingController, target.Dimensions.data(), this->PieceExtents,
    illumination.Values.data(), own);
  this->SumsDone = true;
  volillum::FixedPointIllumination::ToFloat(own.data(), own.size(), illumination.Scale, rgb);
}

//------------------------------------------------------------------------------
int vtkIlluminationVolumeAlgorithm::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  vtkMultiProcessController* controller = volillum::ParallelRun(this->Controller);
  if (!controller)
  {
    if (!input)
    {
      vtkErrorMacro("The input is not a vtkImageData.");
      return 1;
    }
    this->Illuminate(input, output);
    return 1;
  }
  // Every process's errors reach the first process, which a client shows.
  volillum::ParallelMessages messages(controller, this);
  // Ambient occlusion reads the neighbourhood of every point, across the pieces' faces.
  if (this->LightsDistributedPieces() && !(this->AmbientOcclusion > 0.0))
  {
    this->IlluminateDistributed(controller, inputVector[0]->GetInformationObject(0), input, output);
    return 1;
  }
  // Light crosses every piece: every process assembles the whole image (an empty or invalid
  // one is reported as in a serial run). Filters that light points independently compute
  // only this process's part of the illumination grid; the others share their sweeps out
  // and output the sums over the processes for this process's part.
  vtkImageData* whole = this->Distributed->Image(controller, volillum::LitArrayName(this), input);
  volillum::GridGeometry data, target;
  if (!this->ValidGeometry(whole, data, target))
  {
    return 1;
  }
  const bool piece = input && input->GetNumberOfPoints() > 0;
  int extent[6];
  if (piece)
  {
    volillum::TargetPieceExtent(
      whole->GetExtent(), target.Dimensions.data(), input->GetExtent(), extent);
  }
  if (this->LightsPointsIndependently())
  {
    if (piece)
    {
      this->Illuminate(whole, output, extent);
    }
    return 1;
  }
  // The sweeps are shared out and each piece gets the sums over the processes: every
  // process takes part, those without a piece with their empty extent and an unused output.
  this->PieceExtents = volillum::GatherExtents(controller, piece ? extent : nullptr);
  this->SharingController = controller;
  vtkNew<vtkImageData> unused;
  this->Illuminate(whole, piece ? output : unused.Get(),
    this->PieceExtents.data() + 6 * controller->GetLocalProcessId());
  this->SharingController = nullptr;
  this->PieceExtents.clear();
  return 1;
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::UpdateClassification(
  const volillum::GridGeometry& data, bool& inputModified, const double* range)
{
  vtkDataArray* scalars = this->Scalars.Array;
  std::string error;
  ClassificationKey key;
  key.Scalars = this->Scalars.Time;
  key.Component = this->ScalarComponent;
  key.Color = this->ColorTransferFunction ? this->ColorTransferFunction->GetMTime() : 0;
  key.Opacity = this->OpacityFunction ? this->OpacityFunction->GetMTime() : 0;
  key.Scale = this->ResolutionScale;
  key.UnitDistance = this->ScalarOpacityUnitDistance;
  key.Chromatic = this->ChromaticAttenuation;
  key.HasRange = range != nullptr;
  if (range)
  {
    std::copy_n(range, 2, key.Range);
  }
  inputModified = !this->HasClassification || !(key == this->ClassifiedKey) ||
    this->Classified.Geometry.Dimensions != data.Dimensions ||
    this->Classified.Geometry.Spacing != data.Spacing ||
    this->Classified.Geometry.Origin != data.Origin;
  if (inputModified)
  {
    volillum::ClassificationSettings settings;
    settings.Color = this->ColorTransferFunction;
    settings.Opacity = this->OpacityFunction;
    settings.UnitDistance = this->ScalarOpacityUnitDistance;
    settings.Chromatic = this->ChromaticAttenuation;
    settings.Range = range;
    long long nans = 0;
    this->HasClassification = false;
    this->Empty.reset();
    if (!volillum::Classify(scalars, data, settings, this->Classified, error, &nans))
    {
      vtkErrorMacro("Cannot classify the input: " << error << ".");
      return false;
    }
    if (nans > 0)
    {
      vtkWarningMacro(<< nans << " scalar values are NaN; they are treated as empty space.");
    }
    this->ClassifiedKey = key;
    this->HasClassification = true;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::Illuminate(
  vtkImageData* input, vtkImageData* output, const int* piece)
{
  const auto start = std::chrono::steady_clock::now();
  volillum::GridGeometry data, target;
  if (!this->ValidGeometry(input, data, target))
  {
    return;
  }
  std::string error;
  this->Scalars = volillum::CheckScalarsAndLights(
    this, input, this->ScalarComponent, this->Scalars, this->Lights, error);
  if (!this->Scalars.Array)
  {
    vtkErrorMacro(<< error);
    return;
  }
  double bounds[6];
  data.GetBounds(bounds);
  vtkMatrix3x3* direction = input->GetDirectionMatrix();
  const std::vector<volillum::LightState> lights = volillum::ForBounds(
    volillum::InImageFrame(this->GetLightStates(), direction, input->GetOrigin()), bounds);

  bool inputModified = false;
  if (!this->UpdateClassification(data, inputModified))
  {
    return;
  }

  // The points lit: the illumination grid, or its part `piece`.
  volillum::GridGeometry lit = target;
  int extent[6] = { 0, target.Dimensions[0] - 1, 0, target.Dimensions[1] - 1, 0,
    target.Dimensions[2] - 1 };
  if (piece)
  {
    for (int a = 0; a < 3; ++a)
    {
      extent[2 * a] = piece[2 * a];
      extent[2 * a + 1] = piece[2 * a + 1];
      lit.Dimensions[a] = piece[2 * a + 1] - piece[2 * a] + 1;
      lit.Origin[a] = target.Origin[a] + piece[2 * a] * target.Spacing[a];
    }
  }
  // Shared sweeps propagate through the whole grid and output the piece's points.
  auto illumination = NewIlluminationArray(lit.NumberOfPoints());
  UpdateReport report;
  this->SumsDone = false;
  const bool computed = this->ComputeIllumination(this->Classified, lights,
    this->SharingController ? target : lit, inputModified, illumination->GetPointer(0), report);
  if (this->SharingController)
  {
    // A shared run ignores aborts (the other processes wait for this one's sums), and a
    // computation that did not reach its sums still takes part in them, with nothing.
    this->SetAbortExecute(0);
    if (!this->SumsDone)
    {
      volillum::FixedPointIllumination none;
      none.Reset(target.NumberOfPoints(), 1.0);
      this->OutputIllumination(none, target, illumination->GetPointer(0));
    }
  }
  if (inputModified)
  {
    this->Occlusion = nullptr;
  }
  this->OcclusionPoints = 0;
  if (!computed ||
    (this->AmbientOcclusion > 0.0 &&
      !this->AddAmbientOcclusion(lit, inputModified, illumination->GetPointer(0))))
  {
    // Aborted: show what the last complete update produced.
    if (this->LastOutput)
    {
      output->ShallowCopy(this->LastOutput);
    }
    return;
  }

  this->FinishOutput(output, extent, target, direction, illumination, report,
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::AddAmbientOcclusion(
  const volillum::GridGeometry& lit, bool inputModified, float* rgb)
{
  double bounds[6];
  this->Classified.Geometry.GetBounds(bounds);
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  // Rays longer than the diagonal have left the data (beyond it, nothing occludes).
  const double radius = this->AmbientOcclusionRadius > 0.0
    ? std::min(this->AmbientOcclusionRadius, diagonal)
    : 0.05 * diagonal;
  const std::array<double, 10> key = { radius, static_cast<double>(lit.Dimensions[0]),
    static_cast<double>(lit.Dimensions[1]), static_cast<double>(lit.Dimensions[2]), lit.Origin[0],
    lit.Origin[1], lit.Origin[2], lit.Spacing[0], lit.Spacing[1], lit.Spacing[2] };
  if (inputModified || !this->Occlusion || key != this->OcclusionKey)
  {
    this->Occlusion = nullptr;
    if (!(radius > 0.0))
    {
      // A flat extent (a single point) has no neighbourhood: nothing is occluded.
      auto open = NewIlluminationArray(lit.NumberOfPoints());
      std::fill_n(open->GetPointer(0), 3 * lit.NumberOfPoints(), 1.0f);
      this->Occlusion = open;
    }
    else
    {
      volillum::AmbientOcclusionTable table;
      table.Build(this->Classified, this->ChromaticAttenuation ? 3 : 1);
      auto occlusion = NewIlluminationArray(lit.NumberOfPoints());
      if (!volillum::ComputeAmbientOcclusion(table, lit, radius, occlusion->GetPointer(0),
            [this](double fraction) { return this->ReportProgress(fraction); }))
      {
        return false;
      }
      this->Occlusion = occlusion;
    }
    this->Occlusion->SetName("AmbientOcclusion");
    this->OcclusionKey = key;
    this->OcclusionPoints = lit.NumberOfPoints();
  }
  const float strength = static_cast<float>(this->AmbientOcclusion);
  const float* occlusion = this->Occlusion->GetPointer(0);
  const long long values = 3 * lit.NumberOfPoints();
  vtkSMPTools::For(0, values,
    [&](long long begin, long long end)
    {
      for (long long v = begin; v < end; ++v)
      {
        rgb[v] += strength * occlusion[v];
      }
    });
  return true;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::FinishOutput(vtkImageData* output, const int extent[6],
  const volillum::GridGeometry& target, vtkMatrix3x3* direction, vtkFloatArray* illumination,
  const UpdateReport& report, double seconds)
{
  output->SetExtent(const_cast<int*>(extent));
  output->SetOrigin(target.Origin.data());
  output->SetSpacing(target.Spacing.data());
  output->SetDirectionMatrix(direction);
  output->GetPointData()->SetScalars(illumination);
  this->AddOutputArrays(output->GetPointData());
  if (this->AmbientOcclusion > 0.0 && this->Occlusion)
  {
    output->GetPointData()->AddArray(this->Occlusion);
    volillum::AddCountFieldData(
      output->GetFieldData(), "AmbientOcclusionPoints", this->OcclusionPoints);
  }
  this->AddOutputFieldData(output->GetFieldData());
  volillum::AddUpdateFieldData(output->GetFieldData(), report, seconds);
  volillum::AddCountFieldData(
    output->GetFieldData(), "ClassifiedPoints", this->Classified.Geometry.NumberOfPoints());
  this->LastOutput = vtkSmartPointer<vtkImageData>::New();
  this->LastOutput->ShallowCopy(output);
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::DistributedShape(vtkMultiProcessController* controller,
  vtkInformation* inInfo, vtkImageData* input, vtkImageData* shape)
{
  // The whole grid, from the pipeline information (the same on every process).
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  double origin[3] = { 0.0, 0.0, 0.0 }, spacing[3] = { 1.0, 1.0, 1.0 };
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  inInfo->Get(vtkDataObject::ORIGIN(), origin);
  inInfo->Get(vtkDataObject::SPACING(), spacing);
  shape->SetExtent(whole);
  shape->SetOrigin(origin);
  shape->SetSpacing(spacing);
  if (inInfo->Has(vtkDataObject::DIRECTION()))
  {
    double direction[9];
    inInfo->Get(vtkDataObject::DIRECTION(), direction);
    shape->SetDirectionMatrix(direction);
  }
  // The pieces' own geometry, as a serial run takes the input's (the pipeline information
  // may lack it, or hold defaults).
  if (!volillum::AgreeOnGeometry(controller, input, shape))
  {
    vtkErrorMacro("The pieces of the image differ in origin, spacing or orientation.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::BlockOfInput(vtkMultiProcessController* controller,
  vtkImageData* shape, const int* block, vtkImageData*& input)
{
  // Where the pieces are not the blocks (another decomposition), each block's lit array is
  // gathered from the pieces that hold it.
  const bool piece = block != nullptr;
  std::string error;
  if (!volillum::AllOk(
        controller, !piece || (input && volillum::ExtentHolds(input->GetExtent(), block))))
  {
    vtkImageData* const own = input && input->GetNumberOfPoints() > 0 ? input : nullptr;
    bool onCells = false;
    vtkAbstractArray* chosen = own ? volillum::ChooseScalars(this, own, onCells, error) : nullptr;
    input = this->Blocks->Update(
      controller, shape, block, own, vtkDataArray::SafeDownCast(chosen), onCells, error);
    if (!error.empty())
    {
      vtkErrorMacro(<< error);
    }
    if (!volillum::AllOk(controller, !piece || input))
    {
      return false;
    }
  }
  else
  {
    this->Blocks = std::make_unique<volillum::BlockOfPieces>(); // none kept
  }
  // Cell scalars become point values by averaging the cells around a point: over the block,
  // from its cells and the layer of the neighbours' around it (decided before any
  // conversion).
  bool onCells = false;
  vtkAbstractArray* chosen = piece ? volillum::ChooseScalars(this, input, onCells, error) : nullptr;
  // A block without the array: its process says why, and all stop.
  if (piece && !chosen)
  {
    vtkErrorMacro(<< error);
  }
  if (!volillum::AllOk(controller, !piece || chosen))
  {
    return false;
  }
  if (volillum::AllOk(controller, !onCells))
  {
    this->BlockScalars = std::make_unique<volillum::BlockPointScalars>(); // none kept
    return true;
  }
  input = this->BlockScalars->Update(controller, shape->GetExtent(), block, input,
    onCells ? vtkDataArray::SafeDownCast(chosen) : nullptr, this->ScalarComponent,
    volillum::CellScalarsToPoints, error);
  const bool ok = !piece || input;
  if (!ok)
  {
    vtkErrorMacro(<< (error.empty() ? "The cell scalars cannot be made point scalars."
                                    : error.c_str()));
  }
  return volillum::AllOk(controller, ok);
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::DistributedScalarRange(
  vtkMultiProcessController* controller, vtkImageData* input, bool piece, double range[2])
{
  bool ok = true;
  if (piece)
  {
    std::string error;
    this->Scalars = volillum::CheckScalarsAndLights(
      this, input, this->ScalarComponent, this->Scalars, this->Lights, error);
    ok = this->Scalars.Array != nullptr;
    if (!ok)
    {
      vtkErrorMacro(<< error);
    }
  }
  if (!volillum::AllOk(controller, ok))
  {
    return false;
  }
  // The transfer functions span the scalar range of all pieces.
  double local[2] = { VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  if (piece && !volillum::FiniteRange(this->Scalars.Array, 0, local))
  {
    local[0] = VTK_DOUBLE_MAX;
    local[1] = -VTK_DOUBLE_MAX;
  }
  controller->AllReduce(local, range, 1, vtkCommunicator::MIN_OP);
  controller->AllReduce(local + 1, range + 1, 1, vtkCommunicator::MAX_OP);
  if (!(range[0] <= range[1]))
  {
    vtkErrorMacro("Cannot classify the input: the scalars have no finite values.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::IlluminateDistributed(vtkMultiProcessController* controller,
  vtkInformation* inInfo, vtkImageData* input, vtkImageData* output)
{
  const auto start = std::chrono::steady_clock::now();
  vtkNew<vtkImageData> shape;
  volillum::GridGeometry data, target;
  if (!this->DistributedShape(controller, inInfo, input, shape) ||
    !this->ValidGeometry(shape, data, target))
  {
    return;
  }
  // This process takes the samples in the cells of its block of the data (the blocks share
  // their boundary planes, so each cell is taken once).
  const int* whole = shape->GetExtent();
  int block[6];
  const bool piece = volillum::ProcessBlock(controller, whole, block);
  double range[2];
  if (!this->BlockOfInput(controller, shape, piece ? block : nullptr, input) ||
    !this->DistributedScalarRange(controller, input, piece, range))
  {
    return;
  }
  volillum::VolumePiece where;
  where.Whole = data;
  volillum::ClassifiedVolume none;
  bool inputModified = false, ok = true;
  std::vector<volillum::LightState> lights;
  int extent[6];
  if (piece)
  {
    const int* e = input->GetExtent();
    volillum::GridGeometry own = data;
    for (int a = 0; a < 3; ++a)
    {
      own.Dimensions[a] = e[2 * a + 1] - e[2 * a] + 1;
      own.Origin[a] = data.Origin[a] + (e[2 * a] - whole[2 * a]) * data.Spacing[a];
      where.Offset[a] = e[2 * a] - whole[2 * a];
      where.FirstCell[a] = block[2 * a] - whole[2 * a];
      where.LastCell[a] = block[2 * a + 1] - whole[2 * a] - 1;
    }
    ok = this->UpdateClassification(own, inputModified, range);
    double bounds[6];
    data.GetBounds(bounds);
    // The lights turn about the origin of the pipeline information.
    double origin[3] = { 0.0, 0.0, 0.0 };
    inInfo->Get(vtkDataObject::ORIGIN(), origin);
    lights = volillum::ForBounds(
      volillum::InImageFrame(this->GetLightStates(), input->GetDirectionMatrix(), origin), bounds);
    volillum::TargetPieceExtent(whole, target.Dimensions.data(), e, extent);
  }
  if (!volillum::AllOk(controller, ok))
  {
    return;
  }
  const std::vector<int> extents = volillum::GatherExtents(controller, piece ? extent : nullptr);
  // Points the computation leaves unlit stay dark.
  auto illumination = NewIlluminationArray(piece ? volillum::ExtentPoints(extent) : 0);
  illumination->FillValue(0.0f);
  UpdateReport report;
  this->ComputeDistributedIllumination(controller, piece ? this->Classified : none, where, lights,
    target, extents, inputModified, illumination->GetPointer(0), report);
  this->SetAbortExecute(0); // not aborted: the other processes took part
  this->Distributed = std::make_unique<volillum::DistributedInput>(); // no whole input kept
  // Where the pieces are not the blocks the output covers the block (input), as the
  // pieces the pipeline asks for do: they are vtkExtentTranslator's blocks of the output.
  if (piece)
  {
    this->FinishOutput(output, extent, target, input->GetDirectionMatrix(), illumination, report,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::ComputeDistributedIllumination(vtkMultiProcessController*,
  const volillum::ClassifiedVolume&, const volillum::VolumePiece&,
  const std::vector<volillum::LightState>&, const volillum::GridGeometry&, const std::vector<int>&,
  bool, float*, UpdateReport&)
{
  // Reached only by a filter that claims LightsDistributedPieces without lighting them (the
  // output stays dark).
  vtkErrorMacro("This filter does not light distributed pieces.");
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Lights: " << this->Lights.Size() << "\n";
  os << indent << "ScalarComponent: " << this->ScalarComponent << "\n";
  os << indent << "ResolutionScale: " << this->ResolutionScale << "\n";
  os << indent << "ScalarOpacityUnitDistance: " << this->ScalarOpacityUnitDistance << "\n";
  os << indent << "ChromaticAttenuation: " << this->ChromaticAttenuation << "\n";
  os << indent << "AmbientOcclusion: " << this->AmbientOcclusion << "\n";
  os << indent << "AmbientOcclusionRadius: " << this->AmbientOcclusionRadius << "\n";
  os << indent << "ColorTransferFunction: " << this->ColorTransferFunction << "\n";
  os << indent << "OpacityFunction: " << this->OpacityFunction << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
}
