#include "vtkIlluminatedVolumeRepresentation.h"

#include "IlluminationViewLights.h"
#include "vtkAlgorithmOutput.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkRayMarchedIllumination.h"
#include "vtkRenderWindow.h"

#include <array>

struct vtkIlluminatedVolumeRepresentation::vtkInternals
{
  volillum::ViewLights Lights;
  // One filter per method, created when first used; only the active one is kept.
  std::array<vtkSmartPointer<vtkIlluminationVolumeAlgorithm>, 3> Filters;
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
  return filter;
}

//------------------------------------------------------------------------------
bool vtkIlluminatedVolumeRepresentation::RemoveFromView(vtkView* view)
{
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
int vtkIlluminatedVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  if (request == vtkPVView::REQUEST_RENDER())
  {
    this->UpdateIllumination(inInfo);
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
void vtkIlluminatedVolumeRepresentation::UpdateIllumination(vtkInformation* inInfo)
{
  vtkIlluminatedVolumeMapper* mapper = this->GetIlluminatedMapper();
  auto* view = vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW()));
  vtkAlgorithmOutput* port = vtkPVRenderView::GetPieceProducer(inInfo, this, 0);
  auto* image =
    port ? vtkImageData::SafeDownCast(port->GetProducer()->GetOutputDataObject(0)) : nullptr;
  volillum::ColouredArray coloured;
  if (!volillum::ColouredScalars(this, image, coloured))
  {
    // Nothing this representation can light: draw as the Volume representation does.
    mapper->SetIlluminationData(nullptr);
    return;
  }

  vtkIlluminationVolumeAlgorithm* filter = this->GetIlluminationFilter();
  auto* propagation = vtkMultiLightIlluminationVolume::SafeDownCast(filter);
  const bool progressive = propagation && this->MaximumPassesPerUpdate > 0;
  const bool interactive = volillum::IsInteractiveRender(view);
  if (interactive && !progressive && mapper->GetIlluminationData() == filter->GetOutput())
  {
    return; // keep the current illumination while the camera moves
  }

  this->Internals->Lights.Update(view, this->UseLightKit);
  this->Internals->Lights.ApplyTo(filter);
  volillum::SetVolumeInput(filter, port, coloured, this->Property);
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
}
