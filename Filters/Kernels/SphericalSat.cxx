#include "SummedAreaTableKernel.h"

#include "RayMarchKernel.h"
#include "SatPieceRuns.h"

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
  const sat::PieceTest test(piece, false);
  sat::TakenRun(
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
  int channel, double u0, double u1, double v0, double v1, double r0, double r1) const
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
  double lo[3] = { (u0 - this->U0) / this->DU, vIndex(v0),
    r0 <= this->RMin ? 0.0 : (r0 - this->RMin) / this->DR };
  double hi[3] = { (u1 - this->U0) / this->DU, vIndex(v1), (r1 - this->RMin) / this->DR };
  const bool fromWindowStart = lo[2] <= this->Cells.First[2];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] -= this->Cells.First[a];
    hi[a] -= this->Cells.First[a];
  }
  double integral = this->Table.Box(channel, lo, hi);
  if (fromWindowStart && this->Beyond.GetDimensions()[2] > 0)
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
  return this->PatchDepth(channel, s, halfWidth / r, this->RMin, r);
}

double SphericalSAT::ConeFilteredOpticalDepth(
  int channel, const double p[3], double halfWidth, double start, double spread) const
{
  double s[3];
  this->ToSpherical(p, s);
  const double r = std::max(s[2], 1e-12);
  // Distances t from the shadow ray's start (at distance D from the light) toward the light;
  // the cone's half-width there, t spread, seen from the light at distance D - t: an angle
  // below pi / 2 (which takes the whole half-space in front of the light), and at least the
  // patch's and half a cell's (PatchDepth reads no narrower patch).
  const double D = r + start;
  const double end = D - std::min(this->RMin, r);
  const double narrowest = std::max(halfWidth / r, 0.5 * std::min(this->DU, this->DV));
  return ConeSteps(
    start, end, narrowest, 0.5 * vtkMath::Pi(),
    [=](double t) { return std::atan(spread * t / std::max(D - t, 1e-12)); },
    [=](double w)
    {
      const double x = std::tan(w);
      return x * D / (spread + x);
    },
    [&](double t0, double t1, double w)
    { return this->PatchDepth(channel, s, w, D - t1, D - t0); });
}

double SphericalSAT::PatchDepth(
  int channel, const double s[3], double w, double r0, double r1) const
{
  const double pi = vtkMath::Pi();
  // The patch's half-extent in each angle: its angular half-width divided by how fast the
  // direction turns with that angle, and at least half a cell (a hard shadow reads the
  // table at its own angular resolution wherever the sample is).
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
      integral += this->Integral(channel, u0 + 2.0 * pi, pi, vLow, vHigh, r0, r1);
      integral += this->Integral(channel, -pi, u1, vLow, vHigh, r0, r1);
    }
    else if (u1 > pi)
    {
      integral += this->Integral(channel, u0, pi, vLow, vHigh, r0, r1);
      integral += this->Integral(channel, -pi, u1 - 2.0 * pi, vLow, vHigh, r0, r1);
    }
    else
    {
      integral += this->Integral(channel, u0, u1, vLow, vHigh, r0, r1);
    }
  }
  else if (vLow < vHigh)
  {
    const double uLow = std::max(u0, this->U0), uHigh = std::min(u1, this->U1);
    integral = uLow < uHigh ? this->Integral(channel, uLow, uHigh, vLow, vHigh, r0, r1) : 0.0;
  }
  const double solidAngle = this->SolidAngle(u0, u1, v0, v1);
  return solidAngle > 0.0 ? integral / solidAngle : 0.0;
}
}
