#include "IlluminationViewLights.h"

#include "IlluminationLightList.h"

#include "vtkAlgorithm.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPVLight.h"
#include "vtkPVRenderView.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

#include <algorithm>

namespace
{
// Still renders ask for 0.002 frames per second, interactive ones for 5 (vtkPVRenderView).
constexpr double InteractiveUpdateRate = 1.0;

void Transform(vtkMatrix4x4* m, const double in[3], double out[3])
{
  const double p[4] = { in[0], in[1], in[2], 1.0 };
  double q[4];
  m->MultiplyPoint(p, q);
  for (int a = 0; a < 3; ++a)
  {
    out[a] = q[a] / q[3];
  }
}

// World-space position and focal point of a view light.
void WorldGeometry(vtkLight* light, vtkCamera* camera, double position[3], double focal[3])
{
  light->GetPosition(position);
  light->GetFocalPoint(focal);
  if (!camera)
  {
    return;
  }
  if (light->LightTypeIsHeadlight())
  {
    camera->GetPosition(position);
    camera->GetFocalPoint(focal);
  }
  else if (light->LightTypeIsCameraLight())
  {
    vtkMatrix4x4* m = camera->GetCameraLightTransformMatrix();
    const double p[3] = { position[0], position[1], position[2] };
    const double f[3] = { focal[0], focal[1], focal[2] };
    Transform(m, p, position);
    Transform(m, f, focal);
  }
}
}

namespace volillum
{

//------------------------------------------------------------------------------
bool LightValues::operator==(const LightValues& o) const
{
  return this->Positional == o.Positional &&
    std::equal(this->Position, this->Position + 3, o.Position) &&
    std::equal(this->FocalPoint, this->FocalPoint + 3, o.FocalPoint) &&
    std::equal(this->Color, this->Color + 3, o.Color) && this->Intensity == o.Intensity &&
    this->ConeAngle == o.ConeAngle && this->Exponent == o.Exponent && this->On == o.On &&
    this->Radius == o.Radius;
}

//------------------------------------------------------------------------------
int ChangedLights(const std::vector<LightValues>& now, const std::vector<LightValues>& before)
{
  if (now.size() != before.size())
  {
    return -1;
  }
  int changed = 0;
  for (size_t l = 0; l < now.size(); ++l)
  {
    changed += now[l] == before[l] ? 0 : 1;
  }
  return changed;
}

//------------------------------------------------------------------------------
std::vector<LightValues> ReadViewLights(vtkPVRenderView* view, bool includeLightKit, bool sizes)
{
  std::vector<LightValues> values;
  vtkRenderer* renderer = view ? view->GetRenderer() : nullptr;
  if (!renderer)
  {
    return values;
  }
  vtkCamera* camera = renderer->GetActiveCamera();
  vtkLightCollection* lights = renderer->GetLights();
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (!includeLightKit && !vtkPVLight::SafeDownCast(light))
    {
      continue;
    }
    LightValues v;
    WorldGeometry(light, camera, v.Position, v.FocalPoint);
    v.Positional = light->GetPositional() != 0;
    light->GetDiffuseColor(v.Color);
    v.Intensity = light->GetIntensity();
    v.ConeAngle = light->GetConeAngle();
    v.Exponent = light->GetExponent();
    v.On = light->GetSwitch() != 0;
    // A directional light's size is an angle, below 180 degrees (a radius typed for a
    // positional light may outgrow it when the light turns directional).
    const double radius = sizes ? GetLightRadius(light) : 0.0;
    v.Radius = v.Positional ? radius : std::min(radius, 179.0);
    values.push_back(v);
  }
  return values;
}

//------------------------------------------------------------------------------
void ViewLights::Update(const std::vector<LightValues>& values)
{
  this->Lights.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i)
  {
    if (!this->Lights[i])
    {
      this->Lights[i] = vtkSmartPointer<vtkLight>::New();
      this->Lights[i]->SetLightTypeToSceneLight();
    }
    const LightValues& from = values[i];
    vtkLight* to = this->Lights[i];
    to->SetPositional(from.Positional);
    to->SetPosition(from.Position[0], from.Position[1], from.Position[2]);
    to->SetFocalPoint(from.FocalPoint[0], from.FocalPoint[1], from.FocalPoint[2]);
    to->SetDiffuseColor(from.Color[0], from.Color[1], from.Color[2]);
    to->SetIntensity(from.Intensity);
    to->SetConeAngle(from.ConeAngle);
    to->SetExponent(from.Exponent);
    to->SetSwitch(from.On);
    SetLightRadius(to, from.Radius);
  }
}

//------------------------------------------------------------------------------
void RenderStart::Arm(vtkPVRenderView* view, std::function<void(vtkPVRenderView*)> run)
{
  vtkRenderer* renderer = view ? view->GetRenderer() : nullptr;
  if (renderer != this->Renderer)
  {
    this->Detach();
    if (renderer)
    {
      // ParaView's synchronisers observe with the default priority, 0.
      this->Observer =
        renderer->AddObserver(vtkCommand::StartEvent, this, &RenderStart::Started, -1.0f);
      this->Renderer = renderer;
    }
  }
  this->View = view;
  // A render ParaView suppresses (SuppressRendering) draws nothing: nothing is armed, so that
  // no later render of the renderer outside a view's render lights (in parallel one process
  // may make such a render alone, and the lighting is collective).
  this->Pending = renderer && !view->GetSuppressRendering() ? std::move(run) : nullptr;
}

//------------------------------------------------------------------------------
void RenderStart::Detach()
{
  if (this->Renderer)
  {
    this->Renderer->RemoveObserver(this->Observer);
  }
  this->Renderer = nullptr;
  this->Pending = nullptr;
}

//------------------------------------------------------------------------------
void RenderStart::Started()
{
  auto run = std::move(this->Pending);
  this->Pending = nullptr;
  if (run && this->View)
  {
    run(this->View);
  }
}

//------------------------------------------------------------------------------
bool IsInteractiveRender(vtkPVRenderView* view)
{
  vtkRenderWindow* window = view ? view->GetRenderWindow() : nullptr;
  return window && window->GetDesiredUpdateRate() >= InteractiveUpdateRate;
}

//------------------------------------------------------------------------------
bool InScreenshot(vtkPVRenderView* view)
{
  struct Probe : public vtkPVView
  {
    static bool In(vtkPVView* v) { return (v->*(&Probe::GetInCaptureScreenshot))(); }
  };
  return view && Probe::In(view);
}

//------------------------------------------------------------------------------
vtkDataArray* ColouredArrayOf(vtkAlgorithm* representation, vtkDataSet* data, ColouredArray& array)
{
  vtkInformation* info = representation->GetInputArrayInformation(0);
  array.Name =
    info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  array.Association = info->Has(vtkDataObject::FIELD_ASSOCIATION())
    ? info->Get(vtkDataObject::FIELD_ASSOCIATION())
    : vtkDataObject::FIELD_ASSOCIATION_POINTS;
  if (data && array.Name && array.Association == vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    return data->GetPointData()->GetArray(array.Name);
  }
  if (data && array.Name && array.Association == vtkDataObject::FIELD_ASSOCIATION_CELLS)
  {
    return data->GetCellData()->GetArray(array.Name);
  }
  return nullptr;
}

//------------------------------------------------------------------------------
vtkDataArray* ColouredScalars(vtkAlgorithm* representation, vtkDataSet* data, ColouredArray& array)
{
  vtkDataArray* scalars = ColouredArrayOf(representation, data, array);
  return scalars && scalars->GetNumberOfComponents() == 1 ? scalars : nullptr;
}

//------------------------------------------------------------------------------
int ColouredComponent(vtkVolumeProperty* property)
{
  vtkColorTransferFunction* lut = property->GetRGBTransferFunction(0);
  return lut && lut->GetVectorMode() == vtkScalarsToColors::COMPONENT
    ? std::max(lut->GetVectorComponent(), 0)
    : -1;
}

//------------------------------------------------------------------------------
void MeanIllumination(vtkDataObject* output, double mean[3], vtkTimeStamp& computed)
{
  if (!output || output->GetMTime() <= computed)
  {
    return;
  }
  computed.Modified();
  mean[0] = mean[1] = mean[2] = 0.0;
  vtkDataSet* data = vtkDataSet::SafeDownCast(output);
  vtkDataArray* a = data ? data->GetPointData()->GetArray("Illumination") : nullptr;
  if (!a || a->GetNumberOfComponents() != 3 || a->GetNumberOfTuples() == 0)
  {
    return;
  }
  const vtkIdType n = a->GetNumberOfTuples();
  if (auto* values = vtkFloatArray::FastDownCast(a))
  {
    // The filters' arrays: read in place (a virtual call a value takes 0.2 s on 16 M points).
    const float* v = values->GetPointer(0);
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        mean[c] += v[3 * i + c];
      }
    }
  }
  else
  {
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        mean[c] += a->GetComponent(i, c);
      }
    }
  }
  for (int c = 0; c < 3; ++c)
  {
    mean[c] /= static_cast<double>(n);
  }
}

}
