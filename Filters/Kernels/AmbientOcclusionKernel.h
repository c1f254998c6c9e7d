/**
 * @file AmbientOcclusionKernel.h
 * @brief Volumetric ambient occlusion from a summed-area table in the data's frame: at every
 * point, the transmittance averaged over the directions around it, each ray reaching as far
 * as a radius.
 *
 * Method (as in P. Schlegel, M. Makhinya and R. Pajarola, "Extinction-Based Shading and
 * Illumination in GPU Volume Ray-Casting", IEEE TVCG 17(12), 2011: the mean extinction of
 * neighbourhoods read from a summed-area table): the cube around a point is cut into 24
 * pyramids with their apex at the point, four to each face (the face's quadrants). The
 * optical depth along a pyramid is the integral over the distance t along its axis of the
 * extinction averaged over its section at t, divided by the cosine of its middle ray (whose
 * length it then is), up to where that ray is `radius` long. A stair of boxes stands for the
 * pyramid (each box AmbientOcclusionStepRatio times as long as the one before it and as wide
 * as the pyramid at the geometric mean of its ends), each read from the table in eight
 * lookups. The point's ambient transmittance is the mean over the pyramids of
 * exp(-optical depth). In a uniform medium of extinction s it is exp(-s radius), as every
 * ray of length radius gives. Against the average over 512 marched rays
 * (MarchedAmbientOcclusion) on blobs of material (TestAmbientOcclusion): material RMS 1.0 % of
 * the mean for a radius of 4 cells, 2.2 % for 8 (with 54 pyramids instead of 24, 1.0 and
 * 1.4 % at 2.25x the cost; on fainter blobs, leaving out the cosine made the error 6x). A
 * pyramid that reaches into opaque material counts as wholly hidden (the exponential of its
 * mean depth is at most its rays' mean transmittance): above an opaque plane, the table
 * darkens more than the rays do (0.50 against 0.73 at half the radius above it). Beyond the
 * data the medium is empty.
 * @sa SummedAreaTableKernel.h
 */
#ifndef AmbientOcclusionKernel_h
#define AmbientOcclusionKernel_h

#include "IlluminationClassification.h"
#include "RayMarchKernel.h"
#include "SummedAreaTableKernel.h"
#include "VolIllumKernelsModule.h"

namespace volillum
{

/// Growth in length from one box of an ambient-occlusion pyramid's stair to the next (3
/// gives the same figures on the test's blobs).
constexpr double AmbientOcclusionStepRatio = 2.0;

/// The summed-area table of a classified volume's extinction over the cells around its points
/// (each cell from half a spacing before its point to half a spacing after it, holding the
/// point's value), and the ambient transmittance it gives.
class VOLILLUMKERNELS_EXPORT AmbientOcclusionTable
{
public:
  /// Integrate the extinction (channels 1), or the extinction times each channel's
  /// absorption k_c (channels 3 of a chromatic volume; otherwise one channel).
  void Build(const ClassifiedVolume& volume, int channels);

  /// The ambient transmittance at `count` points of a row along the data's x axis (world x
  /// coordinates x, all at y and z) for rays of length `radius` (> 0), 3 floats a point into
  /// rgb (with one channel the three are equal). The boxes of the row's points share their
  /// ends along y and z: the table is collapsed onto x once for each such pair of ends
  /// (RunningIntegralTable::CollapseToLine), and each box reads at most four values.
  void RowTransmittance(
    const double* x, int count, double y, double z, double radius, float* rgb) const;

  /// RowTransmittance at one point.
  void Transmittance(const double p[3], double radius, float rgb[3]) const
  {
    this->RowTransmittance(p, 1, p[1], p[2], radius, rgb);
  }

  int GetNumberOfChannels() const { return this->Table.GetNumberOfChannels(); }

private:
  GridGeometry Geometry;
  RunningIntegralTable Table;
};

/// The ambient transmittance (AmbientOcclusionTable) at every point of the grid `points` into
/// rgb (3 floats a point; with one channel the three are equal), row by row, in 20 chunks
/// with progress (the fraction done) after each; false when progress asked to stop.
VOLILLUMKERNELS_EXPORT bool ComputeAmbientOcclusion(const AmbientOcclusionTable& table,
  const GridGeometry& points, double radius, float* rgb, const ProgressCallback& progress);

/// The reference the tables are measured against: the transmittance averaged over
/// `directions` rays (spread evenly over the sphere, a Fibonacci lattice) from p, each of
/// length `radius` or up to where it leaves the data, integrated through the full-resolution
/// data (SegmentOpticalDepth), per channel into out.
VOLILLUMKERNELS_EXPORT void MarchedAmbientOcclusion(const ClassifiedVolume& volume,
  const double p[3], double radius, int channels, int directions, double out[3]);

}

#endif
