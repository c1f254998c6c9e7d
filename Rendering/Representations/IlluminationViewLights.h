/**
 * @file IlluminationViewLights.h
 * @brief The lights of a ParaView render view, in world coordinates, for the filters.
 *
 * A render view shines the lights of its light kit (camera lights and a headlight, when
 * the view's light kit is on) and the Light Inspector's lights (vtkPVLight: scene, camera
 * or headlights). The illumination filters need every light in the data's (world)
 * coordinates, so ViewLights keeps one scene-light copy per view light and rewrites it
 * from the view's camera before each update. Copies are edited in place: a light whose
 * parameters did not change leaves its copy untouched, which is what lets the filters see
 * a light edit as a change of that light only (a selective update).
 */
#ifndef IlluminationViewLights_h
#define IlluminationViewLights_h

#include "vtkDataObject.h"
#include "vtkLight.h"
#include "vtkSmartPointer.h"
#include "vtkTimeStamp.h"
#include "vtkVolumeProperty.h"
#include "vtkWeakPointer.h"

#include <functional>

#include <vector>

class vtkAlgorithm;
class vtkAlgorithmOutput;
class vtkDataArray;
class vtkDataSet;
class vtkPVRenderView;
class vtkRenderer;

namespace volillum
{

/// What a view light shines, in world coordinates: plain values a worker thread can own.
struct LightValues
{
  bool Positional = false;
  double Position[3] = { 0, 0, 1 };
  double FocalPoint[3] = { 0, 0, 0 };
  double Color[3] = { 1, 1, 1 };
  double Intensity = 1.0;
  double ConeAngle = 30.0;
  double Exponent = 1.0;
  bool On = true;
  double Radius = 0.0; // the light's size (volillum::GetLightRadius)
  bool operator==(const LightValues& other) const;
};

/// How many lights differ between two lists of the same length; -1 when the lengths differ.
int ChangedLights(const std::vector<LightValues>& now, const std::vector<LightValues>& before);

/**
 * The view's lights in world coordinates. With includeLightKit false only the Light
 * Inspector's lights (vtkPVLight) are taken; with sizes false every light's Radius is 0 (a
 * method that ignores sizes sees no change when one is edited).
 */
std::vector<LightValues> ReadViewLights(vtkPVRenderView* view, bool includeLightKit, bool sizes);

class ViewLights
{
public:
  /// Re-read the view's lights with their sizes (ReadViewLights; a filter that ignores the
  /// sizes sees no change when one is edited: vtkIlluminationVolumeAlgorithm::UsesLightSize).
  void Update(vtkPVRenderView* view, bool includeLightKit)
  {
    this->Update(ReadViewLights(view, includeLightKit, true));
  }
  /// Rewrite the copies from values (a copy whose values did not change stays unmodified).
  void Update(const std::vector<LightValues>& values);

  int Size() const { return static_cast<int>(this->Lights.size()); }

  /**
   * Give the copies to a filter with the light API of the illumination filters
   * (AddLight, RemoveAllLights, GetNumberOfLights, GetLight). The filter keeps them by
   * reference, so the list is only handed over again when it is not already the filter's.
   */
  template <class Filter>
  void ApplyTo(Filter* filter) const
  {
    bool same = filter->GetNumberOfLights() == this->Size();
    for (int i = 0; same && i < this->Size(); ++i)
    {
      same = filter->GetLight(i) == this->Lights[i];
    }
    if (same)
    {
      return;
    }
    filter->RemoveAllLights();
    for (const auto& light : this->Lights)
    {
      filter->AddLight(light);
    }
  }

private:
  std::vector<vtkSmartPointer<vtkLight>> Lights;
};

/**
 * Runs a representation's lighting when the view's renderer starts the render that a
 * REQUEST_RENDER announced. On a pvserver process, and on every process of pvbatch but the
 * first, the renderer's camera is synchronised from the client (or the first process) only
 * as that render starts (vtkSynchronizedRenderers, on the renderer's StartEvent): during
 * REQUEST_RENDER it is still the previous render's, and camera lights (the light kit, a
 * headlight) read there would light a new view with the old view's lights. The observer
 * runs after ParaView's (lower priority), once per Arm.
 */
class RenderStart
{
public:
  RenderStart() = default;
  RenderStart(const RenderStart&) = delete;
  RenderStart& operator=(const RenderStart&) = delete;
  ~RenderStart() { this->Detach(); }

  /// The next start of a render of the view's renderer calls run (with the view); a later
  /// Arm before that start replaces it. A view that suppresses its render (SuppressRendering)
  /// arms nothing and disarms what was armed.
  void Arm(vtkPVRenderView* view, std::function<void(vtkPVRenderView*)> run);
  /// Stop observing (the representation leaves the view); nothing armed runs.
  void Detach();

private:
  void Started();

  vtkWeakPointer<vtkPVRenderView> View;
  vtkWeakPointer<vtkRenderer> Renderer;
  unsigned long Observer = 0;
  std::function<void(vtkPVRenderView*)> Pending;
};

/**
 * True while the view renders interactively (the user drags the camera): ParaView's
 * render view asks for a high update rate then and for a very low one in still renders.
 */
bool IsInteractiveRender(vtkPVRenderView* view);

/**
 * True while the view renders for a screenshot or an animation frame (between its
 * PrepareForScreenshot and CleanupAfterScreenshot). vtkPVView keeps that flag's getter
 * protected in ParaView 5.11; it is read here through a member pointer taken in a subclass.
 */
bool InScreenshot(vtkPVRenderView* view);

/// The array a representation colours by (its input array 0), as the illumination
/// filters are told to read it.
struct ColouredArray
{
  const char* Name = nullptr;
  int Association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
};

/**
 * Hand an illumination filter what a representation shares with ParaView's Volume
 * representation: the piece to light, its coloured array (point or cell data; the filters
 * light cell data through point values averaged from the cells around each point), and
 * the volume property's transfer functions and scalar opacity unit distance.
 */
template <class Filter>
void SetVolumeInput(Filter* filter, vtkAlgorithmOutput* piece, const ColouredArray& array,
  vtkVolumeProperty* property)
{
  filter->SetInputConnection(piece);
  filter->SetInputArrayToProcess(0, 0, 0, array.Association, array.Name);
  filter->SetColorTransferFunction(property->GetRGBTransferFunction(0));
  filter->SetOpacityFunction(property->GetScalarOpacity(0));
  filter->SetScalarOpacityUnitDistance(property->GetScalarOpacityUnitDistance(0));
}

/**
 * The array a representation colours by (its input array 0) in the data it renders, when
 * it is a one-component point or cell array that the illumination filters can classify;
 * nullptr otherwise (nothing is lit then). array receives its name and association.
 */
vtkDataArray* ColouredScalars(vtkAlgorithm* representation, vtkDataSet* data, ColouredArray& array);

/// The array a representation colours by in data, whatever its number of components
/// (nullptr when data does not hold it); array receives its name and association.
vtkDataArray* ColouredArrayOf(vtkAlgorithm* representation, vtkDataSet* data, ColouredArray& array);

/// The component of a multi-component array a volume property's colour map shows (its
/// vector mode), or -1 for the magnitude (also without a colour map).
int ColouredComponent(vtkVolumeProperty* property);

/// Mean of the 3-component point array "Illumination" of a filter output (0 without it),
/// recomputed only when the output is newer than computed (which it then updates); mean
/// is left as it is without an output.
void MeanIllumination(vtkDataObject* output, double mean[3], vtkTimeStamp& computed);

}

#endif
