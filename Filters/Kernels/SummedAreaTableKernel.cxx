#include "SummedAreaTableKernel.h"

#include "RayMarchKernel.h"

#include "vtkMath.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

namespace
{
// Whether p is inside the bounds, give or take eps.
bool Inside(const double bounds[6], double eps, const double p[3])
{
  for (int a = 0; a < 3; ++a)
  {
    if (p[a] < bounds[2 * a] - eps || p[a] > bounds[2 * a + 1] + eps)
    {
      return false;
    }
  }
  return true;
}

// Sample the classified data at p, or return false when p is outside its bounds.
bool SampleInside(
  const ClassifiedVolume& data, const double bounds[6], double eps, const double p[3], float s[4])
{
  if (!Inside(bounds, eps, p))
  {
    return false;
  }
  data.Sample(p, s);
  return true;
}
}

SatFrame FrameForDirection(const double direction[3])
{
  SatFrame f;
  double w[3] = { direction[0], direction[1], direction[2] };
  vtkMath::Normalize(w);
  // Start from the data axis least aligned with w and make it orthogonal.
  int least = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (std::abs(w[a]) < std::abs(w[least]))
    {
      least = a;
    }
  }
  // Prefer the data axis order so that a light along a data axis gets the data axes.
  double u[3] = { 0.0, 0.0, 0.0 };
  u[least] = 1.0;
  const double d = vtkMath::Dot(u, w);
  for (int a = 0; a < 3; ++a)
  {
    u[a] -= d * w[a];
  }
  vtkMath::Normalize(u);
  double v[3];
  vtkMath::Cross(w, u, v);
  for (int a = 0; a < 3; ++a)
  {
    f.Axes[0][a] = u[a];
    f.Axes[1][a] = v[a];
    f.Axes[2][a] = w[a];
  }
  return f;
}

std::vector<double> GaussianWeights(int count)
{
  std::vector<double> weights(count);
  double total = 0.0;
  for (int i = 0; i < count; ++i)
  {
    const double x = -1.0 + (i + 0.5) * 2.0 / count; // centre of sub-interval i
    weights[i] = std::exp(-0.5 * (x / 0.5) * (x / 0.5));
    total += weights[i];
  }
  for (auto& w : weights)
  {
    w /= total;
  }
  return weights;
}

int AxisOfDirection(const SatFrame& frame, const double direction[3], int& sign)
{
  for (int a = 0; a < 3; ++a)
  {
    const double c = vtkMath::Dot(frame.Axes[a].data(), direction);
    if (std::abs(std::abs(c) - 1.0) < GeometricTolerance)
    {
      sign = c > 0.0 ? 1 : -1;
      return a;
    }
  }
  sign = 0;
  return -1;
}

void CartesianSAT::ToFrame(const double p[3], double q[3]) const
{
  for (int a = 0; a < 3; ++a)
  {
    q[a] = vtkMath::Dot(p, this->Frame.Axes[a].data()) - this->Origin[a];
  }
}

TableWindow CartesianSAT::Layout(const GridGeometry& g, const SatFrame& frame, double cellSize,
  const VolumePiece* piece, std::array<double, 3>& wholeOrigin, double margin)
{
  double bounds[6];
  g.GetBounds(bounds);
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (int corner = 0; corner < 8; ++corner)
  {
    const double p[3] = { bounds[corner & 1], bounds[2 + ((corner >> 1) & 1)],
      bounds[4 + ((corner >> 2) & 1)] };
    for (int a = 0; a < 3; ++a)
    {
      const double c = vtkMath::Dot(p, frame.Axes[a].data());
      lo[a] = std::min(lo[a], c);
      hi[a] = std::max(hi[a], c);
    }
  }
  TableWindow w;
  for (int a = 0; a < 3; ++a)
  {
    // One cell more than the box holds, centred on it: in a frame of the data's axes the
    // cell centres are the data points (every one, or every second or fourth), so a hard
    // shadow (a box one cell wide) at a point reads exactly the column through it.
    w.Whole[a] =
      1 + std::max(0, static_cast<int>(std::ceil((hi[a] - lo[a]) / cellSize - GeometricTolerance)));
    w.N[a] = w.Whole[a];
    wholeOrigin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * w.Whole[a] * cellSize;
  }
  if (!piece)
  {
    return w;
  }
  // The window: the cells whose centres may lie in the piece's cells (a cell's margin on
  // each side), and beyond the grid's faces that the piece reaches, those within `margin`.
  double wlo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double whi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (int corner = 0; corner < 8; ++corner)
  {
    double p[3];
    for (int a = 0; a < 3; ++a)
    {
      const bool high = (corner >> a) & 1;
      const int index = high ? piece->LastCell[a] + 1 : piece->FirstCell[a];
      const bool face = high ? index >= g.Dimensions[a] - 1 : index <= 0;
      const double outward = (high ? margin : -margin) * (g.Spacing[a] < 0.0 ? -1.0 : 1.0);
      p[a] = g.Origin[a] + index * g.Spacing[a] + (face ? outward : 0.0);
    }
    for (int a = 0; a < 3; ++a)
    {
      const double c = vtkMath::Dot(p, frame.Axes[a].data());
      wlo[a] = std::min(wlo[a], c);
      whi[a] = std::max(whi[a], c);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    const auto cellOf = [&](double c)
    { return std::min(std::max((c - wholeOrigin[a]) / cellSize, 0.0), w.Whole[a] - 1.0); };
    const int first = std::max(0, static_cast<int>(std::floor(cellOf(wlo[a]))) - 1);
    const int last = std::min(w.Whole[a] - 1, static_cast<int>(std::ceil(cellOf(whi[a]))) + 1);
    w.N[a] = last - first + 1;
    w.First[a] = first;
  }
  return w;
}

namespace
{
// Where the centres of a table's cells lie in the grid it covers. A centre is placed from
// the whole table's origin and its index there, so that every piece's window puts it at the
// same place, to the bit (a centre on a plane between pieces must fall in the same cell for
// all of them).
struct CellCentres
{
  CellCentres(const GridGeometry& grid, const SatFrame& frame,
    const std::array<double, 3>& wholeOrigin, double cellSize)
    : Grid(grid)
    , Frame(frame)
    , Origin(wholeOrigin)
    , H(cellSize)
  {
    grid.GetBounds(this->Bounds);
    this->Eps = GeometricTolerance * std::max(this->Bounds[1] - this->Bounds[0], 1.0);
  }

  // Frame coordinate of the centres of the whole table's cells of index i along frame axis b.
  double Coordinate(int b, long long i) const { return this->Origin[b] + (i + 0.5) * this->H; }

  // Data coordinate a of the centre whose frame coordinates' terms are tx, ty[a] and tz[a]
  // (Coordinate times the frame's axes).
  double Position(int a, double tx, const double* ty, const double* tz) const
  {
    return tx * this->Frame.Axes[0][a] + ty[a] + tz[a];
  }

  // The world position of the centre of the whole table's cell c.
  void Centre(const long long c[3], double p[3]) const
  {
    const double qy = this->Coordinate(1, c[1]), qz = this->Coordinate(2, c[2]);
    const double ty[3] = { qy * this->Frame.Axes[1][0], qy * this->Frame.Axes[1][1],
      qy * this->Frame.Axes[1][2] };
    const double tz[3] = { qz * this->Frame.Axes[2][0], qz * this->Frame.Axes[2][1],
      qz * this->Frame.Axes[2][2] };
    const double tx = this->Coordinate(0, c[0]);
    for (int a = 0; a < 3; ++a)
    {
      p[a] = this->Position(a, tx, ty, tz);
    }
  }

  // Along data axis a, the centre at data coordinate p: its cell along a, and whether it lies
  // inside the bounds (within Eps).
  bool Locate(int a, double p, TrilinearCell& cell) const
  {
    AxisCell(this->Grid.Dimensions[a], (p - this->Grid.Origin[a]) / this->Grid.Spacing[a],
      cell.Index[a], cell.Fraction[a]);
    return p >= this->Bounds[2 * a] - this->Eps && p <= this->Bounds[2 * a + 1] + this->Eps;
  }

  const GridGeometry& Grid;
  const SatFrame& Frame;
  const std::array<double, 3>& Origin;
  double H;
  double Bounds[6];
  double Eps;
};

// Whether a piece takes a point at data coordinate p along axis a of its whole grid: its
// cell along a (AxisCell, as the tables' cells find theirs) is one of the piece's and,
// strict, it lies inside the grid's bounds (within CellCentres' tolerance).
struct PieceTest
{
  PieceTest(const VolumePiece& piece, bool strict)
    : Piece(piece)
    , Strict(strict)
  {
    piece.Whole.GetBounds(this->Bounds);
    this->Eps = GeometricTolerance * std::max(this->Bounds[1] - this->Bounds[0], 1.0);
  }

  bool Along(int a, double p) const
  {
    const GridGeometry& g = this->Piece.Whole;
    int index;
    float fraction;
    AxisCell(g.Dimensions[a], (p - g.Origin[a]) / g.Spacing[a], index, fraction);
    return index >= this->Piece.FirstCell[a] && index <= this->Piece.LastCell[a] &&
      (!this->Strict ||
        (p >= this->Bounds[2 * a] - this->Eps && p <= this->Bounds[2 * a + 1] + this->Eps));
  }

  const VolumePiece& Piece;
  bool Strict;
  double Bounds[6];
  double Eps;
};

// The run [first, last] of the n cell centres along a line that a piece takes (first > last:
// none). centre(k, p) gives the world position of centre k, each coordinate monotone in k, or
// the same for all (constant). Every test is monotone along the line, so those centres form
// one run (by their cell alone, a centre beyond a face of the grid lies in the cell it clamps
// to, so the piece's cells at a face reach beyond it). The run is estimated from the straight
// line through the first and last centres (along an axis they span less than a cell of, by
// bisection) and settled with the tests.
template <typename Centre>
void TakenRun(
  const PieceTest& test, int n, const bool constant[3], Centre centre, int& first, int& last)
{
  const VolumePiece& piece = test.Piece;
  const GridGeometry& g = piece.Whole;
  // Whether the piece takes centre k along data axis `only` (all three: -1).
  auto takes = [&](long long k, int only)
  {
    double p[3];
    centre(k, p);
    for (int a = 0; a < 3; ++a)
    {
      if ((only < 0 || a == only) && !test.Along(a, p[a]))
      {
        return false;
      }
    }
    return true;
  };
  double t0 = 0.0, t1 = n - 1.0;
  double ends[2][3];
  centre(0, ends[0]);
  centre(n - 1, ends[1]);
  for (int a = 0; a < 3 && t0 <= t1; ++a)
  {
    // Grid coordinate along data axis a at the first and last centres.
    const double u0 = (ends[0][a] - g.Origin[a]) / g.Spacing[a];
    const double u1 = (ends[1][a] - g.Origin[a]) / g.Spacing[a];
    if (constant[a] || std::abs(u1 - u0) < 1.0)
    {
      // The centres span less than a cell along a, the piece at least one: it takes all of
      // them, none, or those on one side of a single change, found by bisection.
      const bool atFirst = takes(0, a), atLast = takes(n - 1, a);
      if (!atFirst && !atLast)
      {
        first = 0;
        last = -1;
        return;
      }
      if (atFirst != atLast)
      {
        long long in = atFirst ? 0 : n - 1, out = atFirst ? n - 1 : 0;
        while (std::abs(in - out) > 1)
        {
          const long long middle = (in + out) / 2;
          (takes(middle, a) ? in : out) = middle;
        }
        t0 = atFirst ? t0 : std::max(t0, static_cast<double>(in));
        t1 = atFirst ? std::min(t1, static_cast<double>(in)) : t1;
      }
      continue;
    }
    const bool lowFace = !test.Strict && piece.FirstCell[a] == 0;
    const bool highFace = !test.Strict && piece.LastCell[a] >= g.Dimensions[a] - 2;
    const double lo = lowFace ? -VTK_DOUBLE_MAX : piece.FirstCell[a];
    const double hi = highFace ? VTK_DOUBLE_MAX : piece.LastCell[a] + 1.0;
    const double slope = (u1 - u0) / (n - 1); // at least 1 / (n - 1)
    const double k0 = (lo - u0) / slope, k1 = (hi - u0) / slope;
    t0 = std::max(t0, std::min(k0, k1));
    t1 = std::min(t1, std::max(k0, k1));
  }
  t0 = std::min(t0, n + 1.0); // an estimate beside the line stays castable
  t1 = std::max(t1, -2.0);
  first = static_cast<int>(std::max(0.0, std::floor(std::max(t0, -1.0)) - 1.0));
  last = static_cast<int>(std::min(n - 1.0, std::ceil(std::min(t1, double(n))) + 1.0));
  while (first <= last && !takes(first, -1))
  {
    ++first;
  }
  if (first > last)
  {
    return;
  }
  while (first > 0 && takes(first - 1, -1))
  {
    --first;
  }
  while (!takes(last, -1))
  {
    --last;
  }
  while (last < n - 1 && takes(last + 1, -1))
  {
    ++last;
  }
}

// TakenRun along frame axis `axis` of a Cartesian table's column (the whole table's cell
// indices on the other axes; column[axis] is overwritten) of n cells.
void ColumnRun(const CellCentres& centres, const PieceTest& test, int axis, long long column[3],
  int n, int& first, int& last)
{
  bool constant[3];
  for (int a = 0; a < 3; ++a)
  {
    constant[a] = centres.Frame.Axes[axis][a] == 0.0;
  }
  TakenRun(
    test, n, constant,
    [&](long long k, double p[3])
    {
      column[axis] = k;
      centres.Centre(column, p);
    },
    first, last);
}
}

void CartesianSAT::Build(const ClassifiedVolume& data, const SatFrame& frame, double cellSize,
  int channels, const EmptyBlocks* empty, const VolumePiece* piece, double margin)
{
  this->Frame = frame;
  this->H = cellSize;
  // The grid whose bounds the table covers and in which samples find their cells.
  const GridGeometry& g = piece ? piece->Whole : data.Geometry;
  this->Cells = Layout(g, frame, cellSize, piece, this->WholeOrigin, margin);
  const std::array<int, 3>& n = this->Cells.N;
  const std::array<int, 3>& firstCell = this->Cells.First;
  for (int a = 0; a < 3; ++a)
  {
    this->Origin[a] = this->WholeOrigin[a] + firstCell[a] * cellSize;
  }
  for (auto& beyond : this->Beyond)
  {
    beyond = RunningIntegralTable();
  }
  this->Table.Allocate(n, channels);

  // Cell integrals: extinction at the cell centre (zero outside the data) times volume. The
  // centres of a row along the frame's first axis share the other axes' terms of their world
  // positions, and their cell along each data axis the row does not move along.
  const CellCentres centres(g, frame, this->WholeOrigin, cellSize);
  // The cells whose centres are sampled: the piece's, or all the grid's.
  VolumePiece taken;
  if (piece)
  {
    taken = *piece;
  }
  else
  {
    taken.Whole = g;
    for (int a = 0; a < 3; ++a)
    {
      taken.LastCell[a] = std::max(0, g.Dimensions[a] - 2);
    }
  }
  const PieceTest taking(taken, true);
  const double volume = cellSize * cellSize * cellSize;
  const PackedValue* field = data.Properties.data();
  const bool chromatic = channels == 3 && data.IsChromatic();
  const FieldLayout layout(data.Geometry, data.Channels);
  const long long dx = layout.Corner[0], dy = layout.Corner[1], dz = layout.Corner[2];
  vtkSMPTools::For(0, static_cast<long long>(n[2]),
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
      {
        for (long long j = 0; j < n[1]; ++j)
        {
          const double qy = centres.Coordinate(1, firstCell[1] + j);
          const double qz = centres.Coordinate(2, firstCell[2] + k);
          const double ty[3] = { qy * frame.Axes[1][0], qy * frame.Axes[1][1],
            qy * frame.Axes[1][2] };
          const double tz[3] = { qz * frame.Axes[2][0], qz * frame.Axes[2][1],
            qz * frame.Axes[2][2] };
          const double rowX = centres.Coordinate(0, firstCell[0]);
          // Only the centres the piece takes are sampled (a run along the row).
          long long begin = 0, end = n[0];
          {
            long long row[3] = { 0, firstCell[1] + j, firstCell[2] + k };
            int first, last;
            ColumnRun(centres, taking, 0, row, this->Cells.Whole[0], first, last);
            begin = std::min<long long>(n[0], std::max(0, first - firstCell[0]));
            end = std::max(begin, std::min<long long>(n[0], last + 1LL - firstCell[0]));
            for (long long i = 0; i < n[0]; ++i)
            {
              for (int c = 0; c < channels && (i < begin || i >= end); ++c)
              {
                this->Table.SetCell(c, i, j, k, 0.0);
              }
            }
          }
          TrilinearCell cell;
          bool rowInside = true;
          for (int a = 0; a < 3; ++a)
          {
            if (frame.Axes[0][a] == 0.0)
            {
              rowInside = centres.Locate(a, centres.Position(a, rowX, ty, tz), cell) && rowInside;
            }
          }
          for (long long i = begin; i < end; ++i)
          {
            bool inside = rowInside;
            for (int a = 0; a < 3; ++a)
            {
              if (frame.Axes[0][a] != 0.0)
              {
                const double tx = centres.Coordinate(0, firstCell[0] + i);
                inside = centres.Locate(a, centres.Position(a, tx, ty, tz), cell) && inside;
              }
            }
            TrilinearCell at = cell; // in data's grid
            inside = inside && (!piece || piece->Takes(at));
            if (!inside || (empty && empty->ContainsCell(at.Index)))
            {
              for (int c = 0; c < channels; ++c)
              {
                this->Table.SetCell(c, i, j, k, 0.0);
              }
              continue;
            }
            const PackedValue* q = field + layout.Offset(at.Index);
            const auto& f = at.Fraction;
            const double sigma =
              TrilinearInCellSkippingZeros(q, dx, dy, dz, f[0], f[1], f[2]) * data.Scale[0];
            for (int c = 0; c < channels; ++c)
            {
              const double absorb = chromatic
                ? TrilinearInCellSkippingZeros(q + 1 + c, dx, dy, dz, f[0], f[1], f[2]) *
                  static_cast<double>(data.Scale[1 + c])
                : 1.0;
              this->Table.SetCell(c, i, j, k, sigma * absorb * volume);
            }
          }
        }
      }
    });
  this->Table.Integrate();
}

double RunningIntegralTable::Cumulative(int channel, double x, double y, double z) const
{
  // Continuous running integral up to (x, y, z) in cell units: trilinear interpolation of
  // the corner values, exact for a field that is constant in each cell.
  const double c[3] = { std::min(std::max(x, 0.0), static_cast<double>(this->N[0])),
    std::min(std::max(y, 0.0), static_cast<double>(this->N[1])),
    std::min(std::max(z, 0.0), static_cast<double>(this->N[2])) };
  long long i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    i0[a] = std::min(static_cast<long long>(c[a]), static_cast<long long>(this->N[a] - 1));
    f[a] = c[a] - i0[a];
  }
  double result = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
    const double w = (di ? f[0] : 1.0 - f[0]) * (dj ? f[1] : 1.0 - f[1]) * (dk ? f[2] : 1.0 - f[2]);
    if (w != 0.0)
    {
      result += w * this->At(channel, i0[0] + di, i0[1] + dj, i0[2] + dk);
    }
  }
  return result;
}

double RunningIntegralTable::Box(int channel, const double a[3], const double b[3]) const
{
  BoxTaps taps;
  return this->Box(channel, a, b, taps);
}

double RunningIntegralTable::Box(
  int channel, const double a[3], const double b[3], BoxTaps& taps) const
{
  // The inclusion-exclusion of the eight corners' trilinear interpolations, gathered per
  // axis: at most 4 x 4 x 4 table values, fewer at the grid's ends.
  for (int axis = 0; axis < 3; ++axis)
  {
    taps[axis].Set(a[axis], b[axis], this->N[axis]);
  }
  return this->Sum(channel, taps[0], taps[1], taps[2]);
}

double RunningIntegralTable::Sum(
  int channel, const AxisTaps& x, const AxisTaps& y, const AxisTaps& z) const
{
  double sum = 0.0;
  for (int k = 0; k < z.Count; ++k)
  {
    for (int j = 0; j < y.Count; ++j)
    {
      const double* row = &this->Values[this->Index(channel, 0, y.Index[j], z.Index[k])];
      double line = 0.0;
      for (int i = 0; i < x.Count; ++i)
      {
        line += x.Weight[i] * row[x.Index[i] * this->Channels];
      }
      sum += y.Weight[j] * z.Weight[k] * line;
    }
  }
  return sum;
}

void RunningIntegralTable::CollapseToLine(
  int channel, int axis, const BoxTaps& taps, double* line) const
{
  const long long stride[3] = { this->Channels, (this->N[0] + 1LL) * this->Channels,
    (this->N[0] + 1LL) * (this->N[1] + 1LL) * this->Channels };
  const AxisTaps& u = taps[(axis + 1) % 3];
  const AxisTaps& v = taps[(axis + 2) % 3];
  const long long planes = this->N[axis] + 1LL;
  const long long step = stride[axis];
  std::fill_n(line, planes, 0.0);
  for (int a = 0; a < u.Count; ++a)
  {
    for (int b = 0; b < v.Count; ++b)
    {
      const double w = u.Weight[a] * v.Weight[b];
      const double* column = &this->Values[static_cast<size_t>(
        channel + u.Index[a] * stride[(axis + 1) % 3] + v.Index[b] * stride[(axis + 2) % 3])];
      if (step == 1) // a loop the compiler vectorises
      {
        for (long long m = 0; m < planes; ++m)
        {
          line[m] += w * column[m];
        }
        continue;
      }
      for (long long m = 0; m < planes; ++m)
      {
        line[m] += w * column[m * step];
      }
    }
  }
}

void RunningIntegralTable::Allocate(const std::array<int, 3>& n, int channels)
{
  this->N = n;
  this->Channels = channels;
  this->Values.resize(static_cast<size_t>(n[0] + 1) * (n[1] + 1) * (n[2] + 1) * channels);
  // The zero planes; SetCell writes everything else.
  const long long nx = n[0], ny = n[1], nz = n[2];
  vtkSMPTools::For(0, nz + 1,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
        for (long long j = 0; j <= ny; ++j)
          for (long long i = 0; i <= nx; i += (j == 0 || k == 0) ? 1 : nx + 1)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) = 0.0;
    });
}

void RunningIntegralTable::Integrate()
{
  const long long nx = this->N[0], ny = this->N[1], nz = this->N[2];
  const int channels = this->Channels;
  // Running sums along x, then y, then z.
  vtkSMPTools::For(1, nz + 1,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
        for (long long j = 1; j <= ny; ++j)
          for (long long i = 2; i <= nx; ++i)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) += this->At(c, i - 1, j, k);
    });
  vtkSMPTools::For(1, nz + 1,
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
        for (long long j = 2; j <= ny; ++j)
          for (long long i = 1; i <= nx; ++i)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) += this->At(c, i, j - 1, k);
    });
  vtkSMPTools::For(1, ny + 1,
    [&](long long j0, long long j1)
    {
      for (long long k = 2; k <= nz; ++k)
        for (long long j = j0; j < j1; ++j)
          for (long long i = 1; i <= nx; ++i)
            for (int c = 0; c < channels; ++c)
              this->At(c, i, j, k) += this->At(c, i, j, k - 1);
    });
}

double CartesianSAT::LocalReach(double cellSize, double halfWidth, double near)
{
  // The box's cells across the light reach half a cell beyond its side, and the cell where it
  // starts holds its start within half a cell.
  const double across = halfWidth + 0.5 * cellSize;
  const double along = near + 0.5 * cellSize;
  return std::sqrt(2.0 * across * across + along * along);
}

void CartesianSAT::AddCellsBeyond(const VolumePiece& own, const VolumePiece& grown,
  const TableWindow& window, int axis, int sign, double* sums) const
{
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const CellCentres centres(own.Whole, this->Frame, this->WholeOrigin, this->H);
  const PieceTest owned(own, true), other(grown, false);
  const int channels = this->Table.GetNumberOfChannels();
  const auto& mine = this->Cells;
  // The columns both windows have.
  const int u0 = std::max(window.First[u], mine.First[u]);
  const int u1 = std::min(window.First[u] + window.N[u], mine.First[u] + mine.N[u]);
  const int v0 = std::max(window.First[v], mine.First[v]);
  const int v1 = std::min(window.First[v] + window.N[v], mine.First[v] + mine.N[v]);
  vtkSMPTools::For(v0, std::max(v0, v1),
    [&](int begin, int end)
    {
      for (int cv = begin; cv < end; ++cv)
      {
        for (int cu = u0; cu < u1; ++cu)
        {
          long long column[3];
          column[u] = cu;
          column[v] = cv;
          int first, last;
          ColumnRun(centres, owned, axis, column, mine.Whole[axis], first, last);
          first = std::max(first, mine.First[axis]);
          last = std::min(last, mine.First[axis] + mine.N[axis] - 1);
          int grownFirst, grownLast;
          ColumnRun(centres, other, axis, column, mine.Whole[axis], grownFirst, grownLast);
          if (grownFirst <= grownLast)
          {
            first = sign > 0 ? std::max(first, grownLast + 1) : first;
            last = sign > 0 ? last : std::min(last, grownFirst - 1);
          }
          if (first > last)
          {
            continue;
          }
          double lo[3], hi[3];
          lo[u] = cu - mine.First[u];
          lo[v] = cv - mine.First[v];
          lo[axis] = first - mine.First[axis];
          hi[u] = lo[u] + 1.0;
          hi[v] = lo[v] + 1.0;
          hi[axis] = last + 1.0 - mine.First[axis];
          double* out = sums +
            (static_cast<long long>(cv - window.First[v]) * window.N[u] + (cu - window.First[u])) *
              channels;
          for (int c = 0; c < channels; ++c)
          {
            out[c] += this->Table.Box(c, lo, hi);
          }
        }
      }
    });
}

void CartesianSAT::SetBeyond(int axis, int sign, const double* sums)
{
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  std::array<int, 3> n = this->Cells.N;
  n[axis] = 1;
  const int channels = this->Table.GetNumberOfChannels();
  RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  beyond.Allocate(n, channels);
  long long cell[3] = { 0, 0, 0 };
  for (cell[v] = 0; cell[v] < n[v]; ++cell[v])
  {
    for (cell[u] = 0; cell[u] < n[u]; ++cell[u])
    {
      const double* in = sums + (cell[v] * n[u] + cell[u]) * channels;
      for (int c = 0; c < channels; ++c)
      {
        beyond.SetCell(c, cell[0], cell[1], cell[2], in[c]);
      }
    }
  }
  beyond.Integrate();
}

double CartesianSAT::BeyondBox(
  int channel, int axis, int sign, const RunningIntegralTable::BoxTaps& taps) const
{
  const RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  if (beyond.GetDimensions()[axis] == 0)
  {
    return 0.0;
  }
  // The one cell along the axis, whole.
  static const RunningIntegralTable::AxisTaps whole = []
  {
    RunningIntegralTable::AxisTaps t;
    t.Set(0.0, 1.0, 1);
    return t;
  }();
  return beyond.Sum(
    channel, axis == 0 ? whole : taps[0], axis == 1 ? whole : taps[1], axis == 2 ? whole : taps[2]);
}

double CartesianSAT::BoxIntegral(int channel, const double lo[3], const double hi[3]) const
{
  const double a[3] = { lo[0] / this->H, lo[1] / this->H, lo[2] / this->H };
  const double b[3] = { hi[0] / this->H, hi[1] / this->H, hi[2] / this->H };
  return this->Table.Box(channel, a, b);
}

double CartesianSAT::FilteredOpticalDepth(
  int channel, const double p[3], int axis, int sign, double halfWidth) const
{
  double depth;
  std::vector<double> unused;
  this->FilteredOpticalDepths(channel, p, 1, axis, sign, halfWidth, &depth, unused);
  return depth;
}

void CartesianSAT::FilteredOpticalDepths(int channel, const double* points, int count, int axis,
  int sign, double halfWidth, double* depth, std::vector<double>& line) const
{
  const double end = this->Table.GetDimensions()[axis] * this->H;
  const double area = 4.0 * halfWidth * halfWidth;
  const double perCell = 1.0 / this->H;
  // The box of point i in cell units.
  auto box = [&](int i, double lo[3], double hi[3])
  {
    double q[3];
    this->ToFrame(points + 3 * i, q);
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = q[a] - halfWidth;
      hi[a] = q[a] + halfWidth;
    }
    lo[axis] = sign > 0 ? q[axis] : 0.0;
    hi[axis] = sign > 0 ? end : q[axis];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] *= perCell;
      hi[a] *= perCell;
    }
  };
  // The row's axis (along), when its first, middle and last boxes differ on that axis only,
  // and the ends the others share (key). Collapsing costs up to 16 reads a plane of the axis,
  // a box read from the table up to 64.
  int along = -1;
  double keyLo[3], keyHi[3];
  const auto& n = this->Table.GetDimensions();
  if (count > 1)
  {
    double lo[2][3], hi[2][3];
    box(0, lo[0], hi[0]);
    box(count - 1, lo[1], hi[1]);
    box(count / 2, keyLo, keyHi);
    int differing = 0;
    for (int a = 0; a < 3; ++a)
    {
      bool same = true;
      for (int e = 0; e < 2; ++e)
      {
        same = same && lo[e][a] == keyLo[a] && hi[e][a] == keyHi[a];
      }
      if (!same)
      {
        along = a;
        ++differing;
      }
    }
    along = differing == 1 && 3LL * count > n[along] ? along : -1;
  }
  RunningIntegralTable::BoxTaps taps;
  // The key's columns beyond the window (SetBeyond): a sum when the row runs along the
  // light's axis, else collapsed onto the row's axis (beyondLine).
  const RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  double keyBeyond = 0.0;
  bool beyondLine = false;
  if (along >= 0)
  {
    RunningIntegralTable::BoxTaps keyTaps;
    for (int a = 0; a < 3; ++a)
    {
      keyTaps[a].Set(keyLo[a], keyHi[a], n[a]);
    }
    line.resize(2 * (n[along] + 1LL));
    this->Table.CollapseToLine(channel, along, keyTaps, line.data());
    if (along == axis)
    {
      keyBeyond = this->BeyondBox(channel, axis, sign, keyTaps);
    }
    else if (beyond.GetDimensions()[axis] > 0)
    {
      // The columns beyond, collapsed onto the row's axis too (after the table's line).
      keyTaps[axis].Set(0.0, 1.0, 1);
      beyond.CollapseToLine(channel, along, keyTaps, line.data() + n[along] + 1);
      beyondLine = true;
    }
  }
  for (int i = 0; i < count; ++i)
  {
    double lo[3], hi[3];
    box(i, lo, hi);
    // A box beside the table (a window of a piece's table, CartesianSAT::Build) holds nothing.
    if ((hi[0] <= 0.0 || lo[0] >= n[0]) || (hi[1] <= 0.0 || lo[1] >= n[1]) ||
      (hi[2] <= 0.0 || lo[2] >= n[2]))
    {
      depth[i] = 0.0;
      continue;
    }
    const int u = (along + 1) % 3, v = (along + 2) % 3;
    if (along >= 0 && lo[u] == keyLo[u] && hi[u] == keyHi[u] && lo[v] == keyLo[v] &&
      hi[v] == keyHi[v])
    {
      taps[along].Set(lo[along], hi[along], n[along]);
      const double far = beyondLine
        ? RunningIntegralTable::LineBox(line.data() + n[along] + 1, taps[along])
        : keyBeyond;
      depth[i] = (RunningIntegralTable::LineBox(line.data(), taps[along]) + far) / area;
      continue;
    }
    const double inWindow = this->Table.Box(channel, lo, hi, taps);
    depth[i] = (inWindow + this->BeyondBox(channel, axis, sign, taps)) / area;
  }
}

double CartesianSAT::KernelFilteredOpticalDepth(int channel, const double p[3], int axis, int sign,
  double halfWidth, const std::vector<double>& weights) const
{
  const int count = static_cast<int>(weights.size());
  double q[3];
  this->ToFrame(p, q);
  const int a1 = (axis + 1) % 3;
  const int a2 = (axis + 2) % 3;
  const double side = 2.0 * halfWidth / count;
  const double ends[2] = { (sign > 0 ? q[axis] : 0.0) / this->H,
    (sign > 0 ? this->Table.GetDimensions()[axis] * this->H : q[axis]) / this->H };
  // Running integrals at the corners of the count x count squares, at both ends of the
  // cuboids: neighbouring squares share them (eq. 25 with 2 (count+1)^2 table reads); and
  // those of the columns beyond the window (SetBeyond), one cell along the axis.
  const RunningIntegralTable& beyond = this->Beyond[2 * axis + (sign > 0 ? 1 : 0)];
  const int levels = beyond.GetDimensions()[axis] > 0 ? 3 : 2;
  std::vector<double> corner(levels * (count + 1) * (count + 1));
  for (int e = 0; e < levels; ++e)
  {
    for (int i = 0; i <= count; ++i)
    {
      for (int j = 0; j <= count; ++j)
      {
        double c[3];
        c[axis] = e < 2 ? ends[e] : 1.0;
        c[a1] = (q[a1] - halfWidth + i * side) / this->H;
        c[a2] = (q[a2] - halfWidth + j * side) / this->H;
        corner[(e * (count + 1) + i) * (count + 1) + j] =
          (e < 2 ? this->Table : beyond).Cumulative(channel, c[0], c[1], c[2]);
      }
    }
  }
  auto at = [&](int e, int i, int j) { return corner[(e * (count + 1) + i) * (count + 1) + j]; };
  double depth = 0.0;
  for (int i = 0; i < count; ++i)
  {
    for (int j = 0; j < count; ++j)
    {
      double square = 0.0;
      for (int e = 0; e < levels; ++e)
      {
        const double face = at(e, i + 1, j + 1) - at(e, i, j + 1) - at(e, i + 1, j) + at(e, i, j);
        square += e == 0 ? -face : face;
      }
      depth += weights[i] * weights[j] * square / (side * side);
    }
  }
  return depth;
}

double CartesianSAT::CellExtinction(int channel, int i, int j, int k) const
{
  const double lo[3] = { i * this->H, j * this->H, k * this->H };
  const double hi[3] = { lo[0] + this->H, lo[1] + this->H, lo[2] + this->H };
  return this->BoxIntegral(channel, lo, hi) / (this->H * this->H * this->H);
}

namespace
{
// Coordinates of p - light along the frame's axes.
void LightCoordinates(
  const SatFrame& frame, const std::array<double, 3>& light, const double p[3], double q[3])
{
  const double d[3] = { p[0] - light[0], p[1] - light[1], p[2] - light[2] };
  for (int a = 0; a < 3; ++a)
  {
    q[a] = vtkMath::Dot(d, frame.Axes[a].data());
  }
}

// Signed solid angle of the rectangle [0, x] x [0, y] of the plane z = 1 seen from the origin.
double PlaneRectangleSolidAngle(double x, double y)
{
  return std::atan(x * y / std::sqrt(1.0 + x * x + y * y));
}

// Radial cells are this many angular cells long: a shadow ray's near end is integrated
// through the data (vtkFilteredVolumetricShadows), so the table mostly serves the far part,
// where the angular resolution matters most. Measured (material RMS, point and spot lights,
// tables at scale 1, capped at 2^25 cells): aneurism 4.56 / 5.01 % with 1, 3.43 / 3.92 % with
// 2; chest CT 4.93 / 3.85 % with 1, 4.28 / 3.34 % with 2.
constexpr double RadialCellLength = 2.0;

// Cube-map face angles stay this far inside +-pi/2 (their tangents stay finite).
constexpr double FaceAngleLimit = 0.5 * 3.14159265358979323846 * (1.0 - GeometricTolerance);
}

void SphericalSAT::ToSpherical(const double p[3], double s[3]) const
{
  double q[3];
  LightCoordinates(this->Frame, this->Light, p, q);
  s[2] = vtkMath::Norm(q);
  if (this->Polar)
  {
    s[0] = std::atan2(q[1], q[0]);
    s[1] = std::atan2(std::sqrt(q[0] * q[0] + q[1] * q[1]), q[2]);
  }
  else
  {
    s[0] = std::atan2(q[0], q[2]);
    s[1] = std::atan2(q[1], q[2]);
  }
}

void SphericalSAT::Direction(double u, double v, double direction[3]) const
{
  double local[3] = { std::tan(u), std::tan(v), 1.0 };
  if (this->Polar)
  {
    local[0] = std::sin(v) * std::cos(u);
    local[1] = std::sin(v) * std::sin(u);
    local[2] = std::cos(v);
  }
  else
  {
    vtkMath::Normalize(local);
  }
  for (int a = 0; a < 3; ++a)
  {
    direction[a] = local[0] * this->Frame.Axes[0][a] + local[1] * this->Frame.Axes[1][a] +
      local[2] * this->Frame.Axes[2][a];
  }
}

double SphericalSAT::SolidAngle(double u0, double u1, double v0, double v1) const
{
  if (this->Polar)
  {
    return (std::cos(v0) - std::cos(v1)) * (u1 - u0);
  }
  const double x0 = std::tan(u0), x1 = std::tan(u1), y0 = std::tan(v0), y1 = std::tan(v1);
  return PlaneRectangleSolidAngle(x1, y1) - PlaneRectangleSolidAngle(x0, y1) -
    PlaneRectangleSolidAngle(x1, y0) + PlaneRectangleSolidAngle(x0, y0);
}

void SphericalSAT::Plan(
  const double bounds[6], const double light[3], double cellSize, long long maxCells)
{
  std::copy(light, light + 3, this->Light.begin());
  double toCentre[3];
  for (int a = 0; a < 3; ++a)
  {
    toCentre[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]) - light[a];
  }
  if (vtkMath::Norm(toCentre) < 1e-12)
  {
    toCentre[0] = toCentre[1] = 0.0;
    toCentre[2] = 1.0;
  }
  vtkMath::Normalize(toCentre);
  this->Frame = FrameForDirection(toCentre);
  double rMax = 0.0, polar[2], square[2];
  this->ChooseLayout(bounds, rMax, polar, square);
  // The face layout spends the cells the polar one would need, on finer cells.
  const double* angles = this->Polar ? polar : square;
  const double h =
    this->Polar ? cellSize : cellSize * std::cbrt(square[0] * square[1] / (polar[0] * polar[1]));
  double counts[3] = { angles[0] * rMax / h, angles[1] * rMax / h,
    (rMax - this->RMin) / (RadialCellLength * h) };
  const double total =
    std::max(counts[0], 1.0) * std::max(counts[1], 1.0) * std::max(counts[2], 1.0);
  const double shrink = total > maxCells ? std::cbrt(maxCells / total) : 1.0;
  std::array<int, 3> n;
  for (int a = 0; a < 3; ++a)
  {
    n[a] = std::max(1, static_cast<int>(std::ceil(counts[a] * shrink)));
  }
  this->H = h / shrink;
  this->DU = (this->U1 - this->U0) / n[0];
  this->DV = (this->V1 - this->V0) / n[1];
  this->DR = (rMax - this->RMin) / n[2];
  this->RMax = rMax;
  this->Cells = TableWindow();
  this->Cells.N = n;
  this->Cells.Whole = n;
}

void SphericalSAT::Build(const ClassifiedVolume& data, const double light[3], double cellSize,
  int channels, long long maxCells, const VolumePiece* piece)
{
  double bounds[6];
  (piece ? piece->Whole : data.Geometry).GetBounds(bounds);
  this->Plan(bounds, light, cellSize, maxCells);
  this->Beyond = RunningIntegralTable();
  if (piece)
  {
    // The window: the columns and radii of the centres the piece takes (one cell at the
    // table's corner when it takes none).
    const auto& whole = this->Cells.Whole;
    int lo[3] = { whole[0], whole[1], whole[2] }, hi[3] = { -1, -1, -1 };
    for (int j = 0; j < whole[1]; ++j)
    {
      for (int i = 0; i < whole[0]; ++i)
      {
        int first, last;
        this->TakenRun(*piece, i, j, first, last);
        if (first <= last)
        {
          const int cell[3] = { i, j, 0 };
          for (int a = 0; a < 2; ++a)
          {
            lo[a] = std::min(lo[a], cell[a]);
            hi[a] = std::max(hi[a], cell[a]);
          }
          lo[2] = std::min(lo[2], first);
          hi[2] = std::max(hi[2], last);
        }
      }
    }
    for (int a = 0; a < 3; ++a)
    {
      this->Cells.First[a] = hi[a] < 0 ? 0 : lo[a];
      this->Cells.N[a] = hi[a] < 0 ? 1 : hi[a] - lo[a] + 1;
    }
  }
  this->Table.Allocate(this->Cells.N, channels);
  this->FillCells(data, piece);
}

void SphericalSAT::ColumnDirection(int i, int j, double direction[3]) const
{
  const double u0 = this->U0 + i * this->DU;
  const double v0 = this->V0 + j * this->DV;
  this->Direction(u0 + 0.5 * this->DU, v0 + 0.5 * this->DV, direction);
}

void SphericalSAT::TakenRun(const VolumePiece& piece, int i, int j, int& first, int& last) const
{
  double direction[3];
  this->ColumnDirection(i, j, direction);
  const bool constant[3] = { direction[0] == 0.0, direction[1] == 0.0, direction[2] == 0.0 };
  const PieceTest test(piece, false);
  volillum::TakenRun(
    test, this->Cells.Whole[2], constant,
    [&](long long k, double p[3])
    {
      const double r = this->RMin + (k + 0.5) * this->DR;
      for (int a = 0; a < 3; ++a)
      {
        p[a] = this->Light[a] + r * direction[a];
      }
    },
    first, last);
}

double SphericalSAT::LocalReach(double halfWidth, double near) const
{
  // The pyramid of a point at distance r from the light ends in the cells of its patch's
  // columns there: their centres lie within half a radial cell of r, and along the patch's
  // angles within its half-angle (halfWidth / r, widened to half a cell; a half-turn at
  // most) and half a cell more. A cell's world angle is at most its angular size (times the
  // stretch of a face's corner).
  double stretch = 1.0;
  if (!this->Polar)
  {
    const double largest = std::max(std::max(std::abs(this->U0), std::abs(this->U1)),
      std::max(std::abs(this->V0), std::abs(this->V1)));
    stretch = 1.0 / std::cos(largest);
  }
  const double cell = std::max(this->DU, this->DV) * stretch;
  double reach = 0.0;
  for (int step = 0; step <= 256; ++step)
  {
    const double r =
      std::max(this->RMin + (this->RMax - this->RMin) * step / 256.0, 1e-9 * this->RMax);
    // Twice the half-angle per axis bounds the patch's corners (its two angles need not be
    // orthogonal: a polar patch's far ring is wider than its middle near the pole).
    const double angle =
      std::min(vtkMath::Pi(), 2.0 * (std::max(halfWidth / r, 0.5 * cell) + 0.5 * cell));
    reach = std::max(reach, 0.5 * this->DR + (r + 0.5 * this->DR) * angle);
  }
  return near + reach;
}

void SphericalSAT::AddCellsBeyond(
  const VolumePiece& own, const VolumePiece& other, const TableWindow& window, double* sums) const
{
  const int channels = this->Table.GetNumberOfChannels();
  const auto& mine = this->Cells;
  // The columns both windows have.
  const int i0 = std::max(window.First[0], mine.First[0]);
  const int i1 = std::min(window.First[0] + window.N[0], mine.First[0] + mine.N[0]);
  const int j0 = std::max(window.First[1], mine.First[1]);
  const int j1 = std::min(window.First[1] + window.N[1], mine.First[1] + mine.N[1]);
  vtkSMPTools::For(j0, std::max(j0, j1),
    [&](int begin, int end)
    {
      for (int j = begin; j < end; ++j)
      {
        for (int i = i0; i < i1; ++i)
        {
          int first, last, otherFirst, otherLast;
          this->TakenRun(own, i, j, first, last);
          first = std::max(first, mine.First[2]);
          last = std::min(last, mine.First[2] + mine.N[2] - 1);
          this->TakenRun(other, i, j, otherFirst, otherLast);
          if (otherFirst <= otherLast)
          {
            last = std::min(last, otherFirst - 1);
          }
          if (first > last)
          {
            continue;
          }
          const double lo[3] = { static_cast<double>(i - mine.First[0]),
            static_cast<double>(j - mine.First[1]), static_cast<double>(first - mine.First[2]) };
          const double hi[3] = { lo[0] + 1.0, lo[1] + 1.0, last + 1.0 - mine.First[2] };
          double* out = sums +
            (static_cast<long long>(j - window.First[1]) * window.N[0] + (i - window.First[0])) *
              channels;
          for (int c = 0; c < channels; ++c)
          {
            out[c] += this->Table.Box(c, lo, hi);
          }
        }
      }
    });
}

void SphericalSAT::SetBeyond(const double* sums)
{
  const int channels = this->Table.GetNumberOfChannels();
  const std::array<int, 3> n{ { this->Cells.N[0], this->Cells.N[1], 1 } };
  this->Beyond.Allocate(n, channels);
  for (long long j = 0; j < n[1]; ++j)
  {
    for (long long i = 0; i < n[0]; ++i)
    {
      for (int c = 0; c < channels; ++c)
      {
        this->Beyond.SetCell(c, i, j, 0, sums[(j * n[0] + i) * channels + c]);
      }
    }
  }
  this->Beyond.Integrate();
}

void SphericalSAT::ChooseLayout(
  const double bounds[6], double& rMax, double polar[2], double square[2])
{
  const double* light = this->Light.data();
  // Radii and angles that hold the whole box. Outside the box, the cone about the axis that
  // holds its eight corners holds all of it (a cone narrower than a half-space is convex),
  // and so does the rectangle of face angles that holds them when all lie in front (x / z
  // and y / z take their extremes over a convex polyhedron at its vertices); from inside,
  // every direction is needed.
  bool inside = true;
  double nearest[3];
  for (int a = 0; a < 3; ++a)
  {
    inside = inside && light[a] >= bounds[2 * a] && light[a] <= bounds[2 * a + 1];
    nearest[a] = std::min(std::max(light[a], bounds[2 * a]), bounds[2 * a + 1]);
  }
  double thetaMax = 0.0;
  double face[4] = { FaceAngleLimit, -FaceAngleLimit, FaceAngleLimit, -FaceAngleLimit };
  bool inFront = !inside;
  for (int corner = 0; corner < 8; ++corner)
  {
    const double p[3] = { bounds[corner & 1], bounds[2 + ((corner >> 1) & 1)],
      bounds[4 + ((corner >> 2) & 1)] };
    double q[3];
    LightCoordinates(this->Frame, this->Light, p, q);
    const double r = vtkMath::Norm(q);
    rMax = std::max(rMax, r);
    thetaMax = std::max(thetaMax, std::atan2(std::sqrt(q[0] * q[0] + q[1] * q[1]), q[2]));
    inFront = inFront && q[2] > 1e-6 * r;
    const double u = std::atan2(q[0], q[2]), v = std::atan2(q[1], q[2]);
    face[0] = std::min(face[0], u);
    face[1] = std::max(face[1], u);
    face[2] = std::min(face[2], v);
    face[3] = std::max(face[3], v);
  }
  thetaMax = inside || thetaMax >= 0.5 * vtkMath::Pi() ? vtkMath::Pi() : thetaMax;
  this->RMin = inside ? 0.0 : std::sqrt(vtkMath::Distance2BetweenPoints(light, nearest));
  // Angular extents at the far side, in cells: the polar layout spends 2 pi sin(theta) cells
  // on every ring of theta, the face layout about one per cell of solid angle.
  const double spread = thetaMax >= 0.5 * vtkMath::Pi() ? 1.0 : std::sin(thetaMax);
  polar[0] = 2.0 * vtkMath::Pi() * spread;
  polar[1] = thetaMax;
  square[0] = face[1] - face[0];
  square[1] = face[3] - face[2];
  this->Polar = !inFront || square[0] * square[1] >= polar[0] * polar[1];
  if (this->Polar)
  {
    this->U0 = -vtkMath::Pi();
    this->U1 = vtkMath::Pi();
    this->V0 = 0.0;
    this->V1 = thetaMax;
  }
  else
  {
    this->U0 = face[0];
    this->U1 = face[1];
    this->V0 = face[2];
    this->V1 = face[3];
  }
}

void SphericalSAT::FillCells(const ClassifiedVolume& data, const VolumePiece* piece)
{
  const double* light = this->Light.data();
  const int channels = this->Table.GetNumberOfChannels();
  const std::array<int, 3>& n = this->Cells.N;
  const std::array<int, 3>& first = this->Cells.First;
  double bounds[6];
  (piece ? piece->Whole : data.Geometry).GetBounds(bounds);
  // Cell integrals along r with the midpoint rule at most one data spacing apart (cells grow
  // coarser than the data when the table is capped: a thin layer still casts its shadow).
  const int samples = std::max(
    1, static_cast<int>(std::ceil(this->DR / data.Geometry.MinimumSpacing() - GeometricTolerance)));
  const double eps = GeometricTolerance * std::max(bounds[1] - bounds[0], 1.0);
  // Each ray's direction and solid angle, shared by its cells along r, and the cells of a
  // piece's window whose centres the piece takes.
  const long long rays = static_cast<long long>(n[0]) * n[1];
  struct Ray
  {
    double Direction[3];
    double SolidAngle;
    int First, Last; // cells, in the window
  };
  std::vector<Ray> ray(static_cast<size_t>(rays));
  vtkSMPTools::For(0, rays,
    [&](long long begin, long long end)
    {
      for (long long id = begin; id < end; ++id)
      {
        const int i = first[0] + static_cast<int>(id % n[0]);
        const int j = first[1] + static_cast<int>(id / n[0]);
        const double u0 = this->U0 + i * this->DU;
        const double v0 = this->V0 + j * this->DV;
        auto& r = ray[static_cast<size_t>(id)];
        this->ColumnDirection(i, j, r.Direction);
        r.SolidAngle = this->SolidAngle(u0, u0 + this->DU, v0, v0 + this->DV);
        r.First = 0;
        r.Last = n[2] - 1;
        if (piece)
        {
          this->TakenRun(*piece, i, j, r.First, r.Last);
          r.First -= first[2];
          r.Last -= first[2];
        }
      }
    });
  vtkSMPTools::For(0, static_cast<long long>(n[2]),
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
      {
        for (long long id = 0; id < rays; ++id)
        {
          const Ray& r = ray[static_cast<size_t>(id)];
          double cell[3] = { 0.0, 0.0, 0.0 };
          for (int m = 0; m < samples && k >= r.First && k <= r.Last; ++m)
          {
            const double radius = this->RMin + (first[2] + k + (m + 0.5) / samples) * this->DR;
            const double p[3] = { light[0] + radius * r.Direction[0],
              light[1] + radius * r.Direction[1], light[2] + radius * r.Direction[2] };
            float s[4];
            if (!SampleInside(data, bounds, eps, p, s))
            {
              continue;
            }
            for (int c = 0; c < channels; ++c)
            {
              const double absorb = channels == 3 ? s[1 + c] : 1.0;
              cell[c] += s[0] * absorb * this->DR * r.SolidAngle / samples;
            }
          }
          for (int c = 0; c < channels; ++c)
          {
            this->Table.SetCell(c, id % n[0], id / n[0], k, cell[c]);
          }
        }
      }
    });
  this->Table.Integrate();
}

double SphericalSAT::Integral(
  int channel, double u0, double u1, double v0, double v1, double r) const
{
  // A cell holds its content in proportion to solid angle, so a fraction of a polar theta
  // cell is measured in cos(theta), not in theta (face cells are near enough to uniform).
  auto vIndex = [this](double v)
  {
    if (!this->Polar)
    {
      return (v - this->V0) / this->DV;
    }
    const int n = this->Cells.Whole[1];
    const int j = std::min(std::max(static_cast<int>(v / this->DV), 0), n - 1);
    const double c0 = std::cos(j * this->DV);
    const double c1 = std::cos((j + 1) * this->DV);
    return j + (c0 - std::cos(v)) / (c0 - c1);
  };
  // In the whole table's cells, then the window's.
  double lo[3] = { (u0 - this->U0) / this->DU, vIndex(v0), 0.0 };
  double hi[3] = { (u1 - this->U0) / this->DU, vIndex(v1), (r - this->RMin) / this->DR };
  for (int a = 0; a < 3; ++a)
  {
    lo[a] -= this->Cells.First[a];
    hi[a] -= this->Cells.First[a];
  }
  double integral = this->Table.Box(channel, lo, hi);
  if (this->Beyond.GetDimensions()[2] > 0)
  {
    // The columns' cells between the light and the window.
    lo[2] = 0.0;
    hi[2] = 1.0;
    integral += this->Beyond.Box(channel, lo, hi);
  }
  return integral;
}

double SphericalSAT::FilteredOpticalDepth(int channel, const double p[3], double halfWidth) const
{
  double s[3];
  this->ToSpherical(p, s);
  const double r = std::max(s[2], 1e-12);
  const double pi = vtkMath::Pi();
  // The patch's half-extent in each angle: its angular half-width divided by how fast the
  // direction turns with that angle, and at least half a cell (a hard shadow reads the
  // table at its own angular resolution wherever the sample is).
  const double w = halfWidth / r;
  double du, dv;
  if (this->Polar)
  {
    const double sine = std::sin(s[1]);
    du = sine * pi > w ? std::min(w / sine, pi) : pi;
    dv = std::min(w, pi);
  }
  else
  {
    const double x = std::tan(s[0]), y = std::tan(s[1]);
    const double n2 = 1.0 + x * x + y * y;
    du = std::min(w * n2 / ((1.0 + x * x) * std::sqrt(1.0 + y * y)), pi);
    dv = std::min(w * n2 / ((1.0 + y * y) * std::sqrt(1.0 + x * x)), pi);
  }
  du = std::max(du, 0.5 * this->DU);
  dv = std::max(dv, 0.5 * this->DV);
  // The patch's angles, where they exist (theta in [0, pi], face angles inside +-pi/2); the
  // table holds the part within its own range, the rest of the patch misses the box.
  const double lowest = this->Polar ? 0.0 : -FaceAngleLimit;
  const double highest = this->Polar ? pi : FaceAngleLimit;
  const double v0 = std::max(lowest, s[1] - dv);
  const double v1 = std::min(highest, s[1] + dv);
  double u0 = s[0] - du, u1 = s[0] + du;
  if (!this->Polar)
  {
    u0 = std::max(u0, -FaceAngleLimit);
    u1 = std::min(u1, FaceAngleLimit);
  }
  const double vLow = std::max(v0, this->V0), vHigh = std::min(v1, this->V1);
  double integral = 0.0;
  if (vLow < vHigh && this->Polar)
  {
    // The patch may wrap around phi = +-pi: integrate the pieces.
    if (u0 < -pi)
    {
      integral += this->Integral(channel, u0 + 2.0 * pi, pi, vLow, vHigh, r);
      integral += this->Integral(channel, -pi, u1, vLow, vHigh, r);
    }
    else if (u1 > pi)
    {
      integral += this->Integral(channel, u0, pi, vLow, vHigh, r);
      integral += this->Integral(channel, -pi, u1 - 2.0 * pi, vLow, vHigh, r);
    }
    else
    {
      integral += this->Integral(channel, u0, u1, vLow, vHigh, r);
    }
  }
  else if (vLow < vHigh)
  {
    const double uLow = std::max(u0, this->U0), uHigh = std::min(u1, this->U1);
    integral = uLow < uHigh ? this->Integral(channel, uLow, uHigh, vLow, vHigh, r) : 0.0;
  }
  const double solidAngle = this->SolidAngle(u0, u1, v0, v1);
  return solidAngle > 0.0 ? integral / solidAngle : 0.0;
}

}
