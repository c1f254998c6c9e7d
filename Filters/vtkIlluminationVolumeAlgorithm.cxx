#include "vtkIlluminationVolumeAlgorithm.h"

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
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>

vtkCxxSetObjectMacro(
  vtkIlluminationVolumeAlgorithm, ColorTransferFunction, vtkColorTransferFunction);
vtkCxxSetObjectMacro(vtkIlluminationVolumeAlgorithm, OpacityFunction, vtkPiecewiseFunction);

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::ClassificationKey::operator==(const ClassificationKey& o) const
{
  return this->Scalars == o.Scalars && this->Color == o.Color && this->Opacity == o.Opacity &&
    this->Scale == o.Scale && this->UnitDistance == o.UnitDistance &&
    this->Chromatic == o.Chromatic;
}

//------------------------------------------------------------------------------
vtkIlluminationVolumeAlgorithm::vtkIlluminationVolumeAlgorithm()
{
  // Debian's ParaView defaults to the Sequential SMP backend; unless the user chose one
  // with VTK_SMP_BACKEND_IN_USE, the illumination filters run on every core.
  static const bool backendChosen = []
  {
    if (!std::getenv("VTK_SMP_BACKEND_IN_USE") &&
      std::string(vtkSMPTools::GetBackend()) == "Sequential")
    {
      vtkSMPTools::SetBackend("STDThread");
    }
    return true;
  }();
  (void)backendChosen;
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkIlluminationVolumeAlgorithm::~vtkIlluminationVolumeAlgorithm()
{
  this->SetColorTransferFunction(nullptr);
  this->SetOpacityFunction(nullptr);
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::AddLight(vtkLight* light)
{
  if (light)
  {
    this->Lights.emplace_back(light);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::RemoveAllLights()
{
  if (!this->Lights.empty())
  {
    this->Lights.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkLight* vtkIlluminationVolumeAlgorithm::GetLight(int index) const
{
  return index >= 0 && index < this->GetNumberOfLights() ? this->Lights[index].Get() : nullptr;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::SetNumberOfLightParameters(int count)
{
  if (count < 0 || count % volillum::LightParameterCount != 0)
  {
    vtkErrorMacro("The light list needs " << volillum::LightParameterCount
                                          << " numbers per light, got " << count << ".");
    return;
  }
  const size_t lights = static_cast<size_t>(count / volillum::LightParameterCount);
  if (lights == this->Lights.size())
  {
    return;
  }
  while (this->Lights.size() < lights)
  {
    this->Lights.push_back(vtkSmartPointer<vtkLight>::New());
  }
  this->Lights.resize(lights);
  this->Modified();
}

//------------------------------------------------------------------------------
int vtkIlluminationVolumeAlgorithm::GetNumberOfLightParameters() const
{
  return this->GetNumberOfLights() * volillum::LightParameterCount;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::SetLightParameter(int index, double value)
{
  const int light = index / volillum::LightParameterCount;
  if (index < 0 || light >= this->GetNumberOfLights())
  {
    vtkErrorMacro("Light parameter " << index << " is out of range.");
    return;
  }
  double p[volillum::LightParameterCount];
  volillum::GetLightParameters(this->Lights[light], p);
  p[index % volillum::LightParameterCount] = value;
  // vtkLight marks itself modified only for values that change.
  volillum::ApplyLightParameters(this->Lights[light], p);
}

//------------------------------------------------------------------------------
double vtkIlluminationVolumeAlgorithm::GetLightParameter(int index) const
{
  const int light = index / volillum::LightParameterCount;
  if (index < 0 || light >= this->GetNumberOfLights())
  {
    return 0.0;
  }
  double p[volillum::LightParameterCount];
  volillum::GetLightParameters(this->Lights[light], p);
  return p[index % volillum::LightParameterCount];
}

//------------------------------------------------------------------------------
std::vector<volillum::LightState> vtkIlluminationVolumeAlgorithm::GetLightStates() const
{
  std::vector<volillum::LightState> states;
  states.reserve(this->Lights.size());
  for (const auto& light : this->Lights)
  {
    states.push_back(volillum::CaptureLight(light));
  }
  return states;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkIlluminationVolumeAlgorithm::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  for (const auto& light : this->Lights)
  {
    t = std::max(t, light->GetMTime());
  }
  if (this->ColorTransferFunction)
  {
    t = std::max(t, this->ColorTransferFunction->GetMTime());
  }
  if (this->OpacityFunction)
  {
    t = std::max(t, this->OpacityFunction->GetMTime());
  }
  return t;
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
  double spacing[3], origin[3];
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
  // Light crosses the whole volume: always ask for all of the input.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkIlluminationVolumeAlgorithm::ReportProgress(double fraction)
{
  this->UpdateProgress(fraction);
  return !this->GetAbortExecute();
}

//------------------------------------------------------------------------------
int vtkIlluminationVolumeAlgorithm::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  const auto start = std::chrono::steady_clock::now();
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  if (!input)
  {
    vtkErrorMacro("The input is not a vtkImageData.");
    return 1;
  }
  volillum::GridGeometry data, target;
  if (!this->ValidGeometry(input, data, target))
  {
    return 1;
  }
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector);
  vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
  const char* requested = arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  if (!scalars && (!requested || !*requested))
  {
    // No array chosen (ParaView leaves the name empty when the input was not updated yet):
    // use the active point scalars.
    scalars = input->GetPointData()->GetScalars();
  }
  if (!scalars)
  {
    vtkAbstractArray* named = nullptr;
    int association = 0;
    named = this->GetInputAbstractArrayToProcess(0, input, association);
    if (named)
    {
      vtkErrorMacro("The array '" << (named->GetName() ? named->GetName() : "")
                                  << "' is not numeric; choose a numeric point array.");
    }
    else
    {
      vtkErrorMacro("The input has no point scalars to illuminate.");
    }
    return 1;
  }
  if (scalars->GetNumberOfTuples() != input->GetNumberOfPoints())
  {
    vtkErrorMacro("The scalars '" << (scalars->GetName() ? scalars->GetName() : "")
                                  << "' are not point data; choose a point array.");
    return 1;
  }

  const std::vector<volillum::LightState> lights = this->GetLightStates();
  for (size_t i = 0; i < lights.size(); ++i)
  {
    double p[volillum::LightParameterCount];
    volillum::GetLightParameters(this->Lights[i], p);
    for (double v : p)
    {
      if (!std::isfinite(v))
      {
        vtkErrorMacro("Light " << i << " has a parameter that is not a finite number.");
        return 1;
      }
    }
    if (lights[i].Intensity < 0.0)
    {
      vtkErrorMacro("Light " << i << " has a negative intensity.");
      return 1;
    }
  }

  ClassificationKey key;
  key.Scalars = scalars->GetMTime();
  key.Color = this->ColorTransferFunction ? this->ColorTransferFunction->GetMTime() : 0;
  key.Opacity = this->OpacityFunction ? this->OpacityFunction->GetMTime() : 0;
  key.Scale = this->ResolutionScale;
  key.UnitDistance = this->ScalarOpacityUnitDistance;
  key.Chromatic = this->ChromaticAttenuation;
  const bool inputModified = !this->HasClassification || !(key == this->ClassifiedKey) ||
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
    std::string error;
    long long nans = 0;
    this->HasClassification = false;
    if (!volillum::Classify(scalars, data, settings, this->Classified, error, &nans))
    {
      vtkErrorMacro("Cannot classify the input: " << error << ".");
      return 1;
    }
    if (nans > 0)
    {
      vtkWarningMacro(<< nans << " scalar values are NaN; they are treated as empty space.");
    }
    this->ClassifiedKey = key;
    this->HasClassification = true;
  }

  vtkNew<vtkFloatArray> illumination;
  illumination->SetName("Illumination");
  illumination->SetNumberOfComponents(3);
  illumination->SetNumberOfTuples(target.NumberOfPoints());
  UpdateReport report;
  if (!this->ComputeIllumination(
        this->Classified, lights, target, inputModified, illumination->GetPointer(0), report))
  {
    // Aborted: show what the last complete update produced.
    if (this->LastOutput)
    {
      output->ShallowCopy(this->LastOutput);
    }
    return 1;
  }

  output->SetDimensions(target.Dimensions.data());
  output->SetOrigin(target.Origin.data());
  output->SetSpacing(target.Spacing.data());
  output->GetPointData()->SetScalars(illumination);
  this->AddOutputArrays(output->GetPointData());

  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  vtkNew<vtkIntArray> mode;
  mode->SetName("UpdateMode");
  mode->InsertNextValue(report.Mode);
  vtkNew<vtkIntArray> passes;
  passes->SetName("PropagationPasses");
  passes->InsertNextValue(report.Passes);
  vtkNew<vtkDoubleArray> time;
  time->SetName("UpdateSeconds");
  time->InsertNextValue(seconds);
  vtkNew<vtkIntArray> pending;
  pending->SetName("PendingPasses");
  pending->InsertNextValue(report.PendingPasses);
  output->GetFieldData()->AddArray(mode);
  output->GetFieldData()->AddArray(passes);
  output->GetFieldData()->AddArray(pending);
  output->GetFieldData()->AddArray(time);
  this->LastOutput = vtkSmartPointer<vtkImageData>::New();
  this->LastOutput->ShallowCopy(output);
  return 1;
}

//------------------------------------------------------------------------------
void vtkIlluminationVolumeAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Lights: " << this->Lights.size() << "\n";
  os << indent << "ResolutionScale: " << this->ResolutionScale << "\n";
  os << indent << "ScalarOpacityUnitDistance: " << this->ScalarOpacityUnitDistance << "\n";
  os << indent << "ChromaticAttenuation: " << this->ChromaticAttenuation << "\n";
  os << indent << "ColorTransferFunction: " << this->ColorTransferFunction << "\n";
  os << indent << "OpacityFunction: " << this->OpacityFunction << "\n";
}
