/**
 * @file RayMarchKernel.h
 * @brief Brute-force single-scattering illumination: from every point march to every light.
 *
 * The emission-absorption model of N. Max, "Optical Models for Direct Volume Rendering", IEEE
 * Transactions on Visualization and Computer Graphics 1(2), 1995, evaluated by marching.
 *
 * This is the reference the faster methods are tested against. From a point p the kernel
 * marches toward each light (to the volume boundary for a directional light, to the light
 * position or the boundary, whichever comes first, for point and spot lights) with the
 * midpoint rule and multiplies the chromatic step transmittances
 * (1 - a (1 - c)) of IlluminationClassification.h. The radiance of a light (colour x
 * intensity, times the spot-cone factor) times that transmittance is summed over lights.
 * Cost: points x lights x steps trilinear samples; marching stops early once every
 * channel's transmittance is below MinimumTransmittance and the ray counts as dark, which
 * bounds the absolute error of that cut by MinimumTransmittance x radiance. The samples of
 * a ray can be taken piece by piece (PartialTransmittance): the product of the pieces'
 * parts is the ray's transmittance, which lets processes of a parallel run march only
 * through the piece of the volume they hold.
 */
#ifndef RayMarchKernel_h
#define RayMarchKernel_h

#include "IlluminationClassification.h"
#include "IlluminationLights.h"
#include "VolIllumKernelsModule.h"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace volillum
{

struct RayMarchSettings
{
  /// Step length as a fraction of the smallest data spacing.
  double StepFraction = 0.5;
  /// Transmittance below which (in every channel) a ray stops and counts as dark (0).
  double MinimumTransmittance = 1e-5;
};

/// Called with the fraction done; returning false stops the computation.
using ProgressCallback = std::function<bool(double)>;

/**
 * Which blocks of 4 x 4 x 4 cells of a classified volume hold no extinction at any of their
 * points. A trilinear sample in such a block is 0, so marching skips it without reading
 * the volume: the result is the same, and empty space (most of a CT's box) costs a lookup
 * per step instead of a sample.
 */
class VOLILLUMKERNELS_EXPORT EmptyBlocks
{
public:
  /// Cells of a block along each axis.
  static constexpr int Cells = 4;
  explicit EmptyBlocks(const ClassifiedVolume& volume);
  /// The blocks of the grid `whole` as a piece of it shows them (`volume`: its points from
  /// `offset` on, in whole's indices): a block is marked empty unless a point of it in the
  /// piece holds extinction, so blocks the piece does not reach are marked empty. A block of a
  /// grid cut into pieces that share their boundary points is empty where every piece marks it
  /// so: combine the pieces' Marks (the smallest) and call Update.
  EmptyBlocks(
    const GridGeometry& whole, const ClassifiedVolume& volume, const std::array<int, 3>& offset);
  /// One mark a block (1: empty), x fastest.
  std::vector<char>& Marks() { return this->Empty; }
  const std::vector<char>& Marks() const { return this->Empty; }
  /// Takes changed Marks into account.
  void Update();
  /// Whether samples in a grid cell (TrilinearCell::Index) are certainly 0.
  bool ContainsCell(const int cell[3]) const
  {
    return this->RowContains(this->Row(cell[1], cell[2]), cell[0]);
  }
  /// ContainsCell in two steps for the cells of a row along x: the row's blocks (cell indices
  /// along y and z), then whether cell x of the row is in an empty block.
  long long Row(int cellY, int cellZ) const
  {
    return this->Blocks[0] *
      (std::min(cellY / Cells, this->Blocks[1] - 1) +
        this->Blocks[1] * static_cast<long long>(std::min(cellZ / Cells, this->Blocks[2] - 1)));
  }
  bool RowContains(long long row, int cellX) const
  {
    return this->Empty[static_cast<size_t>(row + std::min(cellX / Cells, this->Blocks[0] - 1))] !=
      0;
  }
  /// Whether the cells first to last (first <= last) along axis a (0 or 1 only: x or y) of
  /// the row of cells through `cell` all lie in empty blocks: two lookups whatever the row's
  /// length.
  bool ContainsCells(int a, const int cell[3], int first, int last) const;

private:
  std::array<int, 3> Last{ { 0, 0, 0 } };   // last point index per axis
  std::array<int, 3> Blocks{ { 0, 0, 0 } }; // blocks per axis
  std::vector<char> Empty;
  // Per axis a (x and y) and block: how many blocks are not empty from the first of its row
  // along a to it, inclusive, modulo 2^16 (exact differences while a row has fewer than 2^16
  // blocks; empty for longer rows, which ContainsCells walks block by block).
  std::array<std::vector<std::uint16_t>, 2> Filled;
};

/**
 * Per-channel transmittance from point p to the light (0 outside a spot cone); with
 * `empty`, samples in empty blocks are skipped. A ray whose transmittance falls below
 * MinimumTransmittance in every channel counts as dark (0).
 */
VOLILLUMKERNELS_EXPORT std::array<double, 3> RayMarchTransmittance(const ClassifiedVolume& volume,
  const LightState& light, const double p[3], const RayMarchSettings& settings,
  const EmptyBlocks* empty = nullptr);

/**
 * A classified volume as a piece of a bigger grid (a distributed volume's piece). Whole:
 * the grid of all pieces (the geometry RayMarchTransmittance marches through); Offset: the
 * whole grid's index of the volume's first point; FirstCell .. LastCell: the cells (named
 * by their first point's index in the whole grid) whose samples the piece takes. Pieces
 * that share their boundary planes and take the cells from their first plane up to their
 * last take every sample of the whole grid exactly once between them.
 */
struct VolumePiece
{
  GridGeometry Whole;
  std::array<int, 3> Offset{ { 0, 0, 0 } };
  std::array<int, 3> FirstCell{ { 0, 0, 0 } };
  std::array<int, 3> LastCell{ { -1, -1, -1 } };
  /// The volume as the only piece of its grid (all its cells).
  static VolumePiece WholeOf(const ClassifiedVolume& volume);
  /// Whether the piece takes the samples of `cell` (indexed in the whole grid); if so, the
  /// cell's index becomes its index in the piece's volume.
  bool Takes(TrilinearCell& cell) const;
};

/**
 * The part of RayMarchTransmittance's ray from p to a light (`incidence`: ComputeIncidence
 * of the light at p; the same steps through the whole grid) that lies in the piece: per channel,
 * the product of the step transmittances of the samples in its cells (1 where there is none).
 * Marching stops once every channel is below `cut`. The products of all pieces, times the cone
 * factor, then DarkenedTransmittance, give RayMarchTransmittance up to the order of the
 * multiplications.
 */
VOLILLUMKERNELS_EXPORT std::array<double, 3> PartialTransmittance(const ClassifiedVolume& volume,
  const VolumePiece& piece, const Incidence& incidence, const double p[3],
  const RayMarchSettings& settings, double cut, const EmptyBlocks* empty = nullptr);

/// A ray's transmittance from its cone factor and the product of its steps' transmittances:
/// 0 where every channel is below MinimumTransmittance.
VOLILLUMKERNELS_EXPORT std::array<double, 3> DarkenedTransmittance(
  double cone, const std::array<double, 3>& product, const RayMarchSettings& settings);

/**
 * Optical depth per channel (extinction x k_c with three channels, extinction alone with
 * one) of the segment from p along the unit direction d over `length`, through the
 * classified data at full resolution: midpoint rule with steps of at most its smallest
 * spacing; with `empty`, samples in empty blocks are skipped.
 */
VOLILLUMKERNELS_EXPORT void SegmentOpticalDepth(const ClassifiedVolume& volume, const double p[3],
  const double d[3], double length, int channels, double depth[3],
  const EmptyBlocks* empty = nullptr);

/**
 * SegmentOpticalDepth for a row of `count` points (x[i], y, z) along the grid's x axis, all
 * with the same direction and length: the samples of the row share their cells and fractions
 * along y and z, so only the position along x is found per point. depth receives three values
 * per point (the channels asked for), each the same as SegmentOpticalDepth gives.
 */
VOLILLUMKERNELS_EXPORT void RowSegmentOpticalDepths(const ClassifiedVolume& volume, const double* x,
  int count, double y, double z, const double d[3], double length, int channels, double* depth,
  const EmptyBlocks* empty = nullptr);

/// Summed illumination of the lights that are on at point p: radiance x transmittance.
VOLILLUMKERNELS_EXPORT std::array<double, 3> RayMarchIlluminationAt(const ClassifiedVolume& volume,
  const std::vector<LightState>& lights, const double p[3], const RayMarchSettings& settings,
  const EmptyBlocks* empty = nullptr);

/// Fill rgb (3 floats per target point, x fastest) with the summed illumination of all
/// lights. Returns false when progress asked to stop (rgb is then incomplete).
VOLILLUMKERNELS_EXPORT bool RayMarchIllumination(const ClassifiedVolume& volume,
  const std::vector<LightState>& lights, const GridGeometry& target,
  const RayMarchSettings& settings, float* rgb, const ProgressCallback& progress);

}

#endif
