#include "vtkIlluminationStatus.h"

#include "IlluminationBackground.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkIlluminationStatus);

//------------------------------------------------------------------------------
int vtkIlluminationStatus::GetIlluminationBusy()
{
  return volillum::BackgroundLighting::AnyBusy() ? 1 : 0;
}

int vtkIlluminationStatus::GetIlluminationReady()
{
  return volillum::BackgroundLighting::AnyReady() ? 1 : 0;
}

int vtkIlluminationStatus::GetIlluminationPublications()
{
  return static_cast<int>(volillum::BackgroundLighting::Publications() & 0x7fffffff);
}

int vtkIlluminationStatus::GetIlluminationWaits()
{
  return static_cast<int>(volillum::BackgroundLighting::Waits() & 0x7fffffff);
}

double vtkIlluminationStatus::GetIlluminationProgress()
{
  return volillum::BackgroundLighting::LeastProgress();
}

void vtkIlluminationStatus::CancelIllumination()
{
  volillum::BackgroundLighting::CancelAll();
}

//------------------------------------------------------------------------------
void vtkIlluminationStatus::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IlluminationBusy: " << this->GetIlluminationBusy() << "\n";
  os << indent << "IlluminationReady: " << this->GetIlluminationReady() << "\n";
}
