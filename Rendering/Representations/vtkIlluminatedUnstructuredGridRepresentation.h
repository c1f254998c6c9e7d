/**
 * @class vtkIlluminatedUnstructuredGridRepresentation
 * @brief ParaView's "Illuminated Volume" representation of unstructured grids.
 *
 * Shares the Volume representation's colour map, scalar opacity, unit distance and
 * coloured array, and lights the grid with the render view's lights (the Light
 * Inspector's and, with UseLightKit, the light kit's) through
 * vtkUnstructuredGridIllumination, the two-level solver: as each still render starts (with
 * the camera it renders, volillum::RenderStart) the piece this process renders is lit per
 * vertex (LitColors = transfer-function colour x
 * illumination) and drawn with projected tetrahedra on those colours. The solver keeps
 * each light's solution, so a light edit recomputes that light only. Interactive renders
 * keep the current lighting (or draw the level-of-detail outline when ParaView asks for
 * it). With AsynchronousLighting (serial runs) the lighting runs on a worker thread as for
 * image data (see vtkIlluminatedVolumeRepresentation and IlluminationBackground.h): a still
 * render draws the last finished lighting, a level-0-only lighting comes first when the
 * final one is expected to take over 1 s (LightingCosts), a newer edit supersedes a running one and
 * CancelIllumination stops it. UpdateMode, UpdateSeconds and PropagationPasses report the
 * last finished update. In parallel
 * (pvserver or pvbatch under MPI, rendered on the server) the processes light the pieces
 * they render together as each render starts: ParaView gives each process whole cells for
 * ordered compositing, and the solver, with the global controller, gets from the other
 * processes only their cells near the piece (see Documentation/parallel.md). A process without
 * cells takes part.
 *
 * The coloured array is a point or cell array; an array of several components is lit by
 * what the colour map shows of it (its magnitude or the chosen component). Arrays mapped
 * without the colour map (Map Scalars off, Multi Components Mapping, a separate opacity
 * array) are drawn as the Volume representation draws them, unlit.
 */
#ifndef vtkIlluminatedUnstructuredGridRepresentation_h
#define vtkIlluminatedUnstructuredGridRepresentation_h

#include "IlluminationFilterSupport.h" // for volillum::UpdateReport
#include "VolIllumRepresentationsModule.h"
#include "vtkNew.h"
#include "vtkUnstructuredGridVolumeRepresentation.h"

#include <memory>

class vtkPVRenderView;
class vtkProjectedTetrahedraMapper;
class vtkUnstructuredGrid;
class vtkUnstructuredGridIllumination;
class vtkVolumeProperty;

class VOLILLUMREPRESENTATIONS_EXPORT vtkIlluminatedUnstructuredGridRepresentation
  : public vtkUnstructuredGridVolumeRepresentation
{
public:
  static vtkIlluminatedUnstructuredGridRepresentation* New();
  vtkTypeMacro(
    vtkIlluminatedUnstructuredGridRepresentation, vtkUnstructuredGridVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * How the illumination is computed: 0, the two-level solver (the only method for
   * unstructured grids; the property mirrors the image representation's Method).
   */
  vtkSetClampMacro(IlluminationMethod, int, 0, 0);
  vtkGetMacro(IlluminationMethod, int);
  ///@}

  ///@{
  /** Solver settings, given to vtkUnstructuredGridIllumination as each lighting starts. */
  vtkSetMacro(ChromaticAttenuation, bool);
  vtkSetVector3Macro(Level0Resolution, int);
  vtkSetMacro(Absorption, double);
  vtkSetVector3Macro(ScatteringStrength, double);
  vtkSetMacro(ScatteringIterations, int);
  vtkSetMacro(Exposure, double);
  ///@}

  ///@{
  /** Light off the render call (see the class description). Default off; the GUI turns it on. */
  vtkSetMacro(AsynchronousLighting, bool);
  vtkGetMacro(AsynchronousLighting, bool);
  ///@}

  /// 1 while a lighting runs, is queued or waits to be drawn (see the image representation).
  int GetIlluminationPending();
  /// Stop the background lighting; the last finished lighting is drawn again.
  void CancelIllumination();

  ///@{
  /** Also light with the view's light kit (when the view has it on). Default on. */
  vtkSetMacro(UseLightKit, bool);
  vtkGetMacro(UseLightKit, bool);
  ///@}

  ///@{
  /**
   * The last update: 0 full / 1 selective, its wall time and the lights propagated;
   * the mean illumination (r g b) over the illumination's points.
   */
  int GetUpdateMode() const { return this->Report.Mode; }
  vtkGetMacro(UpdateSeconds, double);
  int GetPropagationPasses() const { return this->Report.Passes; }
  double* GetMeanIllumination() VTK_SIZEHINT(3);
  ///@}

  /// Hidden, the representation stops its background lighting.
  void SetVisibility(bool visible) override;

  int ProcessViewRequest(
    vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) override;

protected:
  vtkIlluminatedUnstructuredGridRepresentation();
  ~vtkIlluminatedUnstructuredGridRepresentation() override;

  /// Releases this representation's own graphics resources while the view's window is
  /// still there to release them in.
  bool RemoveFromView(vtkView* view) override;

  /// Light the delivered piece and draw it; false when it cannot be lit.
  bool UpdateIllumination(vtkPVRenderView* view);
  /// A serial run: light on the worker thread (AsynchronousLighting) or now; false when
  /// nothing lit is drawn.
  bool LightSerially(vtkPVRenderView* view, vtkUnstructuredGrid* grid, bool interactive,
    const char* array, int association, int component);
  /// Draw what the lighting finished since the last render; whether a lit grid is drawn.
  bool ShowFinishedLighting();
  /// Draw the last final lighting again (unlit when there is none yet).
  void DrawLastFinal();
  /// Give the solver settings to a filter.
  void Configure(vtkUnstructuredGridIllumination* filter) const;

  int IlluminationMethod = 0;
  bool UseLightKit = true;
  bool ChromaticAttenuation = false;
  int Level0Resolution[3] = { 64, 64, 64 };
  double Absorption = 1.0;
  double ScatteringStrength[3] = { 0.0, 0.0, 0.0 };
  int ScatteringIterations = 10;
  double Exposure = 5.0;
  bool AsynchronousLighting = false;
  volillum::UpdateReport Report;
  double UpdateSeconds = 0.0;
  // Computed when asked for, once per new illumination (a pass over every point).
  double MeanIllumination[3] = { 0.0, 0.0, 0.0 };
  vtkTimeStamp MeanTime;

  vtkNew<vtkUnstructuredGridIllumination> Illumination;
  vtkNew<vtkProjectedTetrahedraMapper> LitMapper;
  // Property of the lit drawing: LitColors are direct RGBA (dependent components).
  vtkNew<vtkVolumeProperty> LitProperty;

private:
  vtkIlluminatedUnstructuredGridRepresentation(
    const vtkIlluminatedUnstructuredGridRepresentation&) = delete;
  void operator=(const vtkIlluminatedUnstructuredGridRepresentation&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
