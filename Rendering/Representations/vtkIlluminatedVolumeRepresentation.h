/**
 * @class vtkIlluminatedVolumeRepresentation
 * @brief ParaView's "Illuminated Volume" representation of image data.
 *
 * A volume representation (it shares the Volume representation's colour map, scalar
 * opacity, unit distance and coloured array) that lights the volume with the render
 * view's own lights. As each still render starts (with the camera it renders, after
 * ParaView has synchronised it from the client: volillum::RenderStart) it reads the view's
 * lights (the Light Inspector's lights and, with UseLightKit, the light kit's), converts camera
 * lights to world coordinates, hands them with the colour map editor's transfer functions to an
 * illumination filter (IlluminationMethod: multi-light propagation, filtered shadows or
 * the ray-marched reference) on the piece this process renders, and draws the volume
 * with vtkIlluminatedVolumeMapper. In parallel (pvserver or pvbatch under MPI) the filter
 * lights the pieces where they are with the global controller (see Documentation/parallel.md;
 * ParaView gives a representation vtkExtentTranslator's pieces, the blocks the filter
 * reads), every process together as each render starts (ParaView renders on every process
 * then; the decisions to light or keep the illumination are agreed by reductions), and each
 * process draws its own piece with the illumination over it, so the composited image is lit
 * as a serial one. The filters keep their state between renders, so a light edit
 * re-propagates that light only; a transfer-function or data change recomputes everything.
 *
 * While the user drags the camera (interactive renders) the current illumination is
 * kept. With AsynchronousLighting (serial runs: the GUI's builtin session, a pvserver of one
 * process, pvpython) a still render does not wait for a lighting expected to take over
 * 0.2 s: it draws the last finished illumination (a cheaper preview frame) and hands the new
 * one to a worker thread (IlluminationBackground.h) on copies of what it reads; a coarse
 * illumination (every 4th sample) comes first when the final one is expected to take over
 * 1 s (LightingCosts); a newer edit supersedes the running computation;
 * CancelIllumination stops it and keeps the last finished illumination. The
 * result is shown by a later render (the GUI asks for it: pqIlluminationLightingBehavior;
 * a script renders until IlluminationPending is 0). In a parallel run the processes light
 * together as each render starts, so the lighting is synchronous there whatever the
 * setting. UpdateMode, UpdateSeconds, PropagationPasses and PendingPasses report the last
 * finished update.
 *
 * The coloured array must be a one-component point array; otherwise the volume is drawn
 * without illumination (as the Volume representation draws it).
 */
#ifndef vtkIlluminatedVolumeRepresentation_h
#define vtkIlluminatedVolumeRepresentation_h

#include "IlluminationFilterSupport.h" // for volillum::UpdateReport
#include "VolIllumRepresentationsModule.h"
#include "vtkImageVolumeRepresentation.h"
#include "vtkSmartPointer.h"

#include <memory>

class vtkIlluminatedVolumeMapper;
class vtkImageData;
class vtkIlluminationVolumeAlgorithm;
class vtkPVRenderView;

class VOLILLUMREPRESENTATIONS_EXPORT vtkIlluminatedVolumeRepresentation
  : public vtkImageVolumeRepresentation
{
public:
  static vtkIlluminatedVolumeRepresentation* New();
  vtkTypeMacro(vtkIlluminatedVolumeRepresentation, vtkImageVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Methods
  {
    MultiLightPropagation = 0,
    FilteredShadows = 1,
    RayMarchedReference = 2
  };

  ///@{
  /** How the illumination is computed. Default MultiLightPropagation. */
  vtkSetClampMacro(IlluminationMethod, int, MultiLightPropagation, RayMarchedReference);
  vtkGetMacro(IlluminationMethod, int);
  ///@}

  ///@{
  /** Illumination volume resolution relative to the data: 1, 0.5 or 0.25. Default 0.5. */
  vtkSetMacro(ResolutionScale, double);
  vtkGetMacro(ResolutionScale, double);
  ///@}

  ///@{
  /** Light passing coloured material takes on its colour. Default off. */
  vtkSetMacro(ChromaticAttenuation, bool);
  vtkGetMacro(ChromaticAttenuation, bool);
  ///@}

  ///@{
  /** Filtered shadows: filter width in voxels and kernel (0 box, 1 Gaussian). */
  vtkSetClampMacro(ShadowFilterWidth, double, 0.0, 64.0);
  vtkGetMacro(ShadowFilterWidth, double);
  vtkSetClampMacro(ShadowFilterKernel, int, 0, 1);
  vtkGetMacro(ShadowFilterKernel, int);
  ///@}

  ///@{
  /**
   * Ambient occlusion (vtkIlluminationVolumeAlgorithm::SetAmbientOcclusion): the intensity of
   * an even ambient light that reaches each sample through the transmittance averaged over
   * the directions within AmbientOcclusionRadius (world units; 0: a twentieth of the data's
   * diagonal); it adds to the lights, under every method. Default 0: none.
   */
  vtkSetClampMacro(AmbientOcclusion, double, 0.0, 1e6);
  vtkGetMacro(AmbientOcclusion, double);
  vtkSetClampMacro(AmbientOcclusionRadius, double, 0.0, 1e300);
  vtkGetMacro(AmbientOcclusionRadius, double);
  ///@}

  ///@{
  /**
   * Compute the illumination off the render call (see the class description). Default off
   * (scripts get the final illumination from each Render()); the GUI turns it on.
   */
  vtkSetMacro(AsynchronousLighting, bool);
  vtkGetMacro(AsynchronousLighting, bool);
  ///@}

  /**
   * 1 while an illumination is computed or queued in the background, or finished and not
   * drawn yet; 0 when the last render drew the final illumination.
   */
  int GetIlluminationPending();

  /// Stop the background computation; the last finished illumination is drawn again.
  void CancelIllumination();

  ///@{
  /** Also light with the view's light kit (when the view has it on). Default on. */
  vtkSetMacro(UseLightKit, bool);
  vtkGetMacro(UseLightKit, bool);
  ///@}

  ///@{
  /** Shading weights, forwarded to vtkIlluminatedVolumeMapper. */
  void SetIlluminationAmbient(double value);
  void SetIlluminationDiffuse(double value);
  void SetExposure(double value);
  void SetGradientShading(bool enable);
  void SetPhongAmbient(double value);
  void SetPhongDiffuse(double value);
  void SetPhongSpecular(double value);
  void SetPhongSpecularPower(double value);
  ///@}

  ///@{
  /**
   * The last update: 0 full / 1 selective, its wall time, passes done and left; the
   * mean illumination (r g b) over the illumination volume's points.
   */
  int GetUpdateMode() const { return this->Report.Mode; }
  vtkGetMacro(UpdateSeconds, double);
  int GetPropagationPasses() const { return this->Report.Passes; }
  double* GetMeanIllumination() VTK_SIZEHINT(3);
  int GetPendingPasses() const { return this->Report.PendingPasses; }
  ///@}

  /**
   * Whether this process lights its own piece where it is, the processes together as each
   * render starts: true in a parallel run, false in a serial one.
   */
  bool GetDistributedIllumination() const;

  /// Hidden, the representation stops its background lighting.
  void SetVisibility(bool visible) override;

  int ProcessViewRequest(
    vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) override;

protected:
  vtkIlluminatedVolumeRepresentation();
  ~vtkIlluminatedVolumeRepresentation() override;

  /// Releases this representation's own graphics resources while the view's window is
  /// still there to release them in.
  bool RemoveFromView(vtkView* view) override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /**
   * ParaView colours a multi-component array through its magnitude or one of its
   * components (the colour map's vector mode) when components are mapped independently;
   * the Volume representation's mapper reduces the array itself. The illuminated mapper and
   * the illumination filters read one component, so in the data this representation
   * renders the coloured array is replaced, under its own name, by the values ParaView
   * colours by: on new data (ReduceColouredVectors), and in place when the colour map's
   * vector mode or component changes (UpdateVectorMode, before each render).
   */
  void ReduceColouredVectors();
  void UpdateVectorMode();

  vtkIlluminatedVolumeMapper* GetIlluminatedMapper();
  vtkIlluminationVolumeAlgorithm* GetIlluminationFilter();
  /// Lights the piece this process renders in the view (as its renderer starts a render).
  void UpdateIllumination(vtkPVRenderView* view);
  /// A serial run: lights on a worker thread (AsynchronousLighting) or now.
  void LightSerially(vtkPVRenderView* view, vtkImageData* image, bool interactive);
  /// Draw what the background lighting finished since the last render.
  void ShowFinishedLighting();
  bool UpdateFilter(vtkIlluminationVolumeAlgorithm* filter);

  int IlluminationMethod = MultiLightPropagation;
  double ResolutionScale = 0.5;
  bool ChromaticAttenuation = false;
  double ShadowFilterWidth = 3.0;
  int ShadowFilterKernel = 0;
  double AmbientOcclusion = 0.0;
  double AmbientOcclusionRadius = 0.0;
  bool AsynchronousLighting = false;
  bool UseLightKit = true;

  volillum::UpdateReport Report;
  double UpdateSeconds = 0.0;
  // Computed when asked for, once per new illumination (a pass over every point).
  double MeanIllumination[3] = { 0.0, 0.0, 0.0 };
  vtkTimeStamp MeanTime;

private:
  vtkIlluminatedVolumeRepresentation(const vtkIlluminatedVolumeRepresentation&) = delete;
  void operator=(const vtkIlluminatedVolumeRepresentation&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
