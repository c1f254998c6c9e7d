#include "vtkIlluminatedUnstructuredGridRepresentation.h"

#include "IlluminationParallel.h"
#include "IlluminationViewLights.h"
#include "vtkAlgorithmOutput.h"
#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkProjectedTetrahedraMapper.h"
#include "vtkRenderWindow.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnstructuredGridIllumination.h"
#include "vtkVolumeProperty.h"

#include <algorithm>

struct vtkIlluminatedUnstructuredGridRepresentation::vtkInternals
{
  volillum::ViewLights Lights;
  volillum::RenderStart Start;
  bool Lit = false; // whether the last render drew the lit grid
  // What the lit mapper draws: a copy of the filter's output, so that a render that pulls on
  // the mapper (its bounds) never updates the filter, whose update is collective in parallel.
  vtkNew<vtkUnstructuredGrid> LitGrid;
};

vtkStandardNewMacro(vtkIlluminatedUnstructuredGridRepresentation);

//------------------------------------------------------------------------------
vtkIlluminatedUnstructuredGridRepresentation::vtkIlluminatedUnstructuredGridRepresentation()
  : Internals(new vtkInternals)
{
  this->Illumination->SetLitColors(true);
  volillum::ForwardProgress(this->Illumination, this);
  this->SetProgressText("Illuminating the grid");
  this->LitMapper->SetScalarModeToUsePointFieldData();
  this->LitMapper->SelectScalarArray("LitColors");
  // LitColors hold the colour and the opacity already: no lookup, alpha byte -> [0, 1].
  this->LitProperty->IndependentComponentsOff();
  vtkNew<vtkPiecewiseFunction> alpha;
  alpha->AddPoint(0.0, 0.0);
  alpha->AddPoint(255.0, 1.0);
  this->LitProperty->SetScalarOpacity(alpha);
}

//------------------------------------------------------------------------------
vtkIlluminatedUnstructuredGridRepresentation::~vtkIlluminatedUnstructuredGridRepresentation() =
  default;

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::SetChromaticAttenuation(bool enable)
{
  this->Illumination->SetChromaticAttenuation(enable);
}

void vtkIlluminatedUnstructuredGridRepresentation::SetLevel0Resolution(int x, int y, int z)
{
  this->Illumination->SetLevel0Resolution(x, y, z);
}

void vtkIlluminatedUnstructuredGridRepresentation::SetAbsorption(double value)
{
  this->Illumination->SetAbsorption(value);
}

void vtkIlluminatedUnstructuredGridRepresentation::SetScatteringStrength(
  double r, double g, double b)
{
  this->Illumination->SetScatteringStrength(r, g, b);
}

void vtkIlluminatedUnstructuredGridRepresentation::SetScatteringIterations(int count)
{
  this->Illumination->SetScatteringIterations(count);
}

void vtkIlluminatedUnstructuredGridRepresentation::SetExposure(double value)
{
  this->Illumination->SetExposure(value);
}

//------------------------------------------------------------------------------
bool vtkIlluminatedUnstructuredGridRepresentation::RemoveFromView(vtkView* view)
{
  this->Internals->Start.Detach();
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    this->LitMapper->ReleaseGraphicsResources(rview->GetRenderWindow());
  }
  return this->Superclass::RemoveFromView(view);
}

//------------------------------------------------------------------------------
double* vtkIlluminatedUnstructuredGridRepresentation::GetMeanIllumination()
{
  volillum::MeanIllumination(this->Internals->Lit ? this->Illumination->GetOutput() : nullptr,
    this->MeanIllumination, this->MeanTime);
  return this->MeanIllumination;
}

//------------------------------------------------------------------------------
int vtkIlluminatedUnstructuredGridRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  if (request == vtkPVView::REQUEST_RENDER() && !inInfo->Has(vtkPVRenderView::USE_LOD()))
  {
    // Lit as the render starts, with the camera it renders (see volillum::RenderStart).
    this->Internals->Start.Arm(vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW())),
      [this](vtkPVRenderView* view)
      {
        this->Internals->Lit = this->UpdateIllumination(view);
        if (this->Internals->Lit)
        {
          this->Actor->SetMapper(this->LitMapper);
          this->Actor->SetProperty(this->LitProperty);
        }
        else
        {
          this->Actor->SetProperty(this->Property);
        }
      });
  }
  return 1;
}

//------------------------------------------------------------------------------
bool vtkIlluminatedUnstructuredGridRepresentation::UpdateIllumination(vtkPVRenderView* view)
{
  vtkNew<vtkInformation> info;
  info->Set(vtkPVView::VIEW(), view);
  vtkAlgorithmOutput* port = vtkPVRenderView::GetPieceProducer(info, this);
  auto* grid =
    port ? vtkUnstructuredGrid::SafeDownCast(port->GetProducer()->GetOutputDataObject(0)) : nullptr;
  // In parallel the processes light their pieces together (the filter's update is
  // collective): every process decides as the others do, and one without cells takes part
  // (a piece of another type, as with the mapper that resamples to an image, is not lit).
  vtkMultiProcessController* together =
    volillum::ParallelRun(vtkMultiProcessController::GetGlobalController());
  const bool empty = grid && grid->GetNumberOfCells() == 0;
  volillum::ColouredArray coloured;
  vtkDataArray* array = volillum::ColouredArrayOf(this, grid, coloured);
  // Vectors are lit by what the colour map shows of them: their magnitude or a component;
  // vectors mapped as they are (colours, or a separate opacity component) are not lit.
  const bool vectors = array && array->GetNumberOfComponents() > 1;
  const bool lightable = array && !empty &&
    !(vectors &&
      (!this->MapScalars || this->MultiComponentsMapping || this->UseSeparateOpacityArray));
  if (!volillum::AllOk(together, lightable || (together && empty)) ||
    (together && volillum::AllOk(together, empty)))
  {
    return false;
  }
  this->LitProperty->SetScalarOpacityUnitDistance(this->Property->GetScalarOpacityUnitDistance(0));
  auto& internals = *this->Internals;
  if (volillum::AllOk(together, volillum::IsInteractiveRender(view) && (empty || internals.Lit)))
  {
    return internals.Lit; // keep the current lighting while the camera moves
  }
  this->Illumination->SetScalarComponent(
    vectors ? volillum::ColouredComponent(this->Property) : -1);
  internals.Lights.Update(view, this->UseLightKit);
  internals.Lights.ApplyTo(this->Illumination.Get());
  volillum::SetVolumeInput(this->Illumination.Get(), port, coloured, this->Property);
  // Every process updates the filter, or none.
  if (volillum::MustUpdateTogether(
        together, this->Illumination, grid ? grid->GetMTime() : vtkMTimeType(0)))
  {
    this->Illumination->Update();
  }
  vtkUnstructuredGrid* lit = this->Illumination->GetOutput();
  if (!lit || !lit->GetPointData()->GetArray("LitColors"))
  {
    return false;
  }
  volillum::ReadUpdateFieldData(lit->GetFieldData(), this->Report, this->UpdateSeconds);
  if (internals.LitGrid->GetMTime() < lit->GetMTime())
  {
    internals.LitGrid->ShallowCopy(lit);
  }
  this->LitMapper->SetInputData(internals.LitGrid);
  return true;
}

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IlluminationMethod: " << this->IlluminationMethod << "\n";
  os << indent << "UseLightKit: " << this->UseLightKit << "\n";
  os << indent << "UpdateMode: " << this->Report.Mode << "\n";
  os << indent << "UpdateSeconds: " << this->UpdateSeconds << "\n";
  os << indent << "PropagationPasses: " << this->Report.Passes << "\n";
  os << indent << "MeanIllumination: " << this->MeanIllumination[0] << " "
     << this->MeanIllumination[1] << " " << this->MeanIllumination[2] << "\n";
  os << indent << "Illumination: " << this->Illumination.Get() << "\n";
}
