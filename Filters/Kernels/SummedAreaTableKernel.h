/**
 * @file SummedAreaTableKernel.h
 * @brief Light-aligned Cartesian summed-area tables (CSAT) for box-filtered optical depth
 * (section 4.2.1 of the low-pass filtered volumetric shadows paper).
 *
 * Method: M. Ament, F. Sadlo, C. Dachsbacher and D. Weiskopf, "Low-Pass Filtered Volumetric
 * Shadows", IEEE Transactions on Visualization and Computer Graphics 20(12), 2014: filtered optical
 * depth over a patch (eq. 12-13), Cartesian tables shared by orthodirectional lights (eq. 14-15),
 * spherical tables for point lights (eq. 16-24) and separable kernels (eq. 25).
 *
 * A CartesianSAT resamples the extinction of a classified volume onto a regular grid
 * whose axes are an orthonormal frame (one axis along a directional light) and which
 * covers the volume's rotated bounding box, then stores the running integral of
 * extinction x volume in double precision. The integral over any axis-aligned box of that
 * frame, with real-valued corners, is an inclusion-exclusion of eight trilinearly
 * interpolated table values; this is exact for the piecewise-constant cell field, so the
 * box-filtered optical depth of eq. 12-13 costs the same for every filter width. The six
 * directions of one frame share a table (eq. 14-15).
 */
#ifndef SummedAreaTableKernel_h
#define SummedAreaTableKernel_h

#include "IlluminationClassification.h"
#include "LargeArrays.h"
#include "VolIllumKernelsModule.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace volillum
{
class EmptyBlocks;
struct VolumePiece;

/// Orthonormal axes; a light shining along one of them (either sign) can use a table built
/// in this frame.
struct SatFrame
{
  std::array<std::array<double, 3>, 3> Axes;
};

/// A frame whose third axis is the given unit direction and whose other two are the data
/// axes made orthogonal to it (canonical, so lights along data axes get the data's frame).
VOLILLUMKERNELS_EXPORT SatFrame FrameForDirection(const double direction[3]);

/// Normalised weights of a Gaussian over `count` equal sub-intervals of [-1, 1] (standard
/// deviation 1/2, so the patch spans two standard deviations each way).
VOLILLUMKERNELS_EXPORT std::vector<double> GaussianWeights(int count);

/// The axis of the frame parallel to the unit direction (sign +1 or -1), or -1.
VOLILLUMKERNELS_EXPORT int AxisOfDirection(
  const SatFrame& frame, const double direction[3], int& sign);

/// Growth of the width from one box of a cone's stair (ConeSteps) to the next: the width a
/// box takes (the geometric mean of the cone's at its ends) is within sqrt(ConeStepRatio),
/// 5 %, of the cone's anywhere along the box.
constexpr double ConeStepRatio = 1.1;

/**
 * A cone of rays from a point toward a light of finite size as a stair of boxes, each
 * read from a summed-area table at one width (its optical depth over its own patch area),
 * the sum returned. Distances t run from `start` to `end` along the ray toward the light;
 * widthAt(t) is the cone's half-width there (increasing, 0 at t = 0) and distanceOf(w)
 * its inverse. Where the cone is narrower than `narrowest` (the shadow filter's patch) the
 * box keeps that width; once the cone is `widest` (it covers the whole table) one box
 * reaches the end. read(t0, t1, w) gives a box's optical depth. The number of boxes grows
 * with the logarithm of the cone's widening, not with its width.
 */
template <typename WidthAt, typename DistanceOf, typename Read>
double ConeSteps(double start, double end, double narrowest, double widest, const WidthAt& widthAt,
  const DistanceOf& distanceOf, const Read& read)
{
  double depth = 0.0;
  double t = start;
  if (widthAt(t) < narrowest)
  {
    const double t1 = std::min(distanceOf(narrowest), end);
    if (t1 > t)
    {
      depth += read(t, t1, narrowest);
      t = t1;
    }
  }
  while (t < end)
  {
    const double w0 = std::max(widthAt(t), narrowest);
    double t1 = end, w = w0;
    if (w0 < widest)
    {
      t1 = std::min(distanceOf(w0 * ConeStepRatio), end);
      w = std::sqrt(w0 * std::max(widthAt(t1), narrowest));
    }
    if (!(t1 > t))
    {
      t1 = end; // no progress left in the rounding: the rest in one box
    }
    depth += read(t, t1, w);
    t = t1;
  }
  return depth;
}

/**
 * Running integrals of per-cell values over a grid of N[0] x N[1] x N[2] cells, in double
 * precision, with the zero planes stored. Box integrals with real-valued corners (in cell
 * units) are inclusion-exclusions of eight trilinearly interpolated values, exact for
 * values constant in each cell.
 */
class VOLILLUMKERNELS_EXPORT RunningIntegralTable
{
public:
  /// Allocate the cells. A table rebuilt at the same size or smaller keeps its memory
  /// without filling it first: set every cell with SetCell, then call Integrate once.
  void Allocate(const std::array<int, 3>& n, int channels);
  void SetCell(int channel, long long i, long long j, long long k, double value)
  {
    this->At(channel, i + 1, j + 1, k + 1) = value;
  }
  void Integrate();

  /// The grid planes and weights through which a box integral depends on one axis: the
  /// running integral at a real coordinate is linear between its two neighbouring planes.
  /// Planes of weight 0 (an end on a plane) and the zero plane are left out.
  struct AxisTaps
  {
    long long Index[4];
    double Weight[4];
    int Count = 0;
    double A = std::numeric_limits<double>::quiet_NaN(); // the ends they are for (none yet)
    double B = std::numeric_limits<double>::quiet_NaN();
    int N = -1; // and the cells of their axis

    /// The taps of the ends a and b on an axis of n cells, unless they are already set.
    void Set(double a, double b, int n)
    {
      if (a != this->A || b != this->B || n != this->N)
      {
        this->Compute(a, b, n);
      }
    }

  private:
    void Compute(double a, double b, int n)
    {
      this->A = a;
      this->B = b;
      this->N = n;
      this->Count = 0;
      for (int end = 0; end < 2; ++end)
      {
        const double c = std::min(std::max(end ? b : a, 0.0), static_cast<double>(n));
        const long long i0 = std::min(static_cast<long long>(c), static_cast<long long>(n - 1));
        const double f = c - i0;
        const double sign = end ? 1.0 : -1.0;
        this->Add(i0, sign * (1.0 - f));
        this->Add(i0 + 1, sign * f);
      }
    }
    void Add(long long index, double weight)
    {
      if (weight != 0.0 && index != 0)
      {
        this->Index[this->Count] = index;
        this->Weight[this->Count++] = weight;
      }
    }
  };
  using BoxTaps = std::array<AxisTaps, 3>;

  /// Integral over the box [lo, hi] in cell units, clamped to the grid.
  double Box(int channel, const double lo[3], const double hi[3]) const;

  /// The same, keeping each axis's taps in taps: the next box with the same ends on an axis
  /// (boxes around a row of points along another axis) reuses them.
  double Box(int channel, const double lo[3], const double hi[3], BoxTaps& taps) const;

  /// The integral over the box whose ends on each axis are those of its taps (AxisTaps::Set
  /// with this table's number of cells on the axis).
  double Sum(int channel, const AxisTaps& x, const AxisTaps& y, const AxisTaps& z) const;

  /// Boxes whose ends on the two axes other than `axis` are those of taps: the table summed
  /// over those axes' taps into line, one value a plane of `axis` (N[axis] + 1 values).
  /// LineBox then gives each such box from at most four of them.
  void CollapseToLine(int channel, int axis, const BoxTaps& taps, double* line) const;

  /// The integral over a box whose ends on the collapsed axis are those of t.
  static double LineBox(const double* line, const AxisTaps& t)
  {
    double sum = 0.0;
    for (int i = 0; i < t.Count; ++i)
    {
      sum += t.Weight[i] * line[t.Index[i]];
    }
    return sum;
  }

  /// Running integral from the grid's first corner to (x, y, z) in cell units (clamped).
  double Cumulative(int channel, double x, double y, double z) const;

  const std::array<int, 3>& GetDimensions() const { return this->N; }
  int GetNumberOfChannels() const { return this->Channels; }
  size_t GetMemoryBytes() const { return this->Values.size() * sizeof(double); }

private:
  size_t Index(int channel, long long i, long long j, long long k) const
  {
    return static_cast<size_t>(
      ((k * (this->N[1] + 1) + j) * (this->N[0] + 1) + i) * this->Channels + channel);
  }
  double& At(int channel, long long i, long long j, long long k)
  {
    return this->Values[this->Index(channel, i, j, k)];
  }
  double At(int channel, long long i, long long j, long long k) const
  {
    return this->Values[this->Index(channel, i, j, k)];
  }

  std::array<int, 3> N{ { 0, 0, 0 } };
  int Channels = 1;
  LargeVector<double> Values; // written right after allocation (LargeArrays.h)
};

/// Where a table's cells lie among the whole grid's table's (a window of a piece's table):
/// its first cell and number of cells per axis, and the whole table's number of cells.
struct TableWindow
{
  std::array<int, 3> First{ { 0, 0, 0 } };
  std::array<int, 3> N{ { 0, 0, 0 } };
  std::array<int, 3> Whole{ { 0, 0, 0 } };
};

class VOLILLUMKERNELS_EXPORT CartesianSAT
{
public:
  /// The cells Build gives a table in the frame: the window of a piece (VolumePiece: Whole
  /// is the grid whose table it is part of; `margin`: see Build), or with none the whole
  /// table of `whole`; in wholeOrigin the whole table's first corner (frame coordinates).
  static TableWindow Layout(const GridGeometry& whole, const SatFrame& frame, double cellSize,
    const VolumePiece* piece, std::array<double, 3>& wholeOrigin, double margin = 0.0);

  /**
   * Resample the extinction (times the channel's absorption k_c when channels is 3) onto
   * cells of size cellSize in the frame, covering the data's bounds, and integrate. Cells
   * whose centre lies in one of the data's empty blocks (when given) are 0 without a sample.
   * With `piece`, data is a piece of a bigger grid (VolumePiece): the table is the window of
   * the whole grid's table (the same frame, origin and cells) that covers the piece's
   * cells, and only the centres in those cells are sampled (the others are 0). Where the
   * piece reaches a face of the grid, the window also covers the columns within `margin`
   * beyond it: a box of a point near the face may read columns that start outside the grid
   * and enter other pieces further on (AddCellsBeyond; LocalReach without the near segment
   * is enough, since a box starts inside the grid).
   */
  void Build(const ClassifiedVolume& data, const SatFrame& frame, double cellSize, int channels,
    const EmptyBlocks* empty = nullptr, const VolumePiece* piece = nullptr, double margin = 0.0);

  /// Coordinates of a world point in the table's frame, measured from its first corner.
  void ToFrame(const double p[3], double q[3]) const;

  /**
   * Distance from a point within which lie the centres of the cells where its shadow box
   * starts (FilteredOpticalDepth, the kernel's squares too) for tables of cells of size
   * cellSize, a patch of half-width halfWidth and a box that starts `near` toward the light
   * from the point (its near segment). A piece grown by this distance (and a spacing) holds
   * them for every point of the piece: see AddCellsBeyond.
   */
  static double LocalReach(double cellSize, double halfWidth, double near);

  /**
   * Tables of a distributed volume, each process's built over its piece grown by LocalReach
   * (Build with the grown piece: its window holds every cell whose centre the grown piece
   * takes, from its own data and its neighbours'). A shadow box of a point of the piece then
   * starts in the grown piece's cells on each of its columns along the light's axis, so the
   * window holds the box up to where the grown piece's cells end on each column, and beyond
   * that lie only cells of other pieces. This gives them: for each column along `axis` of
   * another process's window (`window`, Layout of `grown`, that process's grown piece), the
   * sum of the cells of this table whose centres lie in the cells of `own` (this process's
   * piece, whose cells the grown piece this table was built over holds) and beyond every
   * cell `grown` takes on the column, toward `sign`. Added into sums: Channels values a
   * column, columns of the window's axes other than `axis` in their order (the first
   * fastest). Summed over the processes, the other process's SetBeyond takes them.
   */
  void AddCellsBeyond(const VolumePiece& own, const VolumePiece& grown, const TableWindow& window,
    int axis, int sign, double* sums) const;

  /// The cells of the whole table beyond this window's grown piece toward `sign` along
  /// `axis`, summed per column (AddCellsBeyond summed over the processes): boxes toward that
  /// end read them as well. A new Build forgets them.
  void SetBeyond(int axis, int sign, const double* sums);

  /// Integral of extinction over the box [lo, hi] (frame coordinates, clamped to the table).
  double BoxIntegral(int channel, const double lo[3], const double hi[3]) const;

  /// Box-filtered optical depth toward a light along frame axis `axis` (direction sign)
  /// from the world point p: the integral over the cuboid of half-width halfWidth around p
  /// reaching to the table's end toward the light, divided by the patch area (eq. 13).
  double FilteredOpticalDepth(
    int channel, const double p[3], int axis, int sign, double halfWidth) const;

  /// FilteredOpticalDepth at `count` world points (3 values a point) into depth. Points
  /// along a row of the table's frame share the taps of the two other axes; when the row's
  /// first, middle and last boxes have the same ends on those axes and the row is long
  /// enough, the table is collapsed onto the row's axis once (into line, resized as needed)
  /// and every box with those ends reads at most four values instead of 64 (the same
  /// integral up to the rounding of the sums: a depth depends, by that rounding, on whether
  /// its row was collapsed, which depends on the row alone).
  void FilteredOpticalDepths(int channel, const double* points, int count, int axis, int sign,
    double halfWidth, double* depth, std::vector<double>& line) const;

  /**
   * FilteredOpticalDepth toward a light of finite size: the cuboid widens into a cone
   * (ConeSteps) whose half-width grows by `spread` per unit of distance from the point the
   * shadow ray starts at, `start` before p (its near segment), and is at least halfWidth.
   * With spread 0 it is FilteredOpticalDepth's cuboid. For whole tables: a window of a
   * piece's table (Build with a piece) would add its columns beyond the window at the
   * width of the cone's last box, not the serial stair's.
   */
  double ConeFilteredOpticalDepth(int channel, const double p[3], int axis, int sign,
    double halfWidth, double start, double spread) const;

  /// The same with a separable kernel: the patch is cut into weights.size()^2 equal
  /// squares, square (i, j) weighted by weights[i] x weights[j] (weights summing to 1),
  /// each square's cuboid read from the table (eq. 25).
  double KernelFilteredOpticalDepth(int channel, const double p[3], int axis, int sign,
    double halfWidth, const std::vector<double>& weights) const;

  /// Mean extinction of cell (i, j, k) for a channel.
  double CellExtinction(int channel, int i, int j, int k) const;

  const SatFrame& GetFrame() const { return this->Frame; }
  const TableWindow& GetWindow() const { return this->Cells; }
  double GetCellSize() const { return this->H; }
  const std::array<int, 3>& GetDimensions() const { return this->Table.GetDimensions(); }
  int GetNumberOfChannels() const { return this->Table.GetNumberOfChannels(); }
  size_t GetMemoryBytes() const { return this->Table.GetMemoryBytes(); }

private:
  /// The integral over the columns of a box (taps: those of its ends in this table; the
  /// axis's are not read) of the cells beyond the window toward sign along axis (SetBeyond;
  /// 0 without).
  double BeyondBox(
    int channel, int axis, int sign, const RunningIntegralTable::BoxTaps& taps) const;

  SatFrame Frame;
  std::array<double, 3> Origin{ { 0.0, 0.0, 0.0 } };      // of the window
  std::array<double, 3> WholeOrigin{ { 0.0, 0.0, 0.0 } }; // of the whole table
  TableWindow Cells;
  double H = 1.0;
  RunningIntegralTable Table;
  /// Per axis and sign (2 axis + (sign > 0)): running integrals of the columns' sums beyond
  /// the window, one cell along the axis (SetBeyond).
  std::array<RunningIntegralTable, 6> Beyond;
};

/**
 * Spherical summed-area table around a point light (eq. 16-24). Cells are laid out in
 * (u, v, r): two angles about the axis from the light toward the volume's centre, and the
 * distance from the light. A light outside the box that sees all of it in front uses the
 * angles of an equiangular cube-map face, u = atan(x / z) and v = atan(y / z) in the axis's
 * frame: nearly square cells of nearly equal solid angle over the rectangle of angles the box
 * covers. A light inside or beside the box uses azimuth and polar angle (phi, theta) over the
 * cone that holds the box (every direction from inside). Build takes whichever needs fewer
 * cells. Cells hold extinction x dr x solid angle (the volume element divided by r^2), so the
 * integral over the spherical pyramid from the light to a sample, divided by the pyramid's
 * solid angle, is the optical depth averaged over the shadow rays through a patch of constant
 * base area at the sample.
 */
class VOLILLUMKERNELS_EXPORT SphericalSAT
{
public:
  /// Angular cells of about cellSize at the volume's far side (finer in the face layout, which
  /// spends the cells the polar one would need), radial cells twice as long; all coarser when
  /// that would exceed maxCells cells (GetCellSize is then larger than cellSize). With
  /// `piece`, data is a piece of a bigger grid (VolumePiece): the table is laid out over the
  /// whole grid and holds the window of cells whose centres the piece takes (a centre beyond
  /// a face of the whole grid counts in the cell it clamps to, so every cell has one piece),
  /// each integrated whole: data must hold all their samples (half a radial cell,
  /// GetRadialCellLength, around the centres). The other cells are 0.
  void Build(const ClassifiedVolume& data, const double light[3], double cellSize, int channels,
    long long maxCells = 1LL << 25, const VolumePiece* piece = nullptr);

  /// The layout Build gives the table of a grid with these bounds, without its cells (for
  /// LocalReach and GetRadialCellLength before the data is at hand).
  void Plan(
    const double bounds[6], const double light[3], double cellSize, long long maxCells = 1LL << 25);

  /**
   * Distance from a point within which lie the centres of the cells where its shadow
   * pyramid ends (FilteredOpticalDepth with this halfWidth, after a near segment of length
   * `near`): those of its patch at its distance, widened to a cell. Tables of a distributed
   * volume work as CartesianSAT::AddCellsBeyond describes, in (u, v) columns along r toward
   * the light: a piece grown by this distance (and a spacing) holds those centres for every
   * point of the piece.
   */
  double LocalReach(double halfWidth, double near) const;

  /// For each (u, v) column of another process's window (`window`, built over the piece
  /// `other`), the sum of the cells of this table whose centres `own` takes (this process's
  /// piece, whose cells the piece this table was built over holds) and that lie between the
  /// light and every cell `other` takes on the column. Added into sums (Channels values a
  /// column, u fastest); summed over the processes, the other process's SetBeyond takes them.
  void AddCellsBeyond(const VolumePiece& own, const VolumePiece& other, const TableWindow& window,
    double* sums) const;

  /// The cells of the whole table between the light and this window's piece, summed per
  /// column (AddCellsBeyond summed over the processes): the pyramids read them as well. A new
  /// Build forgets them.
  void SetBeyond(const double* sums);

  /// Filtered optical depth from the light to p over a square patch of half-width
  /// halfWidth at p's distance, widened to one table cell where it is narrower.
  double FilteredOpticalDepth(int channel, const double p[3], double halfWidth) const;

  /**
   * FilteredOpticalDepth toward a light of finite size: the pyramid narrows toward the
   * light no more than a cone (ConeSteps) whose half-width grows by `spread` per unit of
   * distance from the point the shadow ray starts at, `start` farther from the light than p
   * (its near segment), and never narrower than half a cell. For whole tables, as
   * CartesianSAT::ConeFilteredOpticalDepth.
   */
  double ConeFilteredOpticalDepth(
    int channel, const double p[3], double halfWidth, double start, double spread) const;

  /// (u, v, r) of a world point.
  void ToSpherical(const double p[3], double s[3]) const;

  /// Whether the angles are azimuth and polar angle (else those of a cube-map face).
  bool IsPolar() const { return this->Polar; }
  const RunningIntegralTable& GetTable() const { return this->Table; }
  const std::array<double, 3>& GetLight() const { return this->Light; }
  double GetCellSize() const { return this->H; }
  double GetRadialCellLength() const { return this->DR; }
  const TableWindow& GetWindow() const { return this->Cells; }

private:
  /// The frame, the layout (polar or face) and the range of angles and radii that hold the
  /// box: rMax, and the angular extents at the far side of both layouts (polar: 2 pi sin theta
  /// and theta; face: the rectangle of face angles).
  void ChooseLayout(const double bounds[6], double& rMax, double polar[2], double square[2]);
  /// Integrate the window's cells along r with the midpoint rule (those whose centres the
  /// piece takes, when there is one), then the table.
  void FillCells(const ClassifiedVolume& data, const VolumePiece* piece);
  /// The run [first, last] of cells of whole column (i, j) whose centres the piece takes.
  void TakenRun(const VolumePiece& piece, int i, int j, int& first, int& last) const;
  /// World direction of the centres of whole column (i, j).
  void ColumnDirection(int i, int j, double direction[3]) const;
  /// World direction of the angles (u, v).
  void Direction(double u, double v, double direction[3]) const;
  /// Solid angle of the angle rectangle [u0, u1] x [v0, v1].
  double SolidAngle(double u0, double u1, double v0, double v1) const;
  /// Table integral over [u0, u1] x [v0, v1] x [r0, r1] (angles within the table's range;
  /// r0 at RMin or below: from the light, the cells beyond the window included).
  double Integral(
    int channel, double u0, double u1, double v0, double v1, double r0, double r1) const;
  /// Optical depth between distances r0 and r1 from the light, averaged over the patch of
  /// angular half-width w around the direction of the angles s (ToSpherical): the table's
  /// integral over the patch's angles divided by its solid angle.
  double PatchDepth(int channel, const double s[3], double w, double r0, double r1) const;

  std::array<double, 3> Light{ { 0.0, 0.0, 0.0 } };
  SatFrame Frame; // third axis: from the light toward the volume's centre
  bool Polar = true;
  double H = 1.0;
  double U0 = 0.0, U1 = 0.0, V0 = 0.0, V1 = 0.0; // the angles' range
  double RMin = 0.0;                             // cells start where the box begins
  double DU = 1.0, DV = 1.0, DR = 1.0;
  double RMax = 0.0;
  TableWindow Cells;
  RunningIntegralTable Table;
  RunningIntegralTable Beyond; // per column: the cells between the light and the window
};

}

#endif
