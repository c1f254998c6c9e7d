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
#include "vtkTrivialProducer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnstructuredGridIllumination.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeRepresentationPreprocessor.h"

struct vtkIlluminatedUnstructuredGridRepresentation::vtkInternals
{
  volillum::ViewLights Lights;
  volillum::RenderStart Start;
  bool Lit = false; // whether the last render drew the lit grid
  // A parallel run (pvserver or pvbatch under MPI): the whole grid assembled from every
  // process's piece when the data updates (all processes update together), lit at render
  // time without further communication; the piece this process renders takes its points'
  // values (matched once per piece and whole grid).
  volillum::DistributedInput Distributed;
  vtkNew<vtkTrivialProducer> Whole;
  bool Parallel = false;
  vtkNew<vtkUnstructuredGrid> LitPiece;
  std::vector<vtkIdType> PiecePoints;
  vtkMTimeType PieceTime = 0, WholeTime = 0;
};

vtkStandardNewMacro(vtkIlluminatedUnstructuredGridRepresentation);

//------------------------------------------------------------------------------
vtkIlluminatedUnstructuredGridRepresentation::vtkIlluminatedUnstructuredGridRepresentation()
  : Internals(new vtkInternals)
{
  this->Illumination->SetLitColors(true);
  this->Illumination->SetController(nullptr); // it lights what it is given (see Whole)
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
int vtkIlluminatedUnstructuredGridRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestData(request, inputVector, outputVector))
  {
    return 0;
  }
  auto& internals = *this->Internals;
  vtkMultiProcessController* controller =
    volillum::ParallelRun(vtkMultiProcessController::GetGlobalController());
  internals.Parallel = controller != nullptr;
  if (controller)
  {
    internals.Whole->SetOutput(internals.Distributed.Grid(controller, this,
      vtkUnstructuredGrid::SafeDownCast(this->Preprocessor->GetOutputDataObject(0))));
  }
  return 1;
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
  volillum::ColouredArray coloured;
  vtkDataArray* array = volillum::ColouredArrayOf(this, grid, coloured);
  if (!array || grid->GetNumberOfCells() == 0)
  {
    return false;
  }
  // Vectors are lit by what the colour map shows of them: their magnitude or a component;
  // vectors mapped as they are (colours, or a separate opacity component) are not lit.
  const bool vectors = array->GetNumberOfComponents() > 1;
  if (vectors &&
    (!this->MapScalars || this->MultiComponentsMapping || this->UseSeparateOpacityArray))
  {
    return false;
  }
  this->Illumination->SetScalarComponent(
    vectors ? volillum::ColouredComponent(this->Property) : -1);
  this->LitProperty->SetScalarOpacityUnitDistance(this->Property->GetScalarOpacityUnitDistance(0));
  if (volillum::IsInteractiveRender(view) && this->Internals->Lit)
  {
    return true; // keep the current lighting while the camera moves
  }
  auto& internals = *this->Internals;
  internals.Lights.Update(view, this->UseLightKit);
  internals.Lights.ApplyTo(this->Illumination.Get());
  volillum::SetVolumeInput(this->Illumination.Get(),
    internals.Parallel ? internals.Whole->GetOutputPort() : port, coloured, this->Property);
  this->Illumination->Update();
  vtkUnstructuredGrid* lit = this->Illumination->GetOutput();
  if (!lit || !lit->GetPointData()->GetArray("LitColors"))
  {
    return false;
  }
  volillum::ReadUpdateFieldData(lit->GetFieldData(), this->Report, this->UpdateSeconds);
  if (!internals.Parallel)
  {
    this->LitMapper->SetInputConnection(this->Illumination->GetOutputPort());
    return true;
  }
  // This process draws its own piece, with the values of the whole grid's lighting.
  vtkDataObject* whole = internals.Whole->GetOutputDataObject(0);
  if (grid->GetMTime() != internals.PieceTime || whole->GetMTime() != internals.WholeTime)
  {
    internals.PiecePoints = volillum::MatchPoints(vtkDataSet::SafeDownCast(whole), grid);
    internals.PieceTime = grid->GetMTime();
    internals.WholeTime = whole->GetMTime();
  }
  internals.LitPiece->ShallowCopy(grid);
  volillum::AddPointValues(lit, internals.PiecePoints, { "LitColors" }, internals.LitPiece);
  this->LitMapper->SetInputData(internals.LitPiece);
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
