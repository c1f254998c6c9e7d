/**
 * @class vtkIlluminationVolumeAlgorithm
 * @brief Common base of the filters that compute an illumination volume for vtkImageData.
 *
 * Input: a 3D vtkImageData with a scalar array (chosen with SetInputArrayToProcess; the
 * active point scalars, else the active cell scalars, by default). Cell data are lit as
 * point data, each point the average of the cells around it (vtkCellDataToPointData); an
 * array of several components is lit by its magnitude or one component (ScalarComponent).
 * An image with a direction matrix is lit in its own frame: the lights are taken into the
 * frame of its axes, and the output has the input's direction matrix. Output: a vtkImageData
 * covering the input's bounds at ResolutionScale (1, 0.5 or 0.25 per axis) with the point array
 * "Illumination" (3-component float, linear HDR: an unoccluded white light of intensity 1 gives
 * (1,1,1)), and the field arrays UpdateMode (0 full, 1 selective), PropagationPasses (passes or
 * sweeps the last update did), PendingPasses (passes left for a later update), UpdateSeconds
 * (its wall time) and ClassifiedPoints (the input points the process classified: all of them,
 * or its block in a parallel run of a filter that LightsDistributedPieces). An aborted update
 * leaves the previous output in place.
 *
 * Lights are vtkLight objects (see IlluminationLightList.h for how they are read). The same
 * lights can be given as a flat list of 15 numbers per light, which is how ParaView's
 * "Lights" property sets them: [positional 0/1, position x y z, focal point x y z,
 * colour r g b, intensity, cone angle, exponent, switch 0/1, radius] (the property also
 * takes the 14 numbers per light of lists written before the radius). The radius is the
 * light's size (volillum::GetLightRadius): only vtkFilteredVolumetricShadows uses it.
 *
 * Optical properties come from a vtkColorTransferFunction and a vtkPiecewiseFunction with
 * the meaning they have in vtkVolumeProperty (see IlluminationClassify.h); without
 * them a grey ramp over the scalar range applies.
 *
 * Bad input (no or non-numeric scalars, scalars of another length than the points, a 2D
 * or empty image, non-finite light parameters, a light brighter than MaximumRadiance, an
 * origin or spacing putting the bounds beyond MaximumCoordinate, an unsupported resolution
 * scale, an absurd output size) is reported with vtkErrorMacro and gives an empty output.
 * Very distant lights are far lights (see volillum::ForBounds).
 *
 * @sa vtkMultiLightIlluminationVolume vtkFilteredVolumetricShadows vtkRayMarchedIllumination
 * vtkUnstructuredGridIllumination
 */
#ifndef vtkIlluminationVolumeAlgorithm_h
#define vtkIlluminationVolumeAlgorithm_h

#include "IlluminationClassification.h"
#include "IlluminationFilterSupport.h"
#include "IlluminationLightList.h"
#include "LightPropagationKernel.h"
#include "RayMarchKernel.h"
#include "VolIllumFiltersModule.h"
#include "vtkImageAlgorithm.h"
#include "vtkImageData.h"
#include "vtkSmartPointer.h"

#include <array>  // for std::array
#include <memory> // for std::unique_ptr
#include <vector>

namespace volillum
{
class BlockOfPieces;
class BlockPointScalars;
class DistributedInput;
class EmptyBlocks;
}

class vtkColorTransferFunction;
class vtkFloatArray;
class vtkLight;
class vtkMatrix3x3;
class vtkMultiProcessController;
class vtkPiecewiseFunction;
class vtkFieldData;
class vtkPointData;

class VOLILLUMFILTERS_EXPORT vtkIlluminationVolumeAlgorithm : public vtkImageAlgorithm
{
public:
  vtkTypeMacro(vtkIlluminationVolumeAlgorithm, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The lights. The filter keeps references to the vtkLight objects, so changing a light
   * after adding it changes the next update.
   */
  void AddLight(vtkLight* light);
  void RemoveAllLights();
  int GetNumberOfLights() const { return this->Lights.Size(); }
  vtkLight* GetLight(int index) const;
  ///@}

  /**
   * Add one light from the 15 numbers of the flat layout (ParaView's Lights table sends one
   * row per light this way after RemoveAllLights).
   */
  void AddLightParameters(const double parameters[15]);

  ///@{
  /**
   * Flat light list, 15 numbers per light (see the class description). Setting the number
   * of values creates or removes lights; setting a value edits the light it belongs to. A
   * number that is not a multiple of 15 is an error, and updates give an error and an empty
   * output until the number is one (ParaView's Lights property sets it after its values).
   */
  void SetNumberOfLightParameters(int count);
  int GetNumberOfLightParameters() const;
  void SetLightParameter(int index, double value);
  double GetLightParameter(int index) const;
  ///@}

  ///@{
  /**
   * Which component of a multi-component scalar array is lit: -1 (default) its magnitude,
   * 0 .. components - 1 that component. Ignored for one-component scalars.
   */
  vtkSetClampMacro(ScalarComponent, int, -1, VTK_INT_MAX);
  vtkGetMacro(ScalarComponent, int);
  ///@}

  ///@{
  /**
   * Resolution of the illumination volume relative to the input, per axis: 1, 0.5 or 0.25.
   * Default 1.
   */
  vtkSetMacro(ResolutionScale, double);
  vtkGetMacro(ResolutionScale, double);
  ///@}

  ///@{
  /**
   * Transfer functions. Without them a grey ramp over the scalar range is used.
   */
  void SetColorTransferFunction(vtkColorTransferFunction* ctf);
  vtkGetObjectMacro(ColorTransferFunction, vtkColorTransferFunction);
  void SetOpacityFunction(vtkPiecewiseFunction* otf);
  vtkGetObjectMacro(OpacityFunction, vtkPiecewiseFunction);
  ///@}

  ///@{
  /**
   * Thickness a sample must have for the opacity function's value to be its opacity, as
   * vtkVolumeProperty's ScalarOpacityUnitDistance. Default 1.
   */
  vtkSetMacro(ScalarOpacityUnitDistance, double);
  vtkGetMacro(ScalarOpacityUnitDistance, double);
  ///@}

  ///@{
  /**
   * When on, light passing through coloured material takes on its colour: per
   * channel the step opacity is weighted by (1 - colour). When off, every channel is
   * attenuated by the opacity alone (default: white material then casts shadows too).
   */
  vtkSetMacro(ChromaticAttenuation, bool);
  vtkGetMacro(ChromaticAttenuation, bool);
  vtkBooleanMacro(ChromaticAttenuation, bool);
  ///@}

  ///@{
  /**
   * Ambient occlusion: the intensity of an even, white ambient light (0, the default: none)
   * that reaches each point through the transmittance averaged over the directions around
   * it, each ray AmbientOcclusionRadius long, read from a summed-area table of the
   * extinction (AmbientOcclusionKernel.h: no ray is marched). It adds AmbientOcclusion x that
   * transmittance to the lights' illumination, and the output gains the point array
   * "AmbientOcclusion" (the transmittance, 3 components, per colour with
   * ChromaticAttenuation) and the field array AmbientOcclusionPoints (the points whose
   * transmittance the update computed: 0 when it was kept). The transmittance is computed
   * again only when the data, the classification, the radius or the resolution change, not
   * when a light does. A parallel run with ambient occlusion assembles the whole input on
   * every process.
   */
  vtkSetClampMacro(AmbientOcclusion, double, 0.0, volillum::MaximumRadiance);
  vtkGetMacro(AmbientOcclusion, double);
  ///@}
  ///@{
  /**
   * Length of the ambient-occlusion rays in world units; 0 (the default) is a twentieth of
   * the diagonal of the data's bounds.
   */
  vtkSetClampMacro(AmbientOcclusionRadius, double, 0.0, volillum::MaximumCoordinate);
  vtkGetMacro(AmbientOcclusionRadius, double);
  ///@}
  ///@{
  /**
   * The processes of a parallel run (default: the global controller). With more than one
   * process, each process outputs the illumination points that cover its own piece (see
   * Documentation/parallel.md) and the result equals a serial run's: filters that light
   * distributed pieces (LightsDistributedPieces) light the block of the input each process
   * holds (gathered from the pieces where they are not the blocks) and combine the parts of
   * the light; the others assemble the whole input on every process
   * and light their share of it (their piece's points, or their share of the sweeps). A parallel
   * run of the propagation does not stop when aborted. Every process must update the filter
   * together. Set nullptr to light each piece on its own.
   */
  virtual void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// Current states of the lights (with radius 0 for a filter that does not UsesLightSize).
  std::vector<volillum::LightState> GetLightStates() const;

  vtkMTimeType GetMTime() override;

  /// Upper bound on the number of illumination points (a bigger request is an error).
  static constexpr long long MaximumOutputPoints = 1LL << 29;

  /// Largest coordinate magnitude of the input's bounds (beyond, lengths would overflow).
  static constexpr double MaximumCoordinate = volillum::MaximumCoordinate;

protected:
  vtkIlluminationVolumeAlgorithm();
  ~vtkIlluminationVolumeAlgorithm() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  using UpdateReport = volillum::UpdateReport;

  /**
   * Compute the illumination of all lights on the illumination grid `target` (or, for filters
   * that light points independently, on a part of it) into rgb (3 floats a point, x fastest;
   * in a parallel run that shares sweeps, GetSweepShare, only the points of this process's
   * piece, which OutputIllumination writes: it must be called once, and the update is not
   * aborted).
   * inputModified tells whether the data or the classification changed since the last successful
   * update. Return false when aborted: the output then stays as the last successful update left it.
   */
  virtual bool ComputeIllumination(const volillum::ClassifiedVolume& volume,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    bool inputModified, float* rgb, UpdateReport& report) = 0;

  /**
   * Whether the illumination of a point depends only on its position (the classification and
   * the lights), not on the other points of the grid (false by default: propagation sweeps
   * the whole grid). ComputeIllumination may then be given any part of the illumination
   * grid, and a parallel run computes only its own piece.
   */
  virtual bool LightsPointsIndependently() const { return false; }

  /**
   * Whether a parallel run lights each process's piece of the input where it is
   * (ComputeDistributedIllumination) instead of assembling the whole input on every
   * process (false by default). Each process lights its block of the input (vtkExtentTranslator's
   * block p of N), gathered from the pieces where they are not the blocks (BlockOfPieces: the
   * output then covers the block). Cell scalars become point
   * values over each process's block from its cells and the layer of cells around it
   * (BlockPointScalars), as a serial run averages them.
   */
  virtual bool LightsDistributedPieces() const { return false; }

  /// Whether the lights' radius (their size) changes this filter's output (false by default).
  virtual bool UsesLightSize() const { return false; }

  /**
   * The illumination of a parallel run of a filter that LightsDistributedPieces. `volume`:
   * this process's piece of the classification (no points where the process has no piece);
   * `piece`: where it lies in the whole data grid and which cells it takes; `lights`: in the
   * data's frame (empty where the process has no piece); `extents`: every
   * process's extent of the illumination grid `target` (GatherExtents); inputModified: as
   * for ComputeIllumination. Collective: rgb (all 0 on entry) gets
   * the illumination at the points of this process's extent (3 floats a point, x fastest).
   * Not aborted (the other processes wait for this one).
   */
  virtual void ComputeDistributedIllumination(vtkMultiProcessController* controller,
    const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    const std::vector<int>& extents, bool inputModified, float* rgb, UpdateReport& report);

  /**
   * The sweeps this process runs: in a parallel run of a filter that does not light points
   * independently, its share of them (ComputeIllumination then propagates only those and
   * gives its units to OutputIllumination); otherwise all of them. Such a parallel run
   * must not stop halfway: the other processes wait for this one's sums.
   */
  volillum::SweepShare GetSweepShare() const;

  /**
   * The illumination on the grid `target` into rgb (3 floats a point). Collective in a
   * parallel run that shares sweeps (GetSweepShare): the sums over the processes at the
   * points of this process's piece (rgb holds those only).
   */
  void OutputIllumination(const volillum::FixedPointIllumination& illumination,
    const volillum::GridGeometry& target, float* rgb);

  /// Add any further point arrays of the last computation to the output (none by default).
  virtual void AddOutputArrays(vtkPointData* vtkNotUsed(pointData)) {}
  /// Add any further field arrays describing the last computation (none by default).
  virtual void AddOutputFieldData(vtkFieldData* vtkNotUsed(fieldData)) {}

  /// Report progress; returns false when the update should stop.
  bool ReportProgress(double fraction);

  /// Empty blocks of the current classification, built on first use and kept until the
  /// classification changes (for kernels that skip empty space during ComputeIllumination).
  const volillum::EmptyBlocks* GetEmptyBlocks();

  volillum::LightList Lights;
  int ScalarComponent = -1;
  double ResolutionScale = 1.0;
  vtkColorTransferFunction* ColorTransferFunction = nullptr;
  vtkPiecewiseFunction* OpacityFunction = nullptr;
  double ScalarOpacityUnitDistance = 1.0;
  bool ChromaticAttenuation = false;
  double AmbientOcclusion = 0.0;
  double AmbientOcclusionRadius = 0.0;

private:
  vtkIlluminationVolumeAlgorithm(const vtkIlluminationVolumeAlgorithm&) = delete;
  void operator=(const vtkIlluminationVolumeAlgorithm&) = delete;

  bool ValidGeometry(
    vtkImageData* input, volillum::GridGeometry& data, volillum::GridGeometry& target);

  // Light the whole image input into output (the serial update); with `piece` (an extent
  // of the illumination grid: LightsPointsIndependently, or a parallel run that shares
  // sweeps) output only the points of that extent.
  void Illuminate(vtkImageData* input, vtkImageData* output, const int* piece = nullptr);
  // A parallel update of a filter that LightsDistributedPieces: each process classifies its
  // piece (the transfer functions over the scalar range of all pieces) and
  // ComputeDistributedIllumination gives it its part of the illumination grid. `inInfo`:
  // the input's pipeline information (the whole extent and geometry). Pieces that are not
  // the blocks are gathered into blocks first (Blocks), and the output covers the block;
  // cell scalars become point scalars over the block (BlockScalars).
  void IlluminateDistributed(vtkMultiProcessController* controller, vtkInformation* inInfo,
    vtkImageData* input, vtkImageData* output);
  // Collective, for IlluminateDistributed: `shape` gets the whole extent of `inInfo` and the
  // geometry the pieces agree on; false (with an error) when they differ.
  bool DistributedShape(vtkMultiProcessController* controller, vtkInformation* inInfo,
    vtkImageData* input, vtkImageData* shape);
  // Collective: `input` becomes this process's block (`block`; nullptr for none) of the image
  // `shape` with point scalars to light, gathered from the pieces where they are not the
  // blocks (Blocks) and converted from cell scalars (BlockScalars); false (with the reason)
  // on every process when any cannot.
  bool BlockOfInput(vtkMultiProcessController* controller, vtkImageData* shape, const int* block,
    vtkImageData*& input);
  // Collective: the scalars of every block checked (and the lights), and the range of all
  // blocks' finite scalars, which the transfer functions span; false when any fails.
  bool DistributedScalarRange(
    vtkMultiProcessController* controller, vtkImageData* input, bool piece, double range[2]);
  // Add AmbientOcclusion x the ambient transmittance at the points `lit` into rgb (3 floats a
  // point), computing it unless the last one is still valid (inputModified: see
  // UpdateClassification); false when aborted.
  bool AddAmbientOcclusion(const volillum::GridGeometry& lit, bool inputModified, float* rgb);
  // The end of a successful update: the output's geometry (the illumination grid `target`,
  // or its part `extent`), its arrays and the update's report.
  void FinishOutput(vtkImageData* output, const int extent[6], const volillum::GridGeometry& target,
    vtkMatrix3x3* direction, vtkFloatArray* illumination, const UpdateReport& report,
    double seconds);
  // Classify the scalars (Scalars) on the data grid unless the cached classification was made
  // from the same input and settings (inputModified tells which); false after an error.
  // `range`: the scalar range of the transfer functions (nullptr: the scalars' own).
  bool UpdateClassification(
    const volillum::GridGeometry& data, bool& inputModified, const double* range = nullptr);

  // What the last successful classification was made from; equal keys mean the cached
  // classification is still valid.
  struct ClassificationKey
  {
    vtkMTimeType Scalars = 0;
    int Component = -1;
    vtkMTimeType Color = 0;
    vtkMTimeType Opacity = 0;
    double Scale = 0.0;
    double UnitDistance = 0.0;
    bool Chromatic = false;
    bool HasRange = false;
    double Range[2] = { 0.0, 0.0 };
    bool operator==(const ClassificationKey& o) const;
  };
  ClassificationKey ClassifiedKey;
  volillum::PointScalars Scalars; // the last update's, reused while their source is unchanged
  bool HasClassification = false;
  volillum::ClassifiedVolume Classified;
  std::unique_ptr<const volillum::EmptyBlocks> Empty; // of Classified, when asked for
  vtkSmartPointer<vtkImageData> LastOutput;
  // The ambient transmittance of the last update with ambient occlusion, what it was computed
  // for (the radius, the points' grid) and how many points this update computed it at.
  vtkSmartPointer<vtkFloatArray> Occlusion;
  std::array<double, 10> OcclusionKey{};
  long long OcclusionPoints = 0;
  vtkMultiProcessController* Controller = nullptr;
  std::unique_ptr<volillum::DistributedInput> Distributed; // the whole input of a parallel run
  // Point scalars over this process's block from cell scalars (a parallel run lit where the
  // pieces are).
  std::unique_ptr<volillum::BlockPointScalars> BlockScalars;
  // This process's block of the lit array, from pieces that are not the blocks.
  std::unique_ptr<volillum::BlockOfPieces> Blocks;
  // During a parallel update that shares sweeps: its controller and every process's extent
  // of the illumination grid (GatherExtents); null and empty otherwise. SumsDone: whether
  // OutputIllumination took part in the sums of the current update.
  vtkMultiProcessController* SharingController = nullptr;
  std::vector<int> PieceExtents;
  bool SumsDone = false;
};

#endif
