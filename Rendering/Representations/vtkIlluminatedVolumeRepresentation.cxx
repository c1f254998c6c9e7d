#include "vtkIlluminatedVolumeRepresentation.h"

#include "IlluminationBackground.h"
#include "IlluminationFilterSupport.h"
#include "IlluminationViewLights.h"
#include "ParallelCollectives.h"
#include "vtkAlgorithmOutput.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkExtractVOI.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkFloatArray.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRayMarchedIllumination.h"
#include "vtkRenderWindow.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTrivialProducer.h"
#include "vtkVolumeProperty.h"
#include "vtkWeakPointer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace
{
constexpr int CoarseStride = 4; // the coarse stage lights every 4th sample along each axis
constexpr double CoarseScale = 1.0 / CoarseStride;

// What a serial lighting reads, owned by the job that computes it: light values, copies of
// the transfer functions (new copies only when the colour map editor changed them) and a
// shallow copy of the data (new only when the data changed).
struct LightingRequest
{
  int Method = 0;
  double Scale = 0.5;
  bool Chromatic = false;
  double FilterWidth = 3.0;
  int FilterKernel = 0;
  double AmbientOcclusion = 0.0;
  double AmbientOcclusionRadius = 0.0;
  std::vector<volillum::LightValues> Lights;
  vtkSmartPointer<vtkImageData> Input;
  std::string ArrayName;
  int Association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkSmartPointer<vtkColorTransferFunction> Color;
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
  double UnitDistance = 1.0;
  bool CoarseFirst = false;
  // The cost class of this request against the previous one: -1 everything, otherwise the
  // number of lights that changed (the history of measured costs is kept per class).
  int Kind = -1;

  bool SameInputsAs(const LightingRequest& o) const
  {
    return this->Method == o.Method && this->Scale == o.Scale && this->Chromatic == o.Chromatic &&
      this->FilterWidth == o.FilterWidth && this->FilterKernel == o.FilterKernel &&
      this->AmbientOcclusion == o.AmbientOcclusion &&
      this->AmbientOcclusionRadius == o.AmbientOcclusionRadius && this->Input == o.Input &&
      this->ArrayName == o.ArrayName && this->Association == o.Association &&
      this->Color == o.Color && this->Opacity == o.Opacity && this->UnitDistance == o.UnitDistance;
  }
  bool SameAs(const LightingRequest& o) const
  {
    return this->SameInputsAs(o) && this->Lights == o.Lights;
  }
};
}

struct vtkIlluminatedVolumeRepresentation::vtkInternals
{
  volillum::RenderStart Start;
  // One filter per method, created when first used; only the active one is kept. In a serial
  // run they, Coarse, Lights and Published belong to the lighting job while one runs (see
  // IlluminationBackground.h); the render thread touches them only through Background,
  // declared after them so that its worker is joined before they go.
  std::array<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>, 3> Filters;
  vtkSmartPointer<vtkIlluminationVolumeAlgorithm> Coarse; // CoarseFirst's, of the same method
  int CoarseMethod = -1;
  vtkSmartPointer<vtkImageData> CoarseInput; // the coarse stage's data, made from CoarseSource
  vtkSmartPointer<vtkImageData> CoarseSource;
  volillum::ViewLights Lights;
  vtkMTimeType Published = 0; // the output time of the last published result
  volillum::BackgroundLighting Background;

  // The render thread's side of a serial run.
  LightingRequest Submitted; // the last request handed to a job
  bool HasSubmitted = false;
  volillum::JobCopies Copies;
  volillum::ShownLighting Shown; // what the mapper draws

  // A multi-component coloured array, the one-component array that stands for it in the
  // rendered data, and the component its values were made from (-1: the magnitude).
  vtkSmartPointer<vtkDataArray> Vectors;
  vtkSmartPointer<vtkDataArray> Reduced;
  int Component = -1;
  // A parallel run (pvserver or pvbatch under MPI): the filter lights the pieces where they
  // are as each render starts, every process together (Piece: this process's piece within
  // the whole extent), and gives each process the illumination over its piece (ParaView's
  // pieces are the filter's blocks).
  vtkNew<vtkTrivialProducer> Piece;
  vtkMultiProcessController* Controller = nullptr; // lighting the pieces where they are

  /// Nothing to light or draw any more: stop the lighting, drop what it left to draw.
  void Forget()
  {
    this->Background.Cancel();
    this->Background.Discard();
    this->HasSubmitted = false;
    this->Shown.Final = true;
  }
  LightingRequest MakeRequest(vtkIlluminatedVolumeRepresentation* self, vtkPVRenderView* view,
    vtkImageData* image, const volillum::ColouredArray& coloured);
  vtkIlluminationVolumeAlgorithm* FilterFor(int method);
  void Light(const LightingRequest& request, volillum::BackgroundLighting::Job& job);
};

vtkStandardNewMacro(vtkIlluminatedVolumeRepresentation);

//------------------------------------------------------------------------------
vtkIlluminatedVolumeRepresentation::vtkIlluminatedVolumeRepresentation()
  : Internals(new vtkInternals)
{
  // Replace the superclass's volume mapper with the illuminated one (the actor is the
  // superclass's; it is given the mapper in UpdateMapperParameters).
  this->VolumeMapper = vtkSmartPointer<vtkIlluminatedVolumeMapper>::New();
  this->SetProgressText("Illuminating the volume");
}

//------------------------------------------------------------------------------
vtkIlluminatedVolumeRepresentation::~vtkIlluminatedVolumeRepresentation() = default;

//------------------------------------------------------------------------------
vtkIlluminatedVolumeMapper* vtkIlluminatedVolumeRepresentation::GetIlluminatedMapper()
{
  return static_cast<vtkIlluminatedVolumeMapper*>(this->VolumeMapper.GetPointer());
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::SetIlluminationAmbient(double value)
{
  this->GetIlluminatedMapper()->SetAmbient(value);
}

void vtkIlluminatedVolumeRepresentation::SetIlluminationDiffuse(double value)
{
  this->GetIlluminatedMapper()->SetDiffuse(value);
}

void vtkIlluminatedVolumeRepresentation::SetExposure(double value)
{
  this->GetIlluminatedMapper()->SetExposure(value);
}

void vtkIlluminatedVolumeRepresentation::SetGradientShading(bool enable)
{
  this->GetIlluminatedMapper()->SetGradientShading(enable);
}

void vtkIlluminatedVolumeRepresentation::SetPhongAmbient(double value)
{
  this->GetIlluminatedMapper()->SetPhongAmbient(value);
}

void vtkIlluminatedVolumeRepresentation::SetPhongDiffuse(double value)
{
  this->GetIlluminatedMapper()->SetPhongDiffuse(value);
}

void vtkIlluminatedVolumeRepresentation::SetPhongSpecular(double value)
{
  this->GetIlluminatedMapper()->SetPhongSpecular(value);
}

void vtkIlluminatedVolumeRepresentation::SetPhongSpecularPower(double value)
{
  this->GetIlluminatedMapper()->SetPhongSpecularPower(value);
}

//------------------------------------------------------------------------------
namespace
{
vtkSmartPointer<vtkIlluminationVolumeAlgorithm> NewFilter(int method)
{
  switch (method)
  {
    case vtkIlluminatedVolumeRepresentation::FilteredShadows:
      return vtkSmartPointer<vtkFilteredVolumetricShadows>::New();
    case vtkIlluminatedVolumeRepresentation::RayMarchedReference:
      return vtkSmartPointer<vtkRayMarchedIllumination>::New();
    default:
      return vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
  }
}
}

//------------------------------------------------------------------------------
namespace
{
enum class Frame
{
  Interactive,
  Still,
  Preview
};

// Sample as the Volume representation does (vtkSmartVolumeMapper): still renders every
// half voxel or finer (the distance locked to the data's spacing), interactive ones as the
// frame rate allows. Still frames jitter the ray starts within that step, which keeps them
// no grainier than plain Volume's and free of rings; interactive frames, whose steps are
// coarse, start every ray one step in, as plain Volume's do. A still frame drawn while the
// final illumination is computed in the background is a preview (of a coarse or the previous
// illumination): one sample per `voxel` on every third pixel, about a tenth of a still
// frame's cost, which leaves the cores to the lighting.
void SetSampling(vtkIlluminatedVolumeMapper* mapper, Frame frame, double voxel)
{
  const bool still = frame == Frame::Still;
  mapper->SetAutoAdjustSampleDistances(frame == Frame::Interactive);
  mapper->SetLockSampleDistanceToInputSpacing(still);
  mapper->SetJitteredRayStarts(still);
  if (frame == Frame::Preview)
  {
    mapper->SetSampleDistance(static_cast<float>(voxel));
    mapper->SetImageSampleDistance(3.0f);
  }
  else if (still)
  {
    mapper->SetImageSampleDistance(1.0f);
  }
}
}

//------------------------------------------------------------------------------
vtkIlluminationVolumeAlgorithm* vtkIlluminatedVolumeRepresentation::vtkInternals::FilterFor(
  int method)
{
  for (int m = 0; m < static_cast<int>(this->Filters.size()); ++m)
  {
    if (m != method)
    {
      this->Filters[m] = nullptr; // one illumination volume in memory at a time
    }
  }
  auto& filter = this->Filters[method];
  if (!filter)
  {
    filter = NewFilter(method);
  }
  return filter;
}

//------------------------------------------------------------------------------
vtkIlluminationVolumeAlgorithm* vtkIlluminatedVolumeRepresentation::GetIlluminationFilter()
{
  vtkIlluminationVolumeAlgorithm* filter = this->Internals->FilterFor(this->IlluminationMethod);
  // Pieces lit where they are in a parallel run (see vtkInternals).
  filter->SetController(this->Internals->Controller);
  return filter;
}

//------------------------------------------------------------------------------
LightingRequest vtkIlluminatedVolumeRepresentation::vtkInternals::MakeRequest(
  vtkIlluminatedVolumeRepresentation* self, vtkPVRenderView* view, vtkImageData* image,
  const volillum::ColouredArray& coloured)
{
  LightingRequest r;
  r.Method = self->IlluminationMethod;
  r.Scale = self->ResolutionScale;
  r.Chromatic = self->ChromaticAttenuation;
  r.FilterWidth = self->ShadowFilterWidth;
  r.FilterKernel = self->ShadowFilterKernel;
  r.AmbientOcclusion = self->AmbientOcclusion;
  r.AmbientOcclusionRadius = self->AmbientOcclusionRadius;
  // Only Filtered Shadows uses a light's size: otherwise an edit of it changes nothing.
  r.Lights = volillum::ReadViewLights(
    view, self->UseLightKit, r.Method == vtkIlluminatedVolumeRepresentation::FilteredShadows);
  r.ArrayName = coloured.Name ? coloured.Name : "";
  r.Association = coloured.Association;
  vtkVolumeProperty* property = self->Property;
  r.UnitDistance = property->GetScalarOpacityUnitDistance(0);
  // Copies the job owns, made anew only when their originals changed (a new copy makes the
  // filter recompute everything, as an edit of the original does).
  r.Input = vtkImageData::SafeDownCast(this->Copies.Data(image));
  r.Color = this->Copies.Color(property->GetRGBTransferFunction(0));
  r.Opacity = this->Copies.Opacity(property->GetScalarOpacity(0));
  if (this->HasSubmitted && r.SameInputsAs(this->Submitted))
  {
    r.Kind = volillum::ChangedLights(r.Lights, this->Submitted.Lights);
  }
  return r;
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::vtkInternals::Light(
  const LightingRequest& r, volillum::BackgroundLighting::Job& job)
{
  this->Lights.Update(r.Lights);
  auto configure = [&](vtkIlluminationVolumeAlgorithm* filter, vtkImageData* input, double scale)
  {
    this->Lights.ApplyTo(filter);
    filter->SetController(nullptr);
    filter->SetInputData(input);
    filter->SetInputArrayToProcess(0, 0, 0, r.Association, r.ArrayName.c_str());
    filter->SetColorTransferFunction(r.Color);
    filter->SetOpacityFunction(r.Opacity);
    filter->SetScalarOpacityUnitDistance(r.UnitDistance);
    filter->SetResolutionScale(scale);
    filter->SetChromaticAttenuation(r.Chromatic);
    filter->SetAmbientOcclusion(r.AmbientOcclusion);
    filter->SetAmbientOcclusionRadius(r.AmbientOcclusionRadius);
    if (auto* shadows = vtkFilteredVolumetricShadows::SafeDownCast(filter))
    {
      shadows->SetFilterWidth(r.FilterWidth);
      shadows->SetFilterKernel(r.FilterKernel);
    }
  };
  if (r.CoarseFirst)
  {
    if (!this->Coarse || this->CoarseMethod != r.Method)
    {
      this->Coarse = NewFilter(r.Method);
      this->CoarseMethod = r.Method;
    }
    if (this->CoarseSource != r.Input)
    {
      // Every CoarseStride-th sample: the coarse stage classifies and sweeps a data set
      // CoarseStride^3 times smaller (the propagation's cost follows the data, not only the
      // illumination grid).
      vtkNew<vtkExtractVOI> subsample;
      subsample->SetInputData(r.Input);
      subsample->SetSampleRate(CoarseStride, CoarseStride, CoarseStride);
      subsample->Update();
      this->CoarseInput = subsample->GetOutput();
      this->CoarseSource = r.Input;
    }
    configure(this->Coarse, this->CoarseInput, 1.0);
  }
  vtkIlluminationVolumeAlgorithm* filter = this->FilterFor(r.Method);
  configure(filter, r.Input, r.Scale);
  job.RunStages(r.CoarseFirst ? this->Coarse.Get() : nullptr, filter, r.Kind, this->Published,
    [](vtkDataObject* output)
    {
      auto* image = vtkImageData::SafeDownCast(output);
      return image && image->GetNumberOfPoints() > 0;
    });
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeRepresentation::RemoveFromView(vtkView* view)
{
  this->Internals->Start.Detach();
  this->Internals->Forget();
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    this->GetIlluminatedMapper()->ReleaseGraphicsResources(rview->GetRenderWindow());
  }
  return this->Superclass::RemoveFromView(view);
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::SetVisibility(bool visible)
{
  if (!visible)
  {
    this->Internals->Forget(); // a hidden representation renders nothing it could take
  }
  this->Superclass::SetVisibility(visible);
}

//------------------------------------------------------------------------------
double* vtkIlluminatedVolumeRepresentation::GetMeanIllumination()
{
  volillum::MeanIllumination(
    this->GetIlluminatedMapper()->GetIlluminationData(), this->MeanIllumination, this->MeanTime);
  return this->MeanIllumination;
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeRepresentation::GetDistributedIllumination() const
{
  return this->Internals->Controller != nullptr;
}

//------------------------------------------------------------------------------
int vtkIlluminatedVolumeRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->Internals->Vectors = nullptr;
  this->Internals->Reduced = nullptr;
  if (!this->Superclass::RequestData(request, inputVector, outputVector))
  {
    return 0;
  }
  this->ReduceColouredVectors();
  auto& internals = *this->Internals;
  internals.Controller = volillum::ParallelRun(vtkMultiProcessController::GetGlobalController());
  if (!internals.Controller)
  {
    return 1;
  }
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  }
  internals.Piece->SetOutput(vtkImageData::SafeDownCast(this->Cache));
  internals.Piece->SetWholeExtent(whole);
  return 1;
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::ReduceColouredVectors()
{
  auto& internals = *this->Internals;
  auto* image = vtkImageData::SafeDownCast(this->Cache);
  volillum::ColouredArray coloured;
  vtkDataArray* array = volillum::ColouredArrayOf(this, image, coloured);
  if (!array || array->GetNumberOfComponents() < 2 || !this->MapScalars ||
    this->MultiComponentsMapping || this->UseSeparateOpacityArray)
  {
    return; // one component already, or the components are mapped as they are
  }
  vtkDataSetAttributes* attributes = image->GetAttributes(
    coloured.Association == vtkDataObject::FIELD_ASSOCIATION_CELLS ? vtkDataObject::CELL
                                                                   : vtkDataObject::POINT);
  const bool active = attributes->GetScalars() == attributes->GetArray(coloured.Name);
  // Floating-point values (double for double vectors), under the vectors' name.
  if (array->GetDataType() == VTK_DOUBLE)
  {
    internals.Reduced = vtkSmartPointer<vtkDoubleArray>::New();
  }
  else
  {
    internals.Reduced = vtkSmartPointer<vtkFloatArray>::New();
  }
  internals.Reduced->SetName(array->GetName());
  internals.Reduced->SetNumberOfTuples(array->GetNumberOfTuples());
  internals.Component = volillum::ColouredComponent(this->Property);
  volillum::FillSingleComponent(array, internals.Component, internals.Reduced);
  internals.Vectors = array;
  attributes->RemoveArray(coloured.Name);
  if (active)
  {
    attributes->SetScalars(internals.Reduced);
  }
  else
  {
    attributes->AddArray(internals.Reduced);
  }
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::UpdateVectorMode()
{
  // ParaView changes the vector mode on the colour map alone (the data is not updated): the
  // values are made anew in place, in the array the rendered data shares with the cache.
  auto& internals = *this->Internals;
  if (!internals.Reduced)
  {
    return;
  }
  const int component = volillum::ColouredComponent(this->Property);
  if (component != internals.Component)
  {
    internals.Background.Stop(); // a running lighting reads the values rewritten here
    internals.HasSubmitted = false;
    internals.Component = component;
    volillum::FillSingleComponent(internals.Vectors, component, internals.Reduced);
  }
}

//------------------------------------------------------------------------------
int vtkIlluminatedVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  if (request == vtkPVView::REQUEST_RENDER())
  {
    // Lit as the render starts, with the camera it renders (see volillum::RenderStart).
    this->Internals->Start.Arm(vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW())),
      [this](vtkPVRenderView* view)
      {
        this->UpdateVectorMode();
        this->UpdateIllumination(view);
      });
  }
  return 1;
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeRepresentation::UpdateFilter(vtkIlluminationVolumeAlgorithm* filter)
{
  this->Internals->Background.Run(
    [filter](volillum::BackgroundLighting::Job& job) { job.Update(filter); }, this);
  vtkImageData* output = filter->GetOutput();
  if (!output || output->GetNumberOfPoints() == 0)
  {
    return false;
  }
  volillum::ReadUpdateFieldData(output->GetFieldData(), this->Report, this->UpdateSeconds);
  return true;
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::UpdateIllumination(vtkPVRenderView* view)
{
  vtkIlluminatedVolumeMapper* mapper = this->GetIlluminatedMapper();
  const bool interactiveFrame = volillum::IsInteractiveRender(view);
  SetSampling(mapper, interactiveFrame ? Frame::Interactive : Frame::Still, 0.0);
  vtkNew<vtkInformation> info;
  info->Set(vtkPVView::VIEW(), view);
  vtkAlgorithmOutput* port = vtkPVRenderView::GetPieceProducer(info, this, 0);
  auto* image =
    port ? vtkImageData::SafeDownCast(port->GetProducer()->GetOutputDataObject(0)) : nullptr;
  // Pieces lit where they are: every process decides as the others do (the filter's update
  // is collective), a process without a piece takes part.
  auto& internals = *this->Internals;
  vtkMultiProcessController* together = internals.Controller;
  const bool empty = !image || image->GetNumberOfPoints() == 0;
  volillum::ColouredArray coloured;
  const bool lightable = volillum::ColouredScalars(this, image, coloured) != nullptr;
  if (!volillum::AllOk(together, lightable || (together && empty)))
  {
    // Nothing this representation can light: draw as the Volume representation does.
    internals.Forget();
    mapper->SetIlluminationData(nullptr);
    return;
  }
  if (!together)
  {
    this->LightSerially(view, image, interactiveFrame);
    return;
  }

  vtkIlluminationVolumeAlgorithm* filter = this->GetIlluminationFilter();
  if (volillum::AllOk(together,
        volillum::IsInteractiveRender(view) &&
          (empty || mapper->GetIlluminationData() == filter->GetOutput())))
  {
    return; // keep the current illumination while the camera moves
  }

  internals.Lights.Update(view, this->UseLightKit);
  internals.Lights.ApplyTo(filter);
  volillum::SetVolumeInput(
    filter, together ? internals.Piece->GetOutputPort() : port, coloured, this->Property);
  filter->SetResolutionScale(this->ResolutionScale);
  filter->SetChromaticAttenuation(this->ChromaticAttenuation);
  filter->SetAmbientOcclusion(this->AmbientOcclusion);
  filter->SetAmbientOcclusionRadius(this->AmbientOcclusionRadius);
  if (auto* shadows = vtkFilteredVolumetricShadows::SafeDownCast(filter))
  {
    shadows->SetFilterWidth(this->ShadowFilterWidth);
    shadows->SetFilterKernel(this->ShadowFilterKernel);
  }
  // Every process updates the filter, or none.
  if (!volillum::MustUpdateTogether(together, filter,
        std::max(internals.Piece->GetMTime(), image ? image->GetMTime() : vtkMTimeType(0))))
  {
    return; // the mapper has the current illumination (none for an empty piece)
  }
  if (!this->UpdateFilter(filter))
  {
    mapper->SetIlluminationData(nullptr);
    return;
  }
  mapper->SetIlluminationData(filter->GetOutput());
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::LightSerially(
  vtkPVRenderView* view, vtkImageData* image, bool interactive)
{
  auto& internals = *this->Internals;
  this->ShowFinishedLighting();
  vtkIlluminatedVolumeMapper* mapper = this->GetIlluminatedMapper();
  if (interactive && mapper->GetIlluminationData())
  {
    return; // keep the current illumination while the camera moves
  }
  volillum::ColouredArray coloured;
  volillum::ColouredScalars(this, image, coloured);
  LightingRequest request = internals.MakeRequest(this, view, image, coloured);
  const double scale = request.Scale;
  const auto plan = internals.Shown.Costs.Choose(
    request.Kind, request.Input->GetNumberOfPoints() * scale * scale * scale);
  const bool changed = !internals.HasSubmitted || !request.SameAs(internals.Submitted);
  // A screenshot shows the final illumination: its render waits for it.
  if (!this->AsynchronousLighting || volillum::InScreenshot(view) ||
    (changed && plan == volillum::LightingCosts::Plan::Now && !internals.Background.Busy()))
  {
    internals.Submitted = request;
    internals.HasSubmitted = true;
    internals.Background.Run([&internals, request](volillum::BackgroundLighting::Job& job)
      { internals.Light(request, job); },
      this);
    this->ShowFinishedLighting();
    return;
  }
  if (!changed)
  {
    if (!internals.Background.Busy() && !internals.Shown.Final)
    {
      // Cancelled after a coarse stage: back to the last finished illumination.
      mapper->SetIlluminationData(vtkImageData::SafeDownCast(internals.Shown.LastFinal));
      internals.Shown.Final = true;
      this->MeanTime = vtkTimeStamp(); // the mean of what is drawn now
    }
  }
  else
  {
    request.CoarseFirst = scale > CoarseScale && plan == volillum::LightingCosts::Plan::CoarseFirst;
    internals.Submitted = request;
    internals.HasSubmitted = true;
    internals.Background.Start([&internals, request](volillum::BackgroundLighting::Job& job)
      { internals.Light(request, job); });
  }
  if (!interactive && this->GetIlluminationPending())
  {
    const double* spacing = image->GetSpacing();
    SetSampling(mapper, Frame::Preview,
      std::min({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) }));
  }
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::ShowFinishedLighting()
{
  auto& internals = *this->Internals;
  volillum::BackgroundLighting::Result result;
  if (!internals.Background.Take(result))
  {
    return;
  }
  vtkIlluminatedVolumeMapper* mapper = this->GetIlluminatedMapper();
  internals.Shown.Final = result.Final;
  if (result.Unchanged)
  {
    // The last final illumination holds (a coarse one, or none, may be drawn meanwhile).
    mapper->SetIlluminationData(vtkImageData::SafeDownCast(internals.Shown.LastFinal));
    return;
  }
  mapper->SetIlluminationData(vtkImageData::SafeDownCast(result.Data));
  this->MeanTime = vtkTimeStamp();
  internals.Shown.KeepFinal(result, this->Report, this->UpdateSeconds);
}

//------------------------------------------------------------------------------
int vtkIlluminatedVolumeRepresentation::GetIlluminationPending()
{
  const auto& internals = *this->Internals;
  return internals.Background.Busy() || internals.Background.Ready() || !internals.Shown.Final;
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::CancelIllumination()
{
  this->Internals->Background.Cancel();
}

//------------------------------------------------------------------------------
void vtkIlluminatedVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IlluminationMethod: " << this->IlluminationMethod << "\n";
  os << indent << "ResolutionScale: " << this->ResolutionScale << "\n";
  os << indent << "ChromaticAttenuation: " << this->ChromaticAttenuation << "\n";
  os << indent << "ShadowFilterWidth: " << this->ShadowFilterWidth << "\n";
  os << indent << "AmbientOcclusion: " << this->AmbientOcclusion << "\n";
  os << indent << "AmbientOcclusionRadius: " << this->AmbientOcclusionRadius << "\n";
  os << indent << "ShadowFilterKernel: " << this->ShadowFilterKernel << "\n";
  os << indent << "AsynchronousLighting: " << this->AsynchronousLighting << "\n";
  os << indent << "UseLightKit: " << this->UseLightKit << "\n";
  os << indent << "UpdateMode: " << this->Report.Mode << "\n";
  os << indent << "UpdateSeconds: " << this->UpdateSeconds << "\n";
  os << indent << "PropagationPasses: " << this->Report.Passes << "\n";
  os << indent << "MeanIllumination: " << this->MeanIllumination[0] << " "
     << this->MeanIllumination[1] << " " << this->MeanIllumination[2] << "\n";
  os << indent << "PendingPasses: " << this->Report.PendingPasses << "\n";
  os << indent << "DistributedIllumination: " << this->GetDistributedIllumination() << "\n";
}
