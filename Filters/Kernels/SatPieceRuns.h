/**
 * @file SatPieceRuns.h
 * @brief Which cell centres of a summed-area table along a line a piece of a distributed
 * volume takes (private to the summed-area table kernel's sources): shared by the Cartesian
 * tables' columns and the spherical tables' radial columns.
 */
#ifndef SatPieceRuns_h
#define SatPieceRuns_h

#include "RayMarchKernel.h"
#include "SummedAreaTableKernel.h"

#include "vtkType.h"

#include <algorithm>
#include <cmath>

namespace volillum
{
namespace sat
{
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

// Along data axis a, where n centres span less than a cell and the piece at least one: the
// piece takes all of them, none (false), or those on one side of a single change, found by
// bisection, which narrows the estimate [t0, t1] of the run. takes(k, a): whether the piece
// takes centre k along a.
template <typename Takes>
bool NarrowToSingleChange(const Takes& takes, int n, int a, double& t0, double& t1)
{
  const bool atFirst = takes(0, a), atLast = takes(n - 1, a);
  if (!atFirst && !atLast)
  {
    return false;
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
  return true;
}

// Along data axis a, where n centres on a straight line move from grid coordinate u0 (the
// first) to u1 (the last), a cell or more: narrows the estimate [t0, t1] of the run to the
// centres in the piece's cells (and beyond the grid's faces it reaches, unless strict).
inline void NarrowAlongLine(
  const PieceTest& test, int n, int a, double u0, double u1, double& t0, double& t1)
{
  const VolumePiece& piece = test.Piece;
  const GridGeometry& g = piece.Whole;
  const bool lowFace = !test.Strict && piece.FirstCell[a] == 0;
  const bool highFace = !test.Strict && piece.LastCell[a] >= g.Dimensions[a] - 2;
  const double lo = lowFace ? -VTK_DOUBLE_MAX : piece.FirstCell[a];
  const double hi = highFace ? VTK_DOUBLE_MAX : piece.LastCell[a] + 1.0;
  const double slope = (u1 - u0) / (n - 1); // at least 1 / (n - 1)
  const double k0 = (lo - u0) / slope, k1 = (hi - u0) / slope;
  t0 = std::max(t0, std::min(k0, k1));
  t1 = std::min(t1, std::max(k0, k1));
}

// The run [first, last] of n centres from its estimate [t0, t1], settled with the tests:
// takes(k, -1), whether the piece takes centre k.
template <typename Takes>
void SettleRun(const Takes& takes, int n, double t0, double t1, int& first, int& last)
{
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
  const GridGeometry& g = test.Piece.Whole;
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
    if (!(constant[a] || std::abs(u1 - u0) < 1.0))
    {
      NarrowAlongLine(test, n, a, u0, u1, t0, t1);
    }
    else if (!NarrowToSingleChange(takes, n, a, t0, t1))
    {
      first = 0;
      last = -1;
      return;
    }
  }
  SettleRun(takes, n, t0, t1, first, last);
}
}
}

#endif
