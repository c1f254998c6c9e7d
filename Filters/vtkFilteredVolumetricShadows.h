/**
 * @class vtkFilteredVolumetricShadows
 * @brief Soft volumetric shadows of controllable width from light-aligned summed-area
 * tables (the low-pass filtered volumetric shadows paper, section 4.2).
 *
 * For each directional light the optical depth toward the light is box-filtered over a
 * square patch of side FilterWidth voxels perpendicular to the light (eq. 12-13), read from
 * a Cartesian summed-area table aligned with the light (see SummedAreaTableKernel.h), and
 * the light reaches a point with transmittance exp(-filtered depth). The cost does not
 * depend on FilterWidth; FilterWidth 0 gives hard shadows at the table's resolution
 * (SATResolutionScale, default 1/2 of the input's). Lights along the six directions of one
 * frame share a table (eq. 14-15): lights are grouped into as few tables as possible.
 * Tables are kept while only the lights' colour, intensity or switch change.
 * PropagationPasses reports the number of tables built by the last update.
 *
 * For hard shadows (a patch at most one table cell wide) the first eight table cells of
 * every shadow ray, next to the sample, are integrated along the ray through the
 * full-resolution data instead of read from the table: there the optical depth changes
 * fastest from ray to ray (a sample inside a thin structure or at its edge). Beyond, the
 * table is read over a patch one data spacing wide. The segment shortens linearly to
 * nothing as the patch widens to two cells: soft shadows are filtered along the whole ray.
 *
 * Point and spot lights, outside or inside the volume, read a spherical summed-area table
 * centred on the light (eq. 16-24): the optical depth is averaged over the shadow rays
 * through a patch of constant base area at the sample; a spot light's cone is applied on
 * top. The table's angles are those of a cube-map face when the whole volume lies in front
 * of the light, azimuth and polar angle otherwise (volillum::SphericalSAT). The Gaussian
 * kernel applies to directional lights; point and spot lights use the box.
 *
 * Method: M. Ament, F. Sadlo, C. Dachsbacher and D. Weiskopf, "Low-Pass Filtered Volumetric
 * Shadows", IEEE Transactions on Visualization and Computer Graphics 20(12), 2014.
 *
 * @sa vtkMultiLightIlluminationVolume vtkRayMarchedIllumination vtkIlluminatedVolumeMapper
 */
#ifndef vtkFilteredVolumetricShadows_h
#define vtkFilteredVolumetricShadows_h

#include "FilteredShadowsKernel.h" // for the table lookups
#include "vtkIlluminationVolumeAlgorithm.h"

#include "vtkFloatArray.h"
#include "vtkSmartPointer.h"

class VOLILLUMFILTERS_EXPORT vtkFilteredVolumetricShadows : public vtkIlluminationVolumeAlgorithm
{
public:
  static vtkFilteredVolumetricShadows* New();
  vtkTypeMacro(vtkFilteredVolumetricShadows, vtkIlluminationVolumeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Side of the filter patch in voxels (0: hard shadows), clamped to [0, 1000]. Default 3.
   * A value that is not a finite number is refused with an error.
   */
  void SetFilterWidth(double value);
  vtkGetMacro(FilterWidth, double);
  ///@}

  enum FilterKernels
  {
    Box = 0,
    Gaussian = 1
  };

  ///@{
  /**
   * Filter kernel: Box (default, one table read per light) or Gaussian (eq. 25: the patch
   * cut into 5 x 5 squares weighted by a Gaussian of standard deviation a quarter of the
   * width, 25 reads).
   */
  vtkSetClampMacro(FilterKernel, int, Box, Gaussian);
  vtkGetMacro(FilterKernel, int);
  ///@}

  ///@{
  /**
   * Also output each light's transmittance (exp(-filtered depth), before any spot cone) as
   * the point array "Transmittance<i>" for light i that is on: 3 components with chromatic
   * attenuation, 1 without. Default off.
   */
  vtkSetMacro(PerLightTransmittance, bool);
  vtkGetMacro(PerLightTransmittance, bool);
  vtkBooleanMacro(PerLightTransmittance, bool);
  ///@}

  ///@{
  /**
   * In a parallel run, on (the default): each process lights the
   * points of its own piece from its block of the input grown by the reach of a shadow's
   * patch and near segment (a few data spacings, taken from its neighbours) and the part of
   * each table over that grown block (Cartesian for directional lights, spherical for point
   * and spot lights), and receives, per column of that part, the sum of the table's cells
   * between it and each light from the others.
   * No process holds the whole input or whole tables, and each reads only its own points'
   * shadows. Off: every process assembles the whole input and builds whole tables, then
   * lights only the points of its piece (whole-volume memory on each). The result is the same
   * either way, up to rounding. Field arrays GrownPoints and SentBytes report the grown
   * block's points and the bytes a process sent.
   */
  vtkSetMacro(DistributedTables, bool);
  vtkGetMacro(DistributedTables, bool);
  vtkBooleanMacro(DistributedTables, bool);
  ///@}

  ///@{
  /** Resolution of the summed-area tables relative to the input: 1, 0.5 (default) or 0.25. */
  vtkSetMacro(SATResolutionScale, double);
  vtkGetMacro(SATResolutionScale, double);
  ///@}

  /**
   * Largest memory the filter keeps for selective updates (bytes): the light each light
   * brings to every point per unit of its radiance (4 bytes a point and light, 12 with
   * ChromaticAttenuation). Within it, an update shades again only the lights whose geometry
   * (type, position, direction, cone, size, switch) or table changed since the last one,
   * when the classification, FilterWidth, FilterKernel and the grid are those of that update:
   * a colour or intensity edit shades nothing, a Radius edit or a move that light alone (the
   * field array ShadedLights counts the lights shaded). Beyond it, and with PerLightTransmittance,
   * every update shades every light.
   */
  static constexpr double MaximumShareBytes = 1024.0 * 1024.0 * 1024.0;

protected:
  vtkFilteredVolumetricShadows() = default;
  ~vtkFilteredVolumetricShadows() override = default;

  bool LightsPointsIndependently() const override { return true; }
  // With DistributedTables.
  bool LightsDistributedPieces() const override;
  bool UsesLightSize() const override { return true; }
  void ComputeDistributedIllumination(vtkMultiProcessController* controller,
    const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    const std::vector<int>& extents, bool inputModified, float* rgb, UpdateReport& report) override;
  bool ComputeIllumination(const volillum::ClassifiedVolume& volume,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    bool inputModified, float* rgb, UpdateReport& report) override;

  double FilterWidth = 3.0;
  int FilterKernel = Box;
  bool PerLightTransmittance = false;
  bool DistributedTables = true;

  void AddOutputArrays(vtkPointData* pointData) override;
  void AddOutputFieldData(vtkFieldData* fieldData) override;
  double SATResolutionScale = 0.5;

private:
  vtkFilteredVolumetricShadows(const vtkFilteredVolumetricShadows&) = delete;
  // Tables for the frames and the point and spot lights, reusing those of the last update
  // whose frame or light position, resolution and classification hold; built counts the new
  // ones. With `piece` (a parallel run: the grown block), the Cartesian tables' windows over it,
  // and no abort.
  bool UpdateTables(const volillum::ClassifiedVolume& volume,
    const std::vector<volillum::SatFrame>& frames,
    const std::vector<volillum::SphericalLookup>& sphericalLookups, double cellSize, int channels,
    bool inputModified, int& built, const volillum::EmptyBlocks* empty,
    const volillum::VolumePiece* piece = nullptr, double margin = 0.0);
  // The patch a shadow reads for data of this minimum spacing: half its side (PointShading's
  // Patch), half the side a Cartesian table reads (HalfWidth) and the near segment toward a
  // directional light (NearLength).
  struct Patch
  {
    double Half;
    double HalfWidth;
    double Near;
  };
  Patch PatchFor(double minSpacing) const;
  // The shading (PointShading) of the lookups with the current tables, for the classification
  // `volume` (its empty blocks `empty`) in a grid with these bounds.
  volillum::PointShading Shading(const volillum::ClassifiedVolume& volume, const double bounds[6],
    const std::vector<volillum::ShadowLookup>& lookups,
    const std::vector<volillum::SphericalLookup>& sphericalLookups,
    std::vector<float*> transmittances, const volillum::EmptyBlocks* empty);
  // The reach of a shadow's table reads around a point (`reach`) and the margin of a
  // spherical table's samples around its cells' centres (`margin`), for tables of `cell`.
  void TableReach(const volillum::GridGeometry& data, double cell,
    const std::vector<volillum::SphericalLookup>& sphericalLookups, double& reach,
    double& margin) const;
  // The points of this process's extent `own` of the illumination grid shaded from its grown
  // block and its tables' windows (`data`: the whole data grid).
  void ShadeGrownBlock(const volillum::GridGeometry& data,
    const volillum::ClassifiedVolume& grownVolume,
    const std::vector<volillum::ShadowLookup>& lookups,
    const std::vector<volillum::SphericalLookup>& sphericalLookups,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    const int own[6], const volillum::EmptyBlocks* empty, float* rgb);
  // Shade the points of `target` light by light into Shares and sum them into rgb: when
  // `kept` (the classification, the shading settings and the grid are the last update's),
  // only the lights whose geometry or table changed since then are shaded again; false when
  // aborted.
  bool ShadeSelectively(const volillum::ClassifiedVolume& volume, const double bounds[6],
    const std::vector<volillum::LightState>& lights,
    const std::vector<volillum::ShadowLookup>& lookups,
    const std::vector<volillum::SphericalLookup>& sphericalLookups,
    const volillum::GridGeometry& target, bool kept, float* rgb);
  // The per-light transmittance arrays (PerLightTransmittance), null for the others.
  std::vector<float*> AllocateTransmittances(
    const std::vector<volillum::LightState>& lights, int channels, long long points);
  void operator=(const vtkFilteredVolumetricShadows&) = delete;

  // Tables of the last update, reused while the classification and their frames hold.
  std::vector<volillum::CartesianSAT> Tables;
  std::vector<volillum::SphericalSAT> SphericalTables;
  double TablesScale = 0.0;
  // Which tables the last UpdateTables built (per frame and per point or spot light).
  std::vector<bool> RebuiltTables;
  std::vector<bool> RebuiltSphericalTables;
  std::vector<double> TablesWindow; // the whole grid and piece of windows; empty: whole tables
  std::vector<vtkSmartPointer<vtkFloatArray>> Transmittances;
  // Per light of the last serial update: the light that reaches each point per unit of its
  // radiance (spot factor x transmittance, one value a point, three with chromatic
  // attenuation; empty for a light that is off or when there are none), the light's state
  // it was shaded for (radiance 1), and what else it depends on (SharesKey: the grid and the
  // shading settings). ShadedLights: how many lights the last update shaded.
  struct LightShare
  {
    volillum::LightState Geometry;
    std::vector<float> Values;
  };
  std::vector<LightShare> Shares;
  std::vector<double> SharesKey;
  int ShadedLights = 0;
  // The last parallel update with distributed tables (field arrays GrownPoints, SentBytes).
  bool DistributedUpdate = false;
  long long GrownPoints = 0;
  long long SentBytes = 0;
};

#endif
