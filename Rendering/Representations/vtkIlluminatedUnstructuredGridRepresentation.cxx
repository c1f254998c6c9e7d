#include "vtkIlluminatedUnstructuredGridRepresentation.h"

#include "IlluminationBackground.h"
#include "IlluminationViewLights.h"
#include "ParallelCollectives.h"
#include "vtkAlgorithmOutput.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
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
#include <array>
#include <string>
#include <vector>

namespace
{
// What a serial lighting reads, owned by the job (as for image data).
struct GridRequest
{
  std::vector<volillum::LightValues> Lights;
  vtkSmartPointer<vtkDataSet> Input;
  std::string ArrayName;
  int Association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  int Component = -1;
  vtkSmartPointer<vtkColorTransferFunction> Color;
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
  double UnitDistance = 1.0;
  bool Chromatic = false;
  std::array<int, 3> Level0{ { 64, 64, 64 } };
  double Absorption = 1.0;
  std::array<double, 3> Scattering{ { 0.0, 0.0, 0.0 } };
  int ScatteringIterations = 10;
  double Exposure = 5.0;
  bool CoarseFirst = false;
  int Kind = -1; // -1 everything changed, otherwise the number of lights that did

  bool SameInputsAs(const GridRequest& o) const
  {
    return this->Input == o.Input && this->ArrayName == o.ArrayName &&
      this->Association == o.Association && this->Component == o.Component &&
      this->Color == o.Color && this->Opacity == o.Opacity &&
      this->UnitDistance == o.UnitDistance && this->Chromatic == o.Chromatic &&
      this->Level0 == o.Level0 && this->Absorption == o.Absorption &&
      this->Scattering == o.Scattering && this->ScatteringIterations == o.ScatteringIterations &&
      this->Exposure == o.Exposure;
  }
  bool SameAs(const GridRequest& o) const
  {
    return this->SameInputsAs(o) && this->Lights == o.Lights;
  }
};
}

struct vtkIlluminatedUnstructuredGridRepresentation::vtkInternals
{
  volillum::ViewLights Lights;
  volillum::RenderStart Start;
  bool Lit = false; // whether the last render drew the lit grid
  // What the lit mapper draws: a copy of the filter's output, so that a render that pulls on
  // the mapper (its bounds) never updates the filter, whose update is collective in parallel.
  vtkNew<vtkUnstructuredGrid> LitGrid;

  // A serial run: the job owns the filter (the representation's Illumination), Coarse (level 0
  // alone), Lights and Published while it runs; the render thread goes through Background,
  // declared after them so that its worker is joined before they go.
  vtkNew<vtkUnstructuredGridIllumination> Coarse;
  vtkMTimeType Published = 0;
  volillum::BackgroundLighting Background;
  GridRequest Submitted;
  bool HasSubmitted = false;
  volillum::JobCopies Copies;
  volillum::ShownLighting Shown;

  /// Nothing to light or draw any more: stop the lighting, drop what it left to draw.
  void Forget()
  {
    this->Background.Cancel();
    this->Background.Discard();
    this->HasSubmitted = false;
    this->Shown.Final = true;
  }
  void Light(vtkUnstructuredGridIllumination* filter, const GridRequest& request,
    volillum::BackgroundLighting::Job& job);
};

vtkStandardNewMacro(vtkIlluminatedUnstructuredGridRepresentation);

//------------------------------------------------------------------------------
vtkIlluminatedUnstructuredGridRepresentation::vtkIlluminatedUnstructuredGridRepresentation()
  : Internals(new vtkInternals)
{
  this->Illumination->SetLitColors(true);
  this->Internals->Coarse->SetLitColors(true);
  this->Internals->Coarse->SetLevel1Iterations(0); // level 0 alone
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
bool vtkIlluminatedUnstructuredGridRepresentation::RemoveFromView(vtkView* view)
{
  this->Internals->Start.Detach();
  this->Internals->Forget();
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    this->LitMapper->ReleaseGraphicsResources(rview->GetRenderWindow());
  }
  return this->Superclass::RemoveFromView(view);
}

//------------------------------------------------------------------------------
double* vtkIlluminatedUnstructuredGridRepresentation::GetMeanIllumination()
{
  volillum::MeanIllumination(this->Internals->Lit ? this->Internals->LitGrid.Get() : nullptr,
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
    this->Internals->Forget();
    return false;
  }
  this->LitProperty->SetScalarOpacityUnitDistance(this->Property->GetScalarOpacityUnitDistance(0));
  auto& internals = *this->Internals;
  const int component = vectors ? volillum::ColouredComponent(this->Property) : -1;
  if (!together)
  {
    return this->LightSerially(view, grid, volillum::IsInteractiveRender(view), coloured.Name,
      coloured.Association, component);
  }
  if (volillum::AllOk(together, volillum::IsInteractiveRender(view) && (empty || internals.Lit)))
  {
    return internals.Lit; // keep the current lighting while the camera moves
  }
  vtkUnstructuredGridIllumination* filter = this->Illumination;
  this->Configure(filter);
  filter->SetScalarComponent(component);
  internals.Lights.Update(view, this->UseLightKit);
  internals.Lights.ApplyTo(filter);
  volillum::SetVolumeInput(filter, port, coloured, this->Property);
  // Every process updates the filter, or none.
  if (volillum::MustUpdateTogether(together, filter, grid ? grid->GetMTime() : vtkMTimeType(0)))
  {
    internals.Background.Run(
      [filter](volillum::BackgroundLighting::Job& job) { job.Update(filter); }, this);
  }
  vtkUnstructuredGrid* lit = filter->GetOutput();
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
void vtkIlluminatedUnstructuredGridRepresentation::Configure(
  vtkUnstructuredGridIllumination* filter) const
{
  filter->SetChromaticAttenuation(this->ChromaticAttenuation);
  filter->SetLevel0Resolution(const_cast<int*>(this->Level0Resolution));
  filter->SetAbsorption(this->Absorption);
  filter->SetScatteringStrength(const_cast<double*>(this->ScatteringStrength));
  filter->SetScatteringIterations(this->ScatteringIterations);
  filter->SetExposure(this->Exposure);
}

//------------------------------------------------------------------------------
bool vtkIlluminatedUnstructuredGridRepresentation::LightSerially(vtkPVRenderView* view,
  vtkUnstructuredGrid* grid, bool interactive, const char* array, int association, int component)
{
  auto& internals = *this->Internals;
  this->ShowFinishedLighting();
  if (interactive && internals.Lit)
  {
    return true; // keep the current lighting while the camera moves
  }
  GridRequest r;
  r.Lights = volillum::ReadViewLights(view, this->UseLightKit, false);
  r.Input = internals.Copies.Data(grid);
  r.ArrayName = array ? array : "";
  r.Association = association;
  r.Component = component;
  r.Color = internals.Copies.Color(this->Property->GetRGBTransferFunction(0));
  r.Opacity = internals.Copies.Opacity(this->Property->GetScalarOpacity(0));
  r.UnitDistance = this->Property->GetScalarOpacityUnitDistance(0);
  r.Chromatic = this->ChromaticAttenuation;
  std::copy_n(this->Level0Resolution, 3, r.Level0.begin());
  r.Absorption = this->Absorption;
  std::copy_n(this->ScatteringStrength, 3, r.Scattering.begin());
  r.ScatteringIterations = this->ScatteringIterations;
  r.Exposure = this->Exposure;
  if (internals.HasSubmitted && r.SameInputsAs(internals.Submitted))
  {
    r.Kind = volillum::ChangedLights(r.Lights, internals.Submitted.Lights);
  }
  // The filter reads the range of the array it lights: computed here first, so that the job
  // only reads the range the array keeps (the render thread may ask for it meanwhile).
  volillum::ColouredArray coloured;
  if (vtkDataArray* scalars = volillum::ColouredArrayOf(this, grid, coloured))
  {
    scalars->GetRange(component);
  }
  vtkUnstructuredGridIllumination* filter = this->Illumination;
  const auto plan = internals.Shown.Costs.Choose(r.Kind, grid->GetNumberOfPoints());
  const bool changed = !internals.HasSubmitted || !r.SameAs(internals.Submitted);
  // A screenshot shows the final lighting: its render waits for it.
  if (!this->AsynchronousLighting || volillum::InScreenshot(view) ||
    (changed && plan == volillum::LightingCosts::Plan::Now && !internals.Background.Busy()))
  {
    internals.Submitted = r;
    internals.HasSubmitted = true;
    internals.Background.Run([&internals, filter, r](volillum::BackgroundLighting::Job& job)
      { internals.Light(filter, r, job); },
      this);
    return this->ShowFinishedLighting();
  }
  if (changed)
  {
    r.CoarseFirst = plan == volillum::LightingCosts::Plan::CoarseFirst;
    internals.Submitted = r;
    internals.HasSubmitted = true;
    internals.Background.Start([&internals, filter, r](volillum::BackgroundLighting::Job& job)
      { internals.Light(filter, r, job); });
  }
  else if (!internals.Background.Busy() && !internals.Shown.Final)
  {
    // Cancelled after the level-0 stage: back to the last finished lighting.
    this->DrawLastFinal();
  }
  return internals.Lit;
}

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::vtkInternals::Light(
  vtkUnstructuredGridIllumination* filter, const GridRequest& r,
  volillum::BackgroundLighting::Job& job)
{
  this->Lights.Update(r.Lights);
  auto configure = [&](vtkUnstructuredGridIllumination* f)
  {
    this->Lights.ApplyTo(f);
    f->SetController(nullptr);
    f->SetInputData(r.Input);
    f->SetInputArrayToProcess(0, 0, 0, r.Association, r.ArrayName.c_str());
    f->SetScalarComponent(r.Component);
    f->SetColorTransferFunction(r.Color);
    f->SetOpacityFunction(r.Opacity);
    f->SetScalarOpacityUnitDistance(r.UnitDistance);
    f->SetChromaticAttenuation(r.Chromatic);
    f->SetLevel0Resolution(r.Level0[0], r.Level0[1], r.Level0[2]);
    f->SetAbsorption(r.Absorption);
    f->SetScatteringStrength(r.Scattering[0], r.Scattering[1], r.Scattering[2]);
    f->SetScatteringIterations(r.ScatteringIterations);
    f->SetExposure(r.Exposure);
  };
  if (r.CoarseFirst)
  {
    configure(this->Coarse);
  }
  configure(filter);
  job.RunStages(r.CoarseFirst ? this->Coarse.Get() : nullptr, filter, r.Kind, this->Published,
    [](vtkDataObject* output)
    {
      auto* grid = vtkUnstructuredGrid::SafeDownCast(output);
      return grid && grid->GetPointData()->GetArray("LitColors");
    });
}

//------------------------------------------------------------------------------
bool vtkIlluminatedUnstructuredGridRepresentation::ShowFinishedLighting()
{
  auto& internals = *this->Internals;
  volillum::BackgroundLighting::Result result;
  if (!internals.Background.Take(result))
  {
    return internals.Lit;
  }
  if (result.Unchanged)
  {
    if (!internals.Shown.Final || !internals.Lit)
    {
      this->DrawLastFinal(); // the last final lighting holds; another is drawn meanwhile
    }
    return internals.Lit;
  }
  internals.Shown.Final = result.Final;
  internals.Lit = result.Data != nullptr;
  if (internals.Lit)
  {
    internals.LitGrid->ShallowCopy(result.Data);
    this->LitMapper->SetInputData(internals.LitGrid);
  }
  this->MeanTime = vtkTimeStamp();
  internals.Shown.KeepFinal(result, this->Report, this->UpdateSeconds);
  return internals.Lit;
}

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::DrawLastFinal()
{
  auto& internals = *this->Internals;
  internals.Lit = internals.Shown.LastFinal != nullptr; // none yet: drawn unlit
  if (internals.Lit)
  {
    internals.LitGrid->ShallowCopy(internals.Shown.LastFinal);
    this->LitMapper->SetInputData(internals.LitGrid);
  }
  internals.Shown.Final = true;
  this->MeanTime = vtkTimeStamp();
}

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::SetVisibility(bool visible)
{
  if (!visible)
  {
    this->Internals->Forget(); // a hidden representation renders nothing it could take
  }
  this->Superclass::SetVisibility(visible);
}

//------------------------------------------------------------------------------
int vtkIlluminatedUnstructuredGridRepresentation::GetIlluminationPending()
{
  const auto& internals = *this->Internals;
  return internals.Background.Busy() || internals.Background.Ready() || !internals.Shown.Final;
}

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::CancelIllumination()
{
  this->Internals->Background.Cancel();
}

//------------------------------------------------------------------------------
void vtkIlluminatedUnstructuredGridRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IlluminationMethod: " << this->IlluminationMethod << "\n";
  os << indent << "UseLightKit: " << this->UseLightKit << "\n";
  os << indent << "AsynchronousLighting: " << this->AsynchronousLighting << "\n";
  os << indent << "UpdateMode: " << this->Report.Mode << "\n";
  os << indent << "UpdateSeconds: " << this->UpdateSeconds << "\n";
  os << indent << "PropagationPasses: " << this->Report.Passes << "\n";
  os << indent << "MeanIllumination: " << this->MeanIllumination[0] << " "
     << this->MeanIllumination[1] << " " << this->MeanIllumination[2] << "\n";
  os << indent << "Illumination: " << this->Illumination.Get() << "\n";
}
