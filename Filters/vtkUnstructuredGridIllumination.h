/**
 * @class vtkUnstructuredGridIllumination
 * @brief Illumination of an unstructured grid by many coloured lights with a two-level
 * light solver (Shih, Zhang and Ma).
 *
 * Input: a vtkUnstructuredGrid with a scalar array (SetInputArrayToProcess; the active
 * point scalars, else the active cell scalars, by default). Cell data are lit as point data,
 * each point the average of the cells around it (vtkCellDataToPointData); an array of
 * several components is lit by its magnitude or one component (ScalarComponent). Cells other than
 * tetrahedra (hexahedra, wedges, pyramids, voxels) are split into tetrahedra with
 * vtkDataSetTriangleFilter; 2D cells are ignored (their points, in no tetrahedron, get the light of
 * level 0, also where a parallel piece holds 2D cells only); tetrahedra of (near) zero volume are
 * left out of the light walk and inverted ones are reoriented. Output: the input with the point
 * array "Illumination" (3-component float, the units of the image filters: an unoccluded white
 * light of intensity 1 gives (1,1,1)), optionally "LitColors" (see SetLitColors), and the field
 * arrays UpdateMode (0 full, 1 selective), PropagationPasses (lights propagated), PendingPasses
 * (0), UpdateSeconds, Level0Seconds, Level1Seconds, ScatteringSeconds and LitPoints (the points
 * lit: the grid's, or in parallel those of the piece and the cells near it).
 *
 * Per light: level 0 resamples the classified extinction onto a Level0Resolution grid
 * over the mesh bounds (blank points transparent) and propagates the light there along
 * rays (the Multi-Light Illumination Volume's propagation); level 1 refines it at every
 * vertex: the level-0 light a walk of Level1Iterations mean edge lengths toward the light
 * away, attenuated exactly through the tetrahedra walked (see TetrahedralLightKernel.h). The lights
 * are summed with their colours and a Gauss-Seidel diffusion step (ScatteringStrength per channel,
 * ScatteringIterations) approximates multiple scattering.
 *
 * Updates are selective: each light's transmittance is kept with the light geometry it was
 * computed for, so moving one light recomputes that light only, and changing colours,
 * intensities, switches, cone angles or scattering recomputes none (only the combination
 * and the scattering). The data, the transfer functions, Absorption, Level0Resolution and
 * Level1Iterations make every light recompute. Aborting keeps the previous output.
 *
 * Bad input (no or non-numeric scalars, no 3D cells, no cell with a volume, non-finite
 * light parameters, absurd resolutions) gives a vtkErrorMacro and an empty output.
 *
 * Method: M. Shih, Y. Zhang and K.-L. Ma, "Advanced Lighting for Unstructured-Grid Data
 * Visualization", IEEE Pacific Visualization Symposium (PacificVis), 2015.
 *
 * @sa vtkMultiLightIlluminationVolume vtkTetrahedralizeSurface vtkAdaptiveTetrahedralMesh
 */
#ifndef vtkUnstructuredGridIllumination_h
#define vtkUnstructuredGridIllumination_h

#include "IlluminationFilterSupport.h" // for volillum::PointScalars
#include "IlluminationLightList.h"
#include "TetrahedralLightKernel.h"
#include "VolIllumFiltersModule.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGridAlgorithm.h"

#include <array> // for std::array
#include <functional>
#include <memory> // for std::unique_ptr
#include <vector>

namespace volillum
{
class NeighborhoodGrid;
}

class vtkColorTransferFunction;
class vtkLight;
class vtkMultiProcessController;
class vtkPiecewiseFunction;
class vtkUnsignedCharArray;
class vtkUnstructuredGrid;

class VOLILLUMFILTERS_EXPORT vtkUnstructuredGridIllumination : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkUnstructuredGridIllumination* New();
  vtkTypeMacro(vtkUnstructuredGridIllumination, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Add one light from the 15 numbers of the flat layout (ParaView's Lights table sends one
   * row per light this way after RemoveAllLights).
   */
  void AddLightParameters(const double parameters[15]);

  ///@{
  /**
   * The lights, as for the image filters (vtkIlluminationVolumeAlgorithm): vtkLight
   * objects held by reference, or the flat list of 15 numbers per light.
   */
  void AddLight(vtkLight* light);
  void RemoveAllLights();
  int GetNumberOfLights() const { return this->Lights.Size(); }
  vtkLight* GetLight(int index) const;
  void SetNumberOfLightParameters(int count);
  int GetNumberOfLightParameters() const;
  void SetLightParameter(int index, double value);
  double GetLightParameter(int index) const;
  ///@}

  ///@{
  /**
   * Transfer functions (a grey ramp over the scalar range without them), the scalar
   * opacity unit distance and chromatic attenuation, as for the image filters.
   */
  void SetColorTransferFunction(vtkColorTransferFunction* ctf);
  vtkGetObjectMacro(ColorTransferFunction, vtkColorTransferFunction);
  /**
   * Which component of a multi-component scalar array is lit: -1 (default) its magnitude,
   * 0 .. components - 1 that component. Ignored for one-component scalars.
   */
  vtkSetClampMacro(ScalarComponent, int, -1, VTK_INT_MAX);
  vtkGetMacro(ScalarComponent, int);
  void SetOpacityFunction(vtkPiecewiseFunction* otf);
  vtkGetObjectMacro(OpacityFunction, vtkPiecewiseFunction);
  vtkSetMacro(ScalarOpacityUnitDistance, double);
  vtkGetMacro(ScalarOpacityUnitDistance, double);
  vtkSetMacro(ChromaticAttenuation, bool);
  vtkGetMacro(ChromaticAttenuation, bool);
  vtkBooleanMacro(ChromaticAttenuation, bool);
  ///@}

  ///@{
  /**
   * Points of the level-0 grid along x, y and z (2 to MaximumLevel0Axis each, at most
   * MaximumLevel0Points in all). Default 128^3.
   */
  vtkSetVector3Macro(Level0Resolution, int);
  vtkGetVector3Macro(Level0Resolution, int);
  ///@}

  ///@{
  /**
   * Absorption strength sigma_a: light crossing a segment of opacity alpha keeps
   * (1 - alpha)^sigma_a of itself. 1 (default) is the physical attenuation of the image
   * filters; larger values darken shadows, 0 switches them off.
   */
  vtkSetClampMacro(Absorption, double, 0.0, 1e6);
  vtkGetMacro(Absorption, double);
  ///@}

  ///@{
  /**
   * Length of the level-1 walk in mean edge lengths (semi-Lagrangian steps, taken as one
   * walk): every vertex takes the level-0 light this far toward the light and attenuates it
   * exactly through the tetrahedra on the way. -1 (default) walks four level-0 cells
   * (volillum::Level1Cells); 0 keeps the level-0 solution. Longer walks cost more and, in a
   * parallel run, gather more of the other pieces' cells.
   */
  vtkSetClampMacro(Level1Iterations, int, -1, 100000);
  vtkGetMacro(Level1Iterations, int);
  ///@}

  ///@{
  /**
   * Scattering strength per channel (sigma_s dt of eq. 12, relative to the mean edge
   * length so that it does not depend on the mesh's units). Default 0 0 0: no scattering.
   */
  vtkSetVector3Macro(ScatteringStrength, double);
  vtkGetVector3Macro(ScatteringStrength, double);
  ///@}

  ///@{
  /**
   * Gauss-Seidel iterations of the scattering step. Default 10.
   */
  vtkSetClampMacro(ScatteringIterations, int, 0, 100000);
  vtkGetMacro(ScatteringIterations, int);
  ///@}

  ///@{
  /**
   * When on (default), also add the point array "LitColors": RGBA bytes, the colour
   * transfer function's colour times the Illumination (clamped to 1) and the opacity
   * function's opacity. Volume rendering of the grid with this array as direct colours
   * (vtkVolumeProperty IndependentComponents off; in ParaView Map Scalars off and Multi
   * Components Mapping on) shows the lit volume with per-vertex lighting.
   */
  vtkSetMacro(LitColors, bool);
  vtkGetMacro(LitColors, bool);
  vtkBooleanMacro(LitColors, bool);
  ///@}

  ///@{
  /**
   * How LitColors turn light into brightness (as vtkIlluminatedVolumeMapper's Exposure).
   * 0 (default): the colour x Illumination, clamped to 1. Above 0: the colour x (1 -
   * exp(-Exposure x Illumination)), which approaches the colour itself (the brightness of
   * local shading) where much light arrives, shadowed material darker.
   */
  vtkSetClampMacro(Exposure, double, 0.0, 100.0);
  vtkGetMacro(Exposure, double);
  ///@}

  ///@{
  /**
   * The processes of a parallel run (default: the global controller). With more than one
   * process each lights its piece (ghost cells dropped) with the cells of other pieces near
   * it, exchanging values with their processes (volillum::NeighborhoodGrid); no process
   * holds the whole grid. Each piece gets its points' values, those of a serial run up to
   * rounding. Every process must update the filter together (a parallel update is not
   * aborted); an empty piece is normal and gives an empty output. Set nullptr to light
   * each piece on its own.
   */
  virtual void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  vtkMTimeType GetMTime() override;

  /// Largest level-0 grid (512^3 points), and most points along one of its axes.
  static constexpr long long MaximumLevel0Points = 1LL << 27;
  static constexpr int MaximumLevel0Axis = 1024;

protected:
  vtkUnstructuredGridIllumination();
  ~vtkUnstructuredGridIllumination() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkUnstructuredGridIllumination(const vtkUnstructuredGridIllumination&) = delete;
  void operator=(const vtkUnstructuredGridIllumination&) = delete;

  // Wall time of the phases of an update, reported in the output's field data.
  struct PhaseSeconds
  {
    double Mesh = 0.0, Resample = 0.0, Level0 = 0.0, Level1 = 0.0, Scattering = 0.0;
    double Update = 0.0; // all of it
  };

  // Level0Resolution as an array.
  std::array<int, 3> Level0Dimensions() const;
  // Light the whole grid input into output (the serial update).
  void Illuminate(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output);
  // Collective: light this process's piece of a distributed grid (input) into output.
  void IlluminatePiece(
    vtkMultiProcessController* controller, vtkUnstructuredGrid* input, vtkUnstructuredGrid* output);
  // Collective: the mesh of the piece and its neighbours (Neighborhood) with the whole
  // grid's bounds, mean edge length and colouring; false after an error anywhere.
  bool PrepareDistributedMesh(vtkMultiProcessController* controller, vtkUnstructuredGrid* input);
  // Check the input, the scalars (kept in Scalars) and the lights; false after an error.
  // Without needCells a grid of points alone passes (a parallel piece whose cells are 2D).
  bool CheckInput(vtkUnstructuredGrid* input, bool needCells = true);
  // Check the settings; false after an error.
  bool CheckSettings();
  // Classify and resample onto the level-0 grid when anything but the lights changed (a
  // full update: report.Mode 0); false after an error. With a controller (collective) the
  // classification spans the range of all pieces and the level-0 grid combines them.
  bool UpdateLevel0Grid(
    volillum::UpdateReport& report, vtkMultiProcessController* controller = nullptr);
  // Propagate the lights whose transmittance is missing or was computed for another light
  // geometry; false when aborted. With a neighbourhood (collective: a parallel run, never
  // aborted) the values of other pieces' points come from their processes after each step.
  bool PropagateChangedLights(const std::vector<volillum::LightState>& lights,
    volillum::UpdateReport& report, PhaseSeconds& seconds,
    const volillum::NeighborhoodGrid* neighborhood);
  // The lights summed with their colours (eq. 9) and scattered; afterColor(rgb), when given,
  // runs after each colour of the scattering.
  std::vector<float> CombineAndScatter(const std::vector<volillum::LightState>& lights,
    PhaseSeconds& seconds, const std::function<void(std::vector<float>&)>& afterColor);
  // The input with the illumination rgb (3 per point, the first of rgb for the input's
  // points; copies of a point take the first copy's), the lit colours and the field data.
  void FillOutput(vtkUnstructuredGrid* input, std::vector<float> rgb,
    const volillum::UpdateReport& report, const PhaseSeconds& seconds, vtkUnstructuredGrid* output);
  // The mesh of the tetrahedra of input (split from other cells); the first `own` of them
  // are its own (all when negative).
  bool PrepareMesh(vtkUnstructuredGrid* input, vtkIdType own = -1);
  // The structure PrepareMesh splits into tetrahedra: the input's cells but its ghost cells
  // (DUPLICATECELL in `ghosts`), every copy of a point replaced by the first at its place
  // (FirstAtPlace, cleared where no point has a copy).
  vtkSmartPointer<vtkUnstructuredGrid> JoinedStructure(
    vtkUnstructuredGrid* input, vtkUnsignedCharArray* ghosts);
  bool Classify(vtkDataArray* scalars, const double* range);
  vtkSmartPointer<vtkUnsignedCharArray> ShadeVertices(
    vtkDataArray* scalars, const std::vector<float>& rgb, vtkIdType points);

  volillum::LightList Lights;
  vtkColorTransferFunction* ColorTransferFunction = nullptr;
  vtkPiecewiseFunction* OpacityFunction = nullptr;
  double ScalarOpacityUnitDistance = 1.0;
  bool ChromaticAttenuation = false;
  int Level0Resolution[3] = { 128, 128, 128 };
  double Absorption = 1.0;
  int Level1Iterations = -1;
  double ScatteringStrength[3] = { 0.0, 0.0, 0.0 };
  int ScalarComponent = -1;
  int ScatteringIterations = 10;
  bool LitColors = true;
  double Exposure = 0.0;

  // Caches: the mesh (keyed by the input geometry), the scalars lit (derived from cell data
  // or several components), the per-vertex extinction and level-0
  // grid (keyed by everything a transmittance depends on but the light), and each light's
  // transmittance with the light geometry it was computed for.
  vtkMTimeType MeshKey = 0;
  volillum::PointScalars Scalars; // the last update's, reused while their source is unchanged
  volillum::TetrahedralMesh Mesh;
  // Per point of the mesh, the first point at its place (FirstPointsAtTheirPlaces), whose
  // cells it joins and whose values it takes; empty when every point has a place of its own.
  std::vector<vtkIdType> FirstAtPlace;
  const void* MeshArrays[2] = { nullptr, nullptr }; // the global ids and ghosts the mesh had
  volillum::VertexColoring Coloring;
  std::vector<double> SolutionKey;
  int Channels = 1;
  std::vector<float> Extinction;
  volillum::Level0Grid Level0;
  struct LightCache
  {
    bool Valid = false;
    volillum::LightState State;
    std::vector<float> Rho;
  };
  std::vector<LightCache> Cache;
  vtkSmartPointer<vtkUnstructuredGrid> LastOutput;
  vtkMultiProcessController* Controller = nullptr;
  // A parallel run's piece with the cells of other pieces near it, the scalar range of all
  // pieces, and the bounds of all pieces' points.
  std::unique_ptr<volillum::NeighborhoodGrid> Neighborhood;
  double NeighborhoodDepth = 0.0; // how far beyond the piece Neighborhood reaches
  double WholeRange[2] = { 0.0, 1.0 };
  double WholeBounds[6] = { 0, 0, 0, 0, 0, 0 };
};

#endif
