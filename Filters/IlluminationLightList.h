/**
 * @file IlluminationLightList.h
 * @brief The filters' lights as VTK objects: vtkLight snapshots and the flat parameter list.
 *
 * The pipeline side of the lights (the kernels see only LightState, IlluminationLights.h):
 * LightList holds a filter's vtkLight objects and edits them through the flat list of
 * LightParameterCount numbers per light that ParaView's "Lights" property sends.
 */
#ifndef IlluminationLightList_h
#define IlluminationLightList_h

#include "IlluminationLights.h"
#include "VolIllumFiltersModule.h"

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <string>
#include <vector>

class vtkLight;

namespace volillum
{

/// Snapshot of a vtkLight.
VOLILLUMFILTERS_EXPORT LightState CaptureLight(vtkLight* light);

/// Set a vtkLight from the LightParameterCount numbers of the flat parameter layout.
VOLILLUMFILTERS_EXPORT void ApplyLightParameters(vtkLight* light, const double* parameters);

/// Read the LightParameterCount numbers of the flat parameter layout from a vtkLight.
VOLILLUMFILTERS_EXPORT void GetLightParameters(vtkLight* light, double* parameters);

/// The light's size (LightState::Radius), kept in its vtkInformation as ParaView's ray
/// tracers keep theirs (vtkLight has no member for it); 0 when it has none.
VOLILLUMFILTERS_EXPORT double GetLightRadius(vtkLight* light);

/// Set the light's size; marks the light modified when it changes.
VOLILLUMFILTERS_EXPORT void SetLightRadius(vtkLight* light, double radius);

/**
 * The lights of one filter: vtkLight objects held by reference, editable one by one or
 * through the flat list of LightParameterCount numbers per light that ParaView's "Lights"
 * property sends. Every illumination filter forwards its light API to one of these.
 */
class VOLILLUMFILTERS_EXPORT LightList
{
public:
  /// Add a light; returns false for a null light.
  bool Add(vtkLight* light);
  /// Remove every light; returns whether there were any.
  bool Clear();
  int Size() const { return static_cast<int>(this->Lights.size()); }
  vtkLight* Get(int index) const;

  /// Create or remove lights so that there are count / LightParameterCount of them.
  /// Returns false when count is not a multiple of it: the lights stay, and Validate
  /// reports the count until the next count that is (or Clear); changed tells whether
  /// lights were added or removed.
  bool SetNumberOfParameters(int count, bool& changed);
  int GetNumberOfParameters() const { return this->Size() * LightParameterCount; }
  /// Edit one value of the flat list; returns false when the index is out of range.
  bool SetParameter(int index, double value);
  double GetParameter(int index) const;

  std::vector<LightState> States() const;
  /// Latest modification time of the lights (0 without lights).
  vtkMTimeType GetMTime() const;
  /// Empty when every light is usable, otherwise what is wrong (a count of values that is
  /// not a multiple of LightParameterCount, non-finite parameter, a
  /// directional or spot light that is on and whose position is its focal point, a spot
  /// light that is on with a cone angle of 0 or less, negative intensity or colour, colour x
  /// intensity above MaximumRadiance, a negative radius, a directional light 180 degrees or
  /// more across).
  std::string Validate() const;

private:
  std::vector<vtkSmartPointer<vtkLight>> Lights;
  int IncompleteCount = -1; // the last count of values that was not whole lights, or -1
};

}

#endif
