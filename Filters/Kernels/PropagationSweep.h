/**
 * @file PropagationSweep.h
 * @brief One sweep of the light propagation kernel (LightPropagationKernel.h) as its sources
 * share it (private): the sweep's geometry, its ray sources and the functions one source
 * defines for the others.
 *
 * PropagationPlanning.cxx plans the sweeps and runs them; PropagationSweep.cxx runs one sweep
 * slice by slice (a directional source's ray lattices and the points' deposits) from what
 * SweepSetup.cxx prepares; SegmentTransmittance.cxx integrates the segments light is
 * attenuated over, one at a time or a row at once; PointLightRays.cxx follows a point or spot
 * source's anchored rays; SweepBands.cxx and SweepWedges.cxx run a sweep over a band of rows
 * or a wedge of a light's rays; FixedPointIllumination.cxx holds the fixed-point units.
 */
#ifndef PropagationSweep_h
#define PropagationSweep_h

#include "LightPropagationKernel.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace volillum
{
namespace propagation
{
// Where light of one geometry (kind, position or direction) comes from. Lights that share
// a geometry share the transmittance of their rays, so a sweep propagates each geometry
// once, whatever the lights' colours, intensities, weights and spot cones.
struct RaySource
{
  bool Directional;
  bool Inside;
  double Travel[3]; // directional: the direction light travels
  double Position[3];

  bool operator==(const RaySource& o) const
  {
    return this->Directional == o.Directional && this->Inside == o.Inside &&
      std::equal(this->Travel, this->Travel + 3, o.Travel) &&
      std::equal(this->Position, this->Position + 3, o.Position);
  }
};

// Smallest progress along the sweep axis per unit of path a ray must make for a group to
// carry it.
constexpr double MinimumAlong = 1e-6;

// One task as the sweep deposits it.
struct Deposit
{
  size_t Source;
  bool Spot;
  int OtherAxis = -1, OtherSign = 1; // the other group of a two-group point or spot light
  double Whole = 1.0;                // (weight + other weight) / weight
  double Axis[3];                    // spot cone axis
  double CosCone;
  double Exponent;
  double Scaled[3]; // radiance x weight x sign x fixed-point scale
  bool Recorded = false;
  bool Carried = false; // this sweep (and its pair's other) carries every point's ray
  bool Uniform = false; // group and spot factors 1 at every pixel (PrepareDeposits)
};

inline RaySource SourceOf(const PropagationTask& task)
{
  RaySource r;
  const LightState& l = task.Light;
  r.Directional = l.Kind == LightKind::Directional;
  r.Inside = task.Inside;
  const auto d = l.Direction();
  for (int a = 0; a < 3; ++a)
  {
    r.Travel[a] = r.Directional ? d[a] : 0.0;
    r.Position[a] = r.Directional ? 0.0 : l.Position[a];
  }
  return r;
}

// Grey extinction at points Low to High along x of the volume's grid: point (i, j, k) at
// Values + (i - Low) Stride[0] + j Stride[1] + k Stride[2] (Layout).
struct ExtinctionSlab
{
  const PackedValue* Values = nullptr;
  FieldLayout Layout;
  int Low = 0, High = -1;

  // The whole volume's extinction (grey: one value a point).
  static ExtinctionSlab Entire(const ClassifiedVolume& volume)
  {
    ExtinctionSlab entire;
    entire.Values = volume.Properties.data();
    entire.Layout = FieldLayout(volume.Geometry, 1);
    entire.High = volume.Geometry.Dimensions[0] - 1;
    return entire;
  }
  // Whether it holds the points of a cell whose first point along x is i.
  bool HoldsCell(int i) const { return this->Low <= i && i + 1 <= this->High; }
  // The first value of a cell it holds.
  const PackedValue* Cell(const int index[3]) const
  {
    return this->Values + (this->Layout.Offset(index) - this->Low * this->Layout.Stride[0]);
  }
};

// One sweep over the illumination grid (N, Stride, Origin, Spacing, Bounds) along Axis
// toward Sign; light is attenuated through the full-resolution Volume, whose Empty blocks
// (when given) are skipped.
struct SweepContext
{
  const ClassifiedVolume& Volume;
  const EmptyBlocks* Empty;
  double SegmentStep; // longest midpoint step: the volume's smallest spacing
  int Axis, Sign, B, C;
  int N[3];
  long long Stride[3];
  double Origin[3], Spacing[3];
  double Bounds[6];
  // The layout of the units the sweep deposits into: point (i, j, k) of the grid at
  // 3 ((i, j, k) - UnitFirst) . UnitStride: the whole grid (Stride, UnitFirst 0), or the
  // rows of a band (SweepBand).
  long long UnitStride[3];
  int UnitFirst[3];
  // Whether rows of segments may share their samples' cells (RowSegments for directional
  // sources, DivergingRowSegments for point and spot sources); false integrates every segment
  // on its own.
  bool RowKernels;
  // Values of light per ray or pixel: 3 (RGB) with chromatic attenuation; else 1, as every
  // channel keeps the same transmittance.
  int Channels;
  // Sweeps along x with a directional source, row kernels and no chromatic attenuation: a
  // copy of the volume's extinction at the points along x the current chunk of slices
  // reaches, rows along y contiguous (SweepSlices::SlabFor and CopySlab), read by the grey
  // row kernel; none (Low > High) otherwise.
  ExtinctionSlab Slab;
  // A sweep over a wedge (PropagateSweepWedge): the material it holds (Volume then gives only
  // the grid and the classification's channels and scales), and per slice k the first row of
  // its units (UnitSliceFirst) and where they start (UnitSliceBase, in points). Null and
  // empty otherwise.
  const WedgeVolume* Wedge = nullptr;
  std::vector<int> UnitSliceFirst;
  std::vector<long long> UnitSliceBase;
};

// A ray source as one sweep uses it; for a directional light everything that does not
// depend on the point is worked out once.
//
// A directional light's rays are parallel, so they are followed exactly: a lattice of rays
// one cell apart crosses every slice, and a ray moves from one slice to the next by the
// same offset as every other. The lattice is the grid shifted by the fraction of the
// accumulated offset, so a ray's predecessor is a whole number of cells away and is read
// without interpolation. A grid point interpolates the previous slice's lattice once, where
// its own ray crosses it, and integrates its last step itself (RowFromLattice). Reading the
// previous slice's grid values by interpolation instead would blur a shadow edge a little
// at every slice.
struct SweepSource
{
  RaySource Source;
  bool Enters = false;  // directional: light does not progress along the axis
  double Step = 0.0;    // directional: path length between slices
  double OffsetU = 0.0; // directional: how far a ray moves from one slice to the next, in cells
  double OffsetV = 0.0;

  SweepSource(const RaySource& source, const SweepContext& s)
    : SweepSource(source, s.Axis, s.Sign, s.B, s.C, s.Spacing)
  {
  }
  // The source in a sweep along `axis` toward `sign` of a grid of `spacing`, its rows along
  // b, ordered along c.
  SweepSource(const RaySource& source, int axis, int sign, int b, int c, const double spacing[3])
    : Source(source)
  {
    if (!source.Directional)
    {
      return;
    }
    const double along = sign * source.Travel[axis];
    this->Enters = along <= MinimumAlong;
    if (!this->Enters)
    {
      this->Step = spacing[axis] / along;
      this->OffsetU = source.Travel[b] * this->Step / spacing[b];
      this->OffsetV = source.Travel[c] * this->Step / spacing[c];
    }
  }

  /// Whether the source's light is carried by a ray lattice (see above).
  bool FollowsRays() const { return this->Source.Directional && !this->Enters; }

  /// Point and spot sources: the slice (index along the axis) that anchors the rays
  /// followed, -1 while there is none, and the number of rays along each slice axis.
  int Anchor = -1;
  int RaysB = 0, RaysC = 0;
  /// Point and spot sources: where ray (0, 0) leaves an anchor slice, along B and C (the
  /// rays reach beyond the box on the light's side: RaysBeside).
  double RayOriginB = 0.0, RayOriginC = 0.0;
  /// Point and spot sources: the rows of rays the buffers (and Norms) hold, RayRows from
  /// RayFirst on: every row, or those of a band's cone at any anchor (ConeRows).
  int RayFirst = 0, RayRows = 0;
  /// Point and spot sources: each ray's distance from the light to its anchor point, which
  /// gives its direction at every slice until the anchor moves, so computed once per anchor
  /// (a square root a ray and slice cost more than a fifth of the ray's step): row j of rays
  /// holds those of anchor RowAnchor[j] (-1: none yet).
  std::vector<double> Norms;
  std::vector<int> RowAnchor;
  /// Point and spot sources swept over a wedge (SweepWedge): per slice k, the interval
  /// [ConeLow[k], ConeHigh[k]] along C of the rays the wedge needs there (ConeOfWedge);
  /// empty: every ray.
  std::vector<double> ConeLow, ConeHigh;
};

// How far from a face of the box (bounds) across axis a a point still counts as on it: the
// geometric tolerance of the box's extent.
inline double FaceTolerance(const double bounds[6], int a)
{
  return GeometricTolerance * (bounds[2 * a + 1] - bounds[2 * a] + 1.0);
}

// Most rays DivergingRowSegments takes at once.
constexpr int MaximumDivergingRays = 256;

// A point or spot light's rays diverge, so no lattice keeps them a whole number of cells
// apart. They are followed exactly from an anchor slice instead: rays leave the anchor
// AnchorSpread times closer together than its points, are attenuated slice by slice
// (AdvanceAnchoredRays), and the light reaching a point is interpolated from them where
// the point's own ray crosses the previous slice, then attenuated over its last step. Once
// the rays have spread to a cell apart, the anchor moves to the current slice (its rays
// take the light computed there the same way): the light is interpolated once per anchor
// instead of once per slice, and rays are never farther apart than the grid's points.
// Until a slice in front of the light anchors the rays, light is integrated all the way
// from the light (inside the box only). Measured on the fidelity scenes (material RMS of
// point and spot lights at scale 1 and 0.5): a spread of 1.25 leaves up to 11.9 %, 1.5 up
// to 10.0 % and 2 up to 9.7 %, at 1.6x, 2.2x and 4x the rays (re-anchoring at every
// slice on the grid's points, the former method, up to 20 %).
constexpr double AnchorSpread = 1.5;

// Axis coordinate of slice k of the sweep.
inline double SliceCoordinate(const SweepContext& s, int k)
{
  return s.Origin[s.Axis] + k * s.Spacing[s.Axis];
}

// What slice k does to a point or spot source's rays once its points are lit: nothing
// (InFront false: the slice is not in front of the light), anchor the rays there (Anchor:
// their light is computed from the rays reaching the previous slice) or attenuate the rays
// over the step to it (their position there is the anchor's scaled by Scale from the light).
struct AnchoredStep
{
  bool InFront = false;
  bool Anchor = false;
  double Scale = 1.0;

  AnchoredStep(const SweepContext& s, const SweepSource& sweep, int k)
  {
    const int a = s.Axis;
    const double light = sweep.Source.Position[a];
    const double from = s.Sign * (SliceCoordinate(s, k) - light);
    this->InFront = IsInFront(from, s.Spacing[a]);
    if (!this->InFront)
    {
      return;
    }
    this->Anchor = sweep.Anchor < 0 ||
      from >= AnchorSpread * s.Sign * (SliceCoordinate(s, sweep.Anchor) - light);
    if (!this->Anchor)
    {
      this->Scale = (SliceCoordinate(s, k) - light) / (SliceCoordinate(s, sweep.Anchor) - light);
    }
  }

  // Whether a slice `from` away from the light along the sweep (spacing apart) is in front
  // of it.
  static bool IsInFront(double from, double spacing) { return from > GeometricTolerance * spacing; }
};

// A group's sweep axis, direction, and the axes its rows run along (B) and are ordered
// along (C, SweepRowAxis). Rows run along x (B = x) in sweeps along y and z, so that their
// volume reads and deposits are contiguous; sweeps along x run their rows along y.
struct SweepAxes
{
  int Axis, Sign, B, C;
  explicit SweepAxes(int group)
    : Axis(group / 2)
    , Sign(group % 2 == 0 ? 1 : -1)
    , B(group / 2 == 0 ? 1 : 0)
    , C(group / 2 == 2 ? 1 : 2)
  {
  }
};

// The rows of a sweep one call runs: all, or a band's (SweepBand), whose units hold only its
// rows and whose ray lattices (its rows and the halo either side) get their neighbouring
// rows from `Exchange` after every slice.
struct SweepSpan
{
  bool Banded = false;
  SweepBand Band;
  LatticeExchange Exchange;
  // Or a wedge's (PropagateSweepWedge): per slice its own rows (WedgeRows), reading the
  // material it holds (WedgeMaterial).
  const SweepWedge* Wedge = nullptr;
  const WedgeVolume* WedgeMaterial = nullptr;
};

// Segments (SegmentTransmittance.cxx).

// The part [from, to] of the segment from p back along -d over `length` inside the box.
bool ClipToBox(const double bounds[6], const double p[3], const double d[3], double length,
  double& from, double& to);
// Transmittance (multiplied into out) of the segment from p back along -d over `length`.
void SegmentTransmittance(
  const SweepContext& s, const double p[3], const double d[3], double length, float* out);
// SegmentTransmittance for `count` parallel segments whose near ends lie `spacing` apart
// along the slice axis B (a directional source's rays).
void RowSegments(const SweepContext& s, const double p[3], double spacing, int count,
  const double d[3], double length, float* out);
// SegmentTransmittance for `count` rays of a point or spot source equally spaced along axis B.
void DivergingRowSegments(const SweepContext& s, const double* p, const double* d,
  const double* length, int count, float* out);

// A row of segments of a point or spot source's rays (LightRowTransmittance): ray i (from
// index 0 of its row) ends at Near + i StepB e_B, all at the same coordinates along the
// sweep axis and C, and runs back toward the light over the part Fraction of its way.
struct LightRow
{
  double Light[3];
  double Near[3];
  double StepB = 0.0;
  double Fraction = 0.0;

  // Near end of ray i.
  void NearEnd(int i, double p[3], int b) const
  {
    std::copy_n(this->Near, 3, p);
    p[b] += i * this->StepB;
  }
};

// SegmentTransmittance (one value a ray: no chromatic attenuation) of rays first to
// first + count - 1 of `row`, whose distances from the light are distance[0 .. count - 1].
void LightRowTransmittance(const SweepContext& s, const LightRow& row, int first, int count,
  const double* distance, float* out);

// Point and spot sources' rays (PointLightRays.cxx).

// The rows [first, last] of a point or spot source's rays from anchor slice k that a wedge
// computes.
void ConeRows(const SweepContext& s, const SweepSource& sweep, int k, int& first, int& last);
// Rows [begin, end) of a point or spot source's rays at slice k.
void AdvanceAnchoredRays(const SweepContext& s, SweepSource& sweep, const AnchoredStep& step, int k,
  int begin, int end, float* rays, float* next);
// Transmittance of a source that follows no ray lattice along row ic of slice k.
void RowTransmittance(const SweepContext& s, const SweepSource& sweep, const float* rays, int k,
  int ic, float* out, double* direction, double* groupFactor);

// Wedges (SweepWedges.cxx).

// The rows first[k] to last[k] along C of slice k of grid g that a wedge holds.
void WedgeRowsOf(const GridGeometry& g, const SweepAxes& axes, const double light[3],
  const SweepWedge& wedge, std::vector<int>& first, std::vector<int>& last);
// The rays of a point or spot source that a wedge needs, per slice an interval along C.
void ConeOfWedge(const GridGeometry& g, const SweepAxes& axes, const double light[3],
  const SweepWedge& wedge, std::vector<double>& low, std::vector<double>& high);

// A sweep's preparation (SweepSetup.cxx).

// The geometry of a sweep of the grid g in a group, and whether row kernels apply.
SweepContext MakeSweepContext(const ClassifiedVolume& volume, const EmptyBlocks* empty,
  bool rowKernels, const GridGeometry& g, int group);
// The distinct ray sources of the tasks and each task's deposit.
void PrepareDeposits(const SweepContext& s, const std::vector<PropagationTask>& tasks, double scale,
  std::vector<SweepSource>& prepared, std::vector<Deposit>& deposits);
// The read and write slice buffers of each source of a sweep; returns their bytes.
size_t AllocateSliceBuffers(const SweepContext& s, std::vector<SweepSource>& prepared,
  int latticeRows, std::vector<std::vector<float>>& read, std::vector<std::vector<float>>& write);

// The units a sweep over a band deposits into (SweepSpan::Band): the band's rows only, x
// fastest (PropagateSweepBand).
void SetBandUnits(const SweepBand& band, SweepContext& s);
// The units a sweep over a wedge deposits into (SweepSpan::Wedge): per slice the wedge's rows
// (WedgeRowsOf), and the material it reads (SweepSpan::WedgeMaterial).
void SetWedgeUnits(const GridGeometry& g, int group, const std::vector<PropagationTask>& tasks,
  const SweepSpan& span, SweepContext& s);

// The sweep (PropagationSweep.cxx).

// One sweep of the tasks (all in the same group) through the grid, or over the rows `span`
// gives; false when progress asked to stop.
bool Sweep(const ClassifiedVolume& volume, const EmptyBlocks* empty, bool rowKernels,
  const GridGeometry& g, int group, const std::vector<PropagationTask>& tasks,
  FixedPointIllumination& illumination, PropagationStatistics& statistics,
  const std::function<bool(double)>& progress, const SweepSpan& span = SweepSpan());
}
}

#endif
