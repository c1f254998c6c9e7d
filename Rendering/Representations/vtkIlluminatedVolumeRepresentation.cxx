#include "vtkIlluminatedVolumeRepresentation.h"

#include "IlluminationFilterSupport.h"
#include "IlluminationParallel.h"
#include "IlluminationViewLights.h"
#include "vtkAlgorithmOutput.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
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
#include "vtkRayMarchedIllumination.h"
#include "vtkRenderWindow.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTrivialProducer.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <array>

struct vtkIlluminatedVolumeRepresentation::vtkInternals
{
  volillum::ViewLights Lights;
  volillum::RenderStart Start;
  // One filter per method, created when first used; only the active one is kept.
  std::array<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>, 3> Filters;
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
vtkIlluminationVolumeAlgorithm* vtkIlluminatedVolumeRepresentation::GetIlluminationFilter()
{
  auto& filters = this->Internals->Filters;
  for (int m = 0; m < static_cast<int>(filters.size()); ++m)
  {
    if (m != this->IlluminationMethod)
    {
      filters[m] = nullptr; // one illumination volume in memory at a time
    }
  }
  auto& filter = filters[this->IlluminationMethod];
  if (!filter)
  {
    switch (this->IlluminationMethod)
    {
      case FilteredShadows:
        filter = vtkSmartPointer<vtkFilteredVolumetricShadows>::New();
        break;
      case RayMarchedReference:
        filter = vtkSmartPointer<vtkRayMarchedIllumination>::New();
        break;
      default:
        filter = vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
        break;
    }
    volillum::ForwardProgress(filter, this);
  }
  // Pieces lit where they are in a parallel run (see vtkInternals).
  filter->SetController(this->Internals->Controller);
  return filter;
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeRepresentation::RemoveFromView(vtkView* view)
{
  this->Internals->Start.Detach();
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    this->GetIlluminatedMapper()->ReleaseGraphicsResources(rview->GetRenderWindow());
  }
  return this->Superclass::RemoveFromView(view);
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
  filter->Update();
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
  // Sample as the Volume representation does (vtkSmartVolumeMapper): still renders every
  // half voxel or finer (the distance locked to the data's spacing), interactive ones as the
  // frame rate allows. Still frames jitter the ray starts within that step, which keeps them
  // no grainier than plain Volume's and free of rings; interactive frames, whose steps are
  // coarse, start every ray one step in, as plain Volume's do.
  const bool interactiveFrame = volillum::IsInteractiveRender(view);
  mapper->SetAutoAdjustSampleDistances(interactiveFrame);
  mapper->SetLockSampleDistanceToInputSpacing(!interactiveFrame);
  mapper->SetJitteredRayStarts(!interactiveFrame);
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
    mapper->SetIlluminationData(nullptr);
    return;
  }

  vtkIlluminationVolumeAlgorithm* filter = this->GetIlluminationFilter();
  auto* propagation = vtkMultiLightIlluminationVolume::SafeDownCast(filter);
  const bool progressive = propagation && this->MaximumPassesPerUpdate > 0;
  const bool interactive = volillum::AllOk(together, volillum::IsInteractiveRender(view));
  if (volillum::AllOk(together,
        interactive && !progressive &&
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
  if (propagation)
  {
    // Interactive renders refine progressively; a still render completes the update.
    propagation->SetMaximumPassesPerUpdate(interactive ? this->MaximumPassesPerUpdate : 0);
  }
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
void vtkIlluminatedVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IlluminationMethod: " << this->IlluminationMethod << "\n";
  os << indent << "ResolutionScale: " << this->ResolutionScale << "\n";
  os << indent << "ChromaticAttenuation: " << this->ChromaticAttenuation << "\n";
  os << indent << "ShadowFilterWidth: " << this->ShadowFilterWidth << "\n";
  os << indent << "ShadowFilterKernel: " << this->ShadowFilterKernel << "\n";
  os << indent << "MaximumPassesPerUpdate: " << this->MaximumPassesPerUpdate << "\n";
  os << indent << "UseLightKit: " << this->UseLightKit << "\n";
  os << indent << "UpdateMode: " << this->Report.Mode << "\n";
  os << indent << "UpdateSeconds: " << this->UpdateSeconds << "\n";
  os << indent << "PropagationPasses: " << this->Report.Passes << "\n";
  os << indent << "MeanIllumination: " << this->MeanIllumination[0] << " "
     << this->MeanIllumination[1] << " " << this->MeanIllumination[2] << "\n";
  os << indent << "PendingPasses: " << this->Report.PendingPasses << "\n";
  os << indent << "DistributedIllumination: " << this->GetDistributedIllumination() << "\n";
}
