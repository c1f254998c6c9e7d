#include "SummedAreaTableKernel.h"

#include "RayMarchKernel.h"
#include "SatPieceRuns.h"

#include "vtkMath.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

using namespace sat;

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

// The cells of the grid g whose centres a table samples: the piece's, or all the grid's.
VolumePiece SampledCells(const GridGeometry& g, const VolumePiece* piece)
{
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
  return taken;
}

// A Cartesian table's cell integrals (CartesianSAT::Build): extinction at the cell centre
// (zero outside the data) times volume. The centres of a row along the frame's first axis
// share the other axes' terms of their world positions, and their cell along each data axis
// the row does not move along.
struct CellIntegrals
{
  CellIntegrals(const ClassifiedVolume& data, const CellCentres& centres, const PieceTest& taking,
    const VolumePiece* piece, const EmptyBlocks* empty, const TableWindow& cells, int channels,
    double cellSize, RunningIntegralTable& table)
    : Data(data)
    , Centres(centres)
    , Taking(taking)
    , Piece(piece)
    , Empty(empty)
    , Cells(cells)
    , Channels(channels)
    , Volume(cellSize * cellSize * cellSize)
    , Chromatic(channels == 3 && data.IsChromatic())
    , Layout(data.Geometry, data.Channels)
    , Table(table)
  {
  }

  // The cells of row (j, k) of the table's window.
  void Row(long long j, long long k) const
  {
    const SatFrame& frame = this->Centres.Frame;
    const std::array<int, 3>& firstCell = this->Cells.First;
    const double qy = this->Centres.Coordinate(1, firstCell[1] + j);
    const double qz = this->Centres.Coordinate(2, firstCell[2] + k);
    const double ty[3] = { qy * frame.Axes[1][0], qy * frame.Axes[1][1], qy * frame.Axes[1][2] };
    const double tz[3] = { qz * frame.Axes[2][0], qz * frame.Axes[2][1], qz * frame.Axes[2][2] };
    const double rowX = this->Centres.Coordinate(0, firstCell[0]);
    long long begin, end;
    this->SampledRun(j, k, begin, end);
    TrilinearCell cell;
    bool rowInside = true;
    for (int a = 0; a < 3; ++a)
    {
      if (frame.Axes[0][a] == 0.0)
      {
        rowInside =
          this->Centres.Locate(a, this->Centres.Position(a, rowX, ty, tz), cell) && rowInside;
      }
    }
    for (long long i = begin; i < end; ++i)
    {
      bool inside = rowInside;
      for (int a = 0; a < 3; ++a)
      {
        if (frame.Axes[0][a] != 0.0)
        {
          const double tx = this->Centres.Coordinate(0, firstCell[0] + i);
          inside = this->Centres.Locate(a, this->Centres.Position(a, tx, ty, tz), cell) && inside;
        }
      }
      this->SetCell(i, j, k, cell, inside);
    }
  }

  // Only the centres the piece takes are sampled, a run [begin, end) along row (j, k); the
  // others' cells are set to 0.
  void SampledRun(long long j, long long k, long long& begin, long long& end) const
  {
    const std::array<int, 3>& n = this->Cells.N;
    const std::array<int, 3>& firstCell = this->Cells.First;
    long long row[3] = { 0, firstCell[1] + j, firstCell[2] + k };
    int first, last;
    ColumnRun(this->Centres, this->Taking, 0, row, this->Cells.Whole[0], first, last);
    begin = std::min<long long>(n[0], std::max(0, first - firstCell[0]));
    end = std::max(begin, std::min<long long>(n[0], last + 1LL - firstCell[0]));
    for (long long i = 0; i < n[0]; ++i)
    {
      for (int c = 0; c < this->Channels && (i < begin || i >= end); ++c)
      {
        this->Table.SetCell(c, i, j, k, 0.0);
      }
    }
  }

  // The integral of cell (i, j, k), whose centre lies in the data's cell `at` (inside: within
  // the grid's bounds; a copy, whose index the piece's test moves into the piece's volume).
  void SetCell(long long i, long long j, long long k, TrilinearCell at, bool inside) const
  {
    inside = inside && (!this->Piece || this->Piece->Takes(at));
    if (!inside || (this->Empty && this->Empty->ContainsCell(at.Index)))
    {
      for (int c = 0; c < this->Channels; ++c)
      {
        this->Table.SetCell(c, i, j, k, 0.0);
      }
      return;
    }
    const long long dx = this->Layout.Corner[0], dy = this->Layout.Corner[1],
                    dz = this->Layout.Corner[2];
    const PackedValue* q = this->Data.Properties.data() + this->Layout.Offset(at.Index);
    const auto& f = at.Fraction;
    const double sigma =
      TrilinearInCellSkippingZeros(q, dx, dy, dz, f[0], f[1], f[2]) * this->Data.Scale[0];
    for (int c = 0; c < this->Channels; ++c)
    {
      const double absorb = this->Chromatic
        ? TrilinearInCellSkippingZeros(q + 1 + c, dx, dy, dz, f[0], f[1], f[2]) *
          static_cast<double>(this->Data.Scale[1 + c])
        : 1.0;
      this->Table.SetCell(c, i, j, k, sigma * absorb * this->Volume);
    }
  }

  const ClassifiedVolume& Data;
  const CellCentres& Centres;
  const PieceTest& Taking;
  const VolumePiece* Piece;
  const EmptyBlocks* Empty;
  const TableWindow& Cells;
  const int Channels;
  const double Volume;
  const bool Chromatic;
  const FieldLayout Layout;
  RunningIntegralTable& Table;
};
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
  for (int a = 0; a < 3; ++a)
  {
    this->Origin[a] = this->WholeOrigin[a] + this->Cells.First[a] * cellSize;
  }
  for (auto& beyond : this->Beyond)
  {
    beyond = RunningIntegralTable();
  }
  this->Table.Allocate(n, channels);

  const CellCentres centres(g, frame, this->WholeOrigin, cellSize);
  const VolumePiece taken = SampledCells(g, piece);
  const PieceTest taking(taken, true);
  const CellIntegrals integrals(
    data, centres, taking, piece, empty, this->Cells, channels, cellSize, this->Table);
  vtkSMPTools::For(0, static_cast<long long>(n[2]),
    [&](long long k0, long long k1)
    {
      for (long long k = k0; k < k1; ++k)
      {
        for (long long j = 0; j < n[1]; ++j)
        {
          integrals.Row(j, k);
        }
      }
    });
  this->Table.Integrate();
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
}
