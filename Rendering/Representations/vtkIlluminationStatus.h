/**
 * @class vtkIlluminationStatus
 * @brief The background lighting of the process, for the GUI's polling.
 *
 * Information about every Illuminated Volume representation of the process that lights in
 * the background (AsynchronousLighting): whether a computation runs or is queued, whether a
 * finished illumination waits for a render to show it, and the least progress of those
 * running; CancelIllumination cancels them all (each keeps its last finished illumination).
 * ParaView's proxy for it ("IlluminationStatus") lives on the server only, so in a
 * client-server session the client reads the rendering process's state, not its own; the
 * plugin's pqIlluminationLightingBehavior polls it and re-renders when a result is ready.
 */
#ifndef vtkIlluminationStatus_h
#define vtkIlluminationStatus_h

#include "VolIllumRepresentationsModule.h"
#include "vtkObject.h"

class VOLILLUMREPRESENTATIONS_EXPORT vtkIlluminationStatus : public vtkObject
{
public:
  static vtkIlluminationStatus* New();
  vtkTypeMacro(vtkIlluminationStatus, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// 1 while an illumination is computed or queued in the background.
  int GetIlluminationBusy();
  /// 1 while a finished illumination waits for a render to show it.
  int GetIlluminationReady();
  /// Results published so far (the views show new ones when they render).
  int GetIlluminationPublications();
  /**
   * Renders (or other calls) so far that ran the lighting inline, even one with nothing to
   * update, or waited for a background job (one that did both counts twice): synchronous
   * lighting, screenshots, quick lightings run in the render, a representation deleted while
   * its job runs. A GUI frame with AsynchronousLighting on adds none for a lighting expected
   * to take over 0.2 s.
   */
  int GetIlluminationWaits();
  /// The least progress (0 to 1) of the computations running.
  double GetIlluminationProgress();
  /// Cancel every background computation (the last finished illumination stays).
  void CancelIllumination();

protected:
  vtkIlluminationStatus() = default;
  ~vtkIlluminationStatus() override = default;

private:
  vtkIlluminationStatus(const vtkIlluminationStatus&) = delete;
  void operator=(const vtkIlluminationStatus&) = delete;
};

#endif
