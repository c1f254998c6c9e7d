/**
 * @file FilteredShadowsKernel.h
 * @brief Soft shadows at the points of a grid from light-aligned summed-area tables: the
 * per-point part of the low-pass filtered volumetric shadows (section 4.2 of the paper).
 *
 * Method: M. Ament, F. Sadlo, C. Dachsbacher and D. Weiskopf, "Low-Pass Filtered Volumetric
 * Shadows", IEEE Transactions on Visualization and Computer Graphics 20(12), 2014: the
 * transmittance exp(-filtered optical depth) toward every light (eq. 12-13 for directional
 * lights read from Cartesian tables shared along the axes of one frame, eq. 14-15; eq. 16-24
 * for point and spot lights read from spherical tables), times the light's radiance, summed
 * over the lights. For hard shadows the first NearSegmentCells table cells of every shadow
 * ray are integrated through the full-resolution data instead (see NearSegmentLength).
 * @sa SummedAreaTableKernel.h vtkFilteredVolumetricShadows
 */
#ifndef FilteredShadowsKernel_h
#define FilteredShadowsKernel_h

#include "IlluminationClassification.h"
#include "IlluminationLights.h"
#include "RayMarchKernel.h"
#include "SummedAreaTableKernel.h"
#include "VolIllumKernelsModule.h"

#include <array>
#include <vector>

namespace volillum
{

/// A directional light as a table lookup: which table, which of its axes, toward which end.
struct ShadowLookup
{
  size_t Index; // of the light
  size_t Table;
  int Axis;
  int Sign;
  std::array<double, 3> Radiance;
  std::array<double, 3> Toward; // unit direction toward the light
  double Spread;                // of its shadow cone (DirectionalConeSpread), 0: hard
};

/// A point or spot light and its spherical table.
struct SphericalLookup
{
  size_t Index; // of the light
  size_t Table;
  LightState Light;
};

/// The lights that are on as table lookups: a directional light joins the first frame that
/// has its direction as an axis (eq. 14), or starts a frame of its own; a point or spot light
/// gets a spherical table of its own.
VOLILLUMKERNELS_EXPORT void GroupShadowLights(const std::vector<LightState>& lights,
  std::vector<SatFrame>& frames, std::vector<ShadowLookup>& lookups,
  std::vector<SphericalLookup>& sphericalLookups);

/// Length of the near segment of a shadow ray for tables of cells of size `cell` and a patch
/// of half side `patch`: NearSegmentCells cells for hard shadows (a patch at most a cell wide),
/// shortening linearly to nothing as the patch widens to two cells.
VOLILLUMKERNELS_EXPORT double NearSegmentLength(double cell, double patch);

/**
 * What lighting the points needs: the data, the tables and the settings. Transmittances
 * (per light, or null) receive each light's transmittance (Channels floats per point).
 */
struct VOLILLUMKERNELS_EXPORT PointShading
{
  const ClassifiedVolume& Volume;
  const EmptyBlocks* Empty; // for the near segments; none for soft shadows
  double Bounds[6];
  int Channels;
  const std::vector<ShadowLookup>& Lookups;
  const std::vector<CartesianSAT>& Tables;
  const std::vector<SphericalLookup>& SphericalLookups;
  const std::vector<SphericalSAT>& SphericalTables;
  double Patch;                       // half the patch side
  double HalfWidth;                   // of the patch read from a Cartesian table
  double NearLength;                  // of a directional light's near segment
  std::vector<double> SphericalNear;  // near segment per spherical table
  std::vector<double> Gaussian;       // kernel weights, empty for the box
  std::vector<float*> Transmittances; // per light, or null
};

/// Shade every point of the grid target into rgb (3 floats a point: the light reaching it
/// from every light that is on), row by row along x, in 20 chunks with progress (the fraction
/// done) after each; false when progress asked to stop. The near segments of a row toward a
/// directional light share their samples' cells along y and z (RowSegmentOpticalDepths).
VOLILLUMKERNELS_EXPORT bool ShadePoints(const PointShading& shading, const GridGeometry& target,
  float* rgb, const ProgressCallback& progress);

}

#endif
