/**
 * @file LightPropagationKernel.h
 * @brief Coherence-based light propagation into one fixed-point illumination volume
 * (sections 4-6 of the selective-light-updates paper).
 *
 * Method: E. Sundén and T. Ropinski, "Efficient Volume Illumination with Multiple Light Sources
 * through Selective Light Updates", IEEE Pacific Visualization Symposium (PacificVis), 2015:
 * coherence-based propagation of several lights per sweep (section 4), selective light updates
 * (section 5) and the propagation groups' weights (section 6, eq. 5a/5b).
 *
 * Light is swept slice by slice along one of six axis directions (a propagation group).
 * Every light of a group travels in the same sweep with its own pair of 2D slice buffers.
 * The light reaching a point of the illumination grid is read where the point's ray to the
 * light crosses the previous slice and attenuated over the segment between, integrated
 * through the full-resolution classification (midpoint rule, l_out = l_in prod
 * (1 - a (1 - c))). The buffers hold the light along rays followed exactly, not at the grid
 * points: reading grid values by interpolation at every slice would blur a shadow edge a
 * little at every slice (the numerical diffusion that dominated the error in material). A
 * directional light's parallel rays form a lattice that moves a whole number of cells
 * between slices, so it is never resampled (and where the illumination grid has the data's
 * resolution, the samples of a row of its segments share their cells' fractions: they are
 * found once per row); a point or spot light's diverging rays leave
 * an anchor slice 1.5 times denser than its points and are resampled onto a new anchor
 * when they have spread to a cell apart. The read is a bicubic (Catmull-Rom)
 * interpolation limited to the range of the four surrounding rays, so it creates neither
 * light nor negative values. Light is attenuated inside the box only, so light entering
 * through a side face is attenuated from where it entered. Each point adds weight x sign x
 * light to the illumination volume, so removing a light is propagating its old state with
 * sign -1, or subtracting the units its tasks added when they were recorded
 * (FixedPointIllumination::Recorded).
 *
 * Group weights (eq. 5a/5b): a light outside the volume travels in the groups of the two
 * axis directions closest to its main direction t (a directional light's direction, the
 * direction from a point or spot light to the volume centre). With |t_1| >= |t_2| >= |t_3|
 * the second group gets 2 beta / pi and the first 1 - 2 beta / pi, where
 * beta = atan2(|t_2| - |t_3|, |t_1| - |t_3|). For t in a plane of two axes this is exactly
 * eq. 5a/5b (beta is the angle to the closest face normal); in 3D it also makes the weights
 * continuous when the second and third axes swap (the second weight is 0 there) and when
 * the first and second swap (both are 1/2). A point or spot light may lie beyond the box
 * along the third axis only (just outside a face of a flat box, near an edge): the points on
 * the far side of the light along both the first and the second axis would be carried by
 * neither group, so the third axis's group, which carries every point, replaces the second,
 * weighted by 2 beta / pi with beta = atan2(|t_3|, |t_1|). A second weight below
 * MinimumSecondWeight is dropped, the first group taking the light whole, where that group
 * carries every point (a directional light, or a point or spot light beyond the box along
 * the first axis): such a sweep costs as much as the first for a few per cent of the light,
 * and far more where the light lies level with the second axis's slices, its rays grazing
 * them (a point light beyond the blunt fin's 128^3 level-0 grid along x, second weight
 * 0.03: 662 against 67 ns per point).
 * Where the groups change (a light moving across those thresholds or across a face's
 * plane) the illumination changes by the second weight times the difference between the
 * groups' estimates (their error, a few per cent), not continuously. A light inside
 * the volume travels away from itself in all six groups, a point p weighted by
 * d_a^2 for the group of its direction d = (p - light)/|p - light| along axis a.
 *
 * The illumination volume holds 32-bit fixed-point values (FixedPointIllumination), and
 * every light contribution is rounded before it is added. A light state always rounds to
 * the same integers, so subtracting it later cancels it exactly: selective updates cannot
 * drift, however many are made. Coherent and one-light-per-pass propagation give
 * bit-identical results for the same reason.
 */
#ifndef LightPropagationKernel_h
#define LightPropagationKernel_h

#include "IlluminationClassification.h"
#include "IlluminationLights.h"
#include "LargeArrays.h"
#include "RayMarchKernel.h"
#include "VolIllumKernelsModule.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace volillum
{

/// Group g sweeps along axis g / 2, toward + for even g and toward - for odd g.
constexpr int NumberOfPropagationGroups = 6;

struct GroupWeight
{
  int Group;
  double Weight;
};

/// Smallest weight eq. 5a/5b gives a second group that is kept (AssignPropagationGroups).
constexpr double MinimumSecondWeight = 0.05;

/// The groups a light propagates in with their weights; for a light inside the volume all
/// six groups with weight 1 (the per-point weights are applied during the sweep).
VOLILLUMKERNELS_EXPORT std::vector<GroupWeight> AssignPropagationGroups(
  const LightState& light, const double bounds[6]);

/// One light state to propagate in one group, added (Sign +1) or removed (Sign -1).
struct PropagationTask
{
  LightState Light;
  int Group = 0;
  double Weight = 1.0;
  int Sign = 1;
  bool Inside = false;
  /// A point or spot light outside the volume travels in two groups. Its rays diverge, so
  /// some points may lie where the light runs against one group's direction (that group
  /// cannot carry it there): at those points the other group carries the light's whole
  /// weight. OtherGroup is -1 when the light has one group or is directional.
  int OtherGroup = -1;
  double OtherWeight = 0.0;
  /// Whether the task's contribution is also added to FixedPointIllumination::Recorded.
  bool Recorded = false;
};

/// The tasks that add (sign +1) or remove (sign -1) a light state; none when it is off.
VOLILLUMKERNELS_EXPORT std::vector<PropagationTask> TasksForLight(
  const LightState& light, int sign, const double bounds[6]);

/// Number of sweeps the tasks need: distinct groups when coherent, tasks otherwise.
VOLILLUMKERNELS_EXPORT int CountSweeps(const std::vector<PropagationTask>& tasks, bool coherent);

/**
 * What the parts of an update cost, in nanoseconds per illumination point: a sweep's own
 * work, each light geometry it propagates (a directional one, a point or spot one: the
 * lights' rays), each task it deposits and each deposit into a record, and the fixed-point
 * illumination's bookkeeping (clearing it for a full update, a record started in memory
 * not yet touched or in a record's memory, a record subtracted). Measured by the kernel
 * alone on a 256^3 volume (2 threads; volillum-benchmark compares the estimates of
 * EstimatePropagationCost with the times of Table 1's updates): only their ratios matter.
 */
namespace PropagationCost
{
constexpr double Sweep = 2.0;
constexpr double DirectionalRays = 9.0;
constexpr double PointRays = 25.0;
constexpr double Deposit = 2.0;
constexpr double RecordedDeposit = 3.0;
constexpr double Clear = 1.0;
constexpr double NewRecord = 10.0;
constexpr double ReusedRecord = 1.0;
constexpr double SubtractRecord = 0.7;
}

/// Estimated cost of propagating the tasks (PropagationCost, nanoseconds per illumination
/// point): the sweeps PlanSweeps makes of them, each with its light geometries (lights of
/// the same geometry share their rays) and deposits.
VOLILLUMKERNELS_EXPORT double EstimatePropagationCost(
  const std::vector<PropagationTask>& tasks, bool coherent);

/**
 * RGB illumination in 32-bit fixed point: Scale units (a power of two) per unit of light.
 * Units are added modulo 2^32 and read back as signed: integer sums are exact in any order,
 * and a total reads back exactly while it stays below 2^31 units. Totals are bounded by the
 * summed radiance of the lights (transmittances, group weights and spot factors are at most
 * 1), so the scale is chosen from that bound with room for lights to brighten or dim
 * (ScaleFor); bounds the scale no longer suits (Holds) calls for a reset with a new scale.
 * Precision: 1 / Scale, between 2^-30 and 2^-20 of the bound.
 */
class VOLILLUMKERNELS_EXPORT FixedPointIllumination
{
public:
  /// Largest power of two with bound x Scale <= 2^28 (1 when there is no light).
  static double ScaleFor(double bound);
  /// Whether totals up to `largest` (per channel; any state an update may show) read back
  /// exactly, largest x Scale <= 2^30 (room for the rounding of every contribution), and
  /// the final ones, up to `final`, to at least 2^-20 of it: final x Scale >= 2^20.
  bool Holds(double largest, double final) const;

  void Reset(long long points, double scale)
  {
    this->Values.assign(3 * static_cast<size_t>(points), 0);
    this->Scale = scale;
  }
  long long NumberOfPoints() const { return static_cast<long long>(this->Values.size() / 3); }
  /// Convert to float RGB (3 floats a point).
  void ToFloat(float* rgb) const
  {
    ToFloat(this->Values.data(), this->Values.size(), this->Scale, rgb);
  }
  /// Convert `count` values in units of an illumination of this `scale` to float: value i
  /// from units[i x unitStride] to out[i x outStride].
  static void ToFloat(const std::uint32_t* units, size_t count, double scale, float* out,
    size_t unitStride = 1, size_t outStride = 1);

  /// Start a record (all 0, the layout of Values) for the tasks marked Recorded.
  void StartRecord() { this->Recorded.assign(this->Values.size(), 0); }
  /// Subtract the record from the totals: exactly what the recorded tasks added.
  void SubtractRecord();
  /// Release the record's memory.
  void DropRecord() { LargeVector<std::uint32_t>().swap(this->Recorded); }

  double Scale = 1.0;
  LargeVector<std::uint32_t> Values;
  /// The units the tasks marked Recorded added since StartRecord (empty when none is kept):
  /// one light's contribution, which a later change of that light removes by subtraction
  /// instead of propagating the light's old state again.
  LargeVector<std::uint32_t> Recorded;
};

struct PropagationStatistics
{
  int Sweeps = 0;             // sweeps done (by all processes of a SweepShare)
  long long LightSweeps = 0;  // sum over those sweeps of the tasks each carried
  size_t PeakBufferBytes = 0; // largest total of slice and row buffers alive at once
};

/**
 * The sweeps one of several processes runs (a parallel run: every process propagates the
 * same tasks into an illumination of its own, and the sums over the processes are the
 * illumination). The planned sweeps are shared out, the costliest first, each to the
 * process with the least estimated work so far (a sweep costs SweepCost directional tasks
 * besides its tasks, and a point or spot task counts as PointTaskCost directional ones);
 * every process computes the same assignment. Units are
 * added modulo 2^32, so the sums over the processes equal a single process's illumination
 * bit for bit, and so do the sums after any sequence of selective updates, whichever
 * process ran which sweep of which update.
 */
struct SweepShare
{
  int Process = 0;
  int Processes = 1;
  /// A point or spot task costs about 12 times a directional one (volillum-benchmark,
  /// engine at 256^3: 367 against 31 ns per voxel for the first light).
  static constexpr double PointTaskCost = 12.0;
  /// A sweep's own work (its slices, buffers and deposits) is about one directional task's
  /// (engine at 256^3, one thread: a sweep of 4 directional tasks took 1.05 s, one of 1
  /// task 0.45 s).
  static constexpr double SweepCost = 1.0;
};

/**
 * Propagate the tasks into the illumination on the grid `target`, attenuating light through
 * the full-resolution classification `volume`. Coherent: all tasks of a group share one
 * sweep; otherwise each task has a sweep of its own. Groups along the same axis run
 * consecutively. At most maxSweeps sweeps run (0: no limit); the tasks not done are
 * returned in remaining. Returns false when progress asked to stop (the illumination is
 * then partly updated). With `empty` (the volume's empty blocks), segments skip the samples
 * there (they are 0): the same result, faster where the volume is mostly empty. rowKernels
 * false integrates every segment on its own instead of the segments along a row of the
 * illumination grid at once (a directional light's rays; a point or spot light's steps from
 * the previous slice): the reference the row kernels are tested against, the same result up
 * to float rounding. With a share of several processes, only the planned sweeps assigned to
 * share.Process run here (remaining is the same on every process).
 */
VOLILLUMKERNELS_EXPORT bool PropagateTasks(const ClassifiedVolume& volume,
  const GridGeometry& target, const std::vector<PropagationTask>& tasks, bool coherent,
  int maxSweeps, FixedPointIllumination& illumination, std::vector<PropagationTask>& remaining,
  PropagationStatistics& statistics, const ProgressCallback& progress,
  const EmptyBlocks* empty = nullptr, bool rowKernels = true, const SweepShare& share = {});

/// The process (0 .. processes - 1) of each sweep, given each sweep's tasks (SweepShare).
VOLILLUMKERNELS_EXPORT std::vector<int> AssignSweeps(
  const std::vector<std::vector<PropagationTask>>& sweeps, int processes);

/**
 * The sweeps PropagateTasks plans for the tasks, in the order it runs them: per group in group
 * order, all of a group's tasks in one sweep when coherent, else one sweep a task; at most
 * maxSweeps (0: no limit), the tasks of the others in remaining.
 */
VOLILLUMKERNELS_EXPORT std::vector<std::vector<PropagationTask>> PlanSweeps(
  const std::vector<PropagationTask>& tasks, bool coherent, int maxSweeps,
  std::vector<PropagationTask>& remaining);

/**
 * Rows [First, Last] of the illumination grid along a sweep's row axis (SweepRowAxis), which
 * one process sweeps in a parallel run over bands (PropagateSweepBand): every slice of the
 * sweep, those rows of it.
 */
struct SweepBand
{
  int First = 0;
  int Last = -1;
  /// The lattice rows beyond its own that the band reads and the exchange fills either side:
  /// at least LatticeHalo of its sweep (0: that).
  int Halo = 0;
};

/// The axis along which a sweep of `group` orders its rows (the one across the rows, which
/// run along the other axis of its slices): z for sweeps along x and y, y for sweeps along z.
VOLILLUMKERNELS_EXPORT int SweepRowAxis(int group);

/// The rows of the ray lattices beyond its own that a band reads on either side at every
/// slice, for a sweep of the tasks (one group) over the illumination grid `target`: the rows
/// its rays move across between slices and those of a point's bicubic read.
VOLILLUMKERNELS_EXPORT int LatticeHalo(
  const GridGeometry& target, const std::vector<PropagationTask>& tasks);

/// The points [first, last] along the row axis (SweepRowAxis) of the data grid `data` whose
/// material a band of rows of `target` reads in a sweep of the tasks (one group, directional
/// lights): its rows' and lattice rows' segments back to the previous slice, which move fewer
/// rows across than the halo (LatticeHalo), and one more point either side.
VOLILLUMKERNELS_EXPORT void BandOfData(const GridGeometry& data, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepBand& band, int halo, int& first,
  int& last);

/// Fills, after every slice but the last, the rows of the ray lattices (one pointer per
/// lattice; rows of rowValues floats, row r at lattice + (r - firstRow) rowValues) that a
/// band reads and other bands compute (SweepBand::Halo rows either side of its own). A band's
/// lattices hold only its rows and those (from firstRow, clamped to the lattice).
using LatticeExchange =
  std::function<void(const std::vector<float*>& lattices, size_t rowValues, int firstRow)>;

/**
 * One sweep of the tasks (one group, directional lights: point and spot lights sweep over
 * wedges, PropagateSweepWedge) over the rows `band`: `volume` is a band of the data grid
 * holding, at full extent along the rows and the sweep's axis, the material its rows read
 * (BandOfData); `units` the fixed-point illumination of the band's points only (target's
 * points with the band's rows along the row axis, x fastest; Recorded as in PropagateTasks).
 * A band's own lattice rows are its points' rows (the last band's also the lattice's extra
 * row); its lattices hold those and band.Halo rows either side. Sweeping every band this way,
 * each band's neighbouring lattice rows filled by `exchange` from the bands that compute them,
 * deposits PropagateTasks's units of the sweep. `progress`, if given, is told the fraction of
 * the slices swept after each slice (a band's sweep runs to its end: the other bands wait on
 * it).
 */
VOLILLUMKERNELS_EXPORT void PropagateSweepBand(const ClassifiedVolume& volume,
  const GridGeometry& target, const std::vector<PropagationTask>& tasks, const SweepBand& band,
  FixedPointIllumination& units, const LatticeExchange& exchange, PropagationStatistics& statistics,
  const EmptyBlocks* empty = nullptr, const std::function<void(double)>& progress = nullptr);

/**
 * A wedge of a point or spot light's rays in a sweep (PropagateSweepWedge). A ray from the
 * light keeps its ratio u = (its coordinate along the row axis C - the light's) / (its
 * distance from the light along the sweep) along its whole way, and everything the sweep
 * computes for a point lies along the point's own ray back to the light, within the cone
 * margin of the rays around it. So the points of the slices in front of the light whose u
 * lies in [Low, High), with the rays and material within that margin, need nothing from
 * the rest of the sweep. The rows of the slices not in front of the light (no rays reach
 * them) are split evenly: the Index-th of Count parts.
 */
struct SweepWedge
{
  double Low = -std::numeric_limits<double>::infinity();
  double High = std::numeric_limits<double>::infinity();
  int Index = 0, Count = 1;
};

/**
 * A sweep's tasks (one group) by where their light comes from: the directional tasks in
 * `directional`, and a list of tasks per point or spot light position (the tasks of a
 * wedge sweep share a light).
 */
VOLILLUMKERNELS_EXPORT std::vector<std::vector<PropagationTask>> TasksByLight(
  const std::vector<PropagationTask>& sweep, std::vector<PropagationTask>& directional);

/// `count` wedges of the tasks' point or spot light (one group, one light) over the
/// illumination grid `target`, each with about as many of the points in front of the light.
VOLILLUMKERNELS_EXPORT std::vector<SweepWedge> SplitIntoWedges(
  const GridGeometry& target, const std::vector<PropagationTask>& tasks, int count);

/// Per slice k of `target` along the sweep's axis, the rows [first[k], last[k]] (along the
/// row axis, SweepRowAxis) of the wedge's points: the wedges of SplitIntoWedges split every
/// slice's rows between them.
VOLILLUMKERNELS_EXPORT void WedgeRows(const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepWedge& wedge, std::vector<int>& first,
  std::vector<int>& last);

/**
 * The material of a wedge's sweep: per slice of the data grid along the sweep's axis, the
 * rows along the row axis (SweepRowAxis) from First[a] on (every point along the slice's
 * other axis), held slice after slice in Volume.Properties (slice a from point Base[a] on,
 * its points in the data grid's order, up to Base[a + 1]). Volume.Geometry is the whole data
 * grid's.
 */
struct WedgeVolume
{
  ClassifiedVolume Volume;
  std::vector<int> First;
  std::vector<long long> Base;
};

/// The rows [first[a], last[a]] along the row axis of each slice a of the data grid `data`
/// (along the sweep's axis) that a wedge's sweep over `target` reads (WedgeVolume): the
/// wedge at the slice and its neighbours, widened by the cone margin as its rays spread
/// between anchors, and a cell.
VOLILLUMKERNELS_EXPORT void WedgeOfData(const GridGeometry& data, const GridGeometry& target,
  const std::vector<PropagationTask>& tasks, const SweepWedge& wedge, std::vector<int>& first,
  std::vector<int>& last);

/**
 * One sweep of the tasks (one group, one point or spot light: TasksByLight) over a wedge:
 * `volume` holds the material WedgeOfData gives; `units` the fixed-point illumination of
 * the wedge's points only (per slice k of `target` its rows WedgeRows gives, slice after
 * slice, the points of a slice in the grid's order; Recorded as in PropagateTasks). Sweeping
 * every wedge of SplitIntoWedges this way, each alone, deposits PropagateTasks's units of
 * the sweep. `empty`: the whole data grid's empty blocks, when given (as PropagateTasks).
 * `progress`, if given, is told the fraction of the slices swept.
 */
VOLILLUMKERNELS_EXPORT void PropagateSweepWedge(const WedgeVolume& volume,
  const GridGeometry& target, const std::vector<PropagationTask>& tasks, const SweepWedge& wedge,
  FixedPointIllumination& units, PropagationStatistics& statistics,
  const EmptyBlocks* empty = nullptr, const std::function<void(double)>& progress = nullptr);
}

#endif
