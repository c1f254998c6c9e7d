#include "RayMarchKernel.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{

EmptyBlocks::EmptyBlocks(const ClassifiedVolume& volume)
  : EmptyBlocks(volume.Geometry, volume, { { 0, 0, 0 } })
{
}

EmptyBlocks::EmptyBlocks(
  const GridGeometry& whole, const ClassifiedVolume& volume, const std::array<int, 3>& offset)
{
  for (int a = 0; a < 3; ++a)
  {
    this->Last[a] = whole.Dimensions[a] - 1;
    this->Blocks[a] = std::max(1, (this->Last[a] + Cells - 1) / Cells);
  }
  const long long bx = this->Blocks[0], by = this->Blocks[1], bz = this->Blocks[2];
  this->Empty.assign(static_cast<size_t>(bx * by * bz), 1);
  const auto& n = volume.Geometry.Dimensions;
  const long long nx = n[0], ny = n[1];
  // A block's points run from Cells x b to Cells x (b + 1), the next block's first ones
  // included: a sample in any of its cells reads only those. Those of the piece, in its
  // indices: from the block's first point less the offset, within the piece.
  auto range = [&](int a, long long b, long long& first, long long& last)
  {
    first = std::max<long long>(b * Cells - offset[a], 0);
    last = std::min<long long>(
      std::min<long long>((b + 1) * Cells, this->Last[a]) - offset[a], n[a] - 1);
  };
  vtkSMPTools::For(0, bz,
    [&](long long k0, long long k1)
    {
      long long i0, i1, j0, j1, kk0, kk1;
      for (long long kb = k0; kb < k1; ++kb)
      {
        range(2, kb, kk0, kk1);
        for (long long jb = 0; jb < by; ++jb)
        {
          range(1, jb, j0, j1);
          for (long long ib = 0; ib < bx; ++ib)
          {
            range(0, ib, i0, i1);
            bool empty = true;
            for (long long k = kk0; empty && k <= kk1; ++k)
              for (long long j = j0; empty && j <= j1; ++j)
                for (long long i = i0; empty && i <= i1; ++i)
                {
                  empty = volume.Extinction(i + nx * (j + ny * k)) <= 0.0f;
                }
            this->Empty[static_cast<size_t>(ib + bx * (jb + by * kb))] = empty ? 1 : 0;
          }
        }
      }
    });
  this->Update();
}

void EmptyBlocks::Update()
{
  const long long bx = this->Blocks[0], by = this->Blocks[1], bz = this->Blocks[2];
  const long long stride[2] = { 1, bx };
  for (int a = 0; a < 2; ++a)
  {
    if (this->Blocks[a] >= 65536)
    {
      continue;
    }
    std::vector<std::uint16_t>& filled = this->Filled[a];
    filled.resize(this->Empty.size());
    const long long rows = bx * by * bz / this->Blocks[a];
    vtkSMPTools::For(0, rows,
      [&](long long r0, long long r1)
      {
        for (long long r = r0; r < r1; ++r)
        {
          // Row r's first block: rows along x are numbered by (y, z); along y by (x, z).
          const long long first = a == 0 ? r * bx : (r % bx) + bx * by * (r / bx);
          std::uint16_t count = 0;
          for (long long b = 0; b < this->Blocks[a]; ++b)
          {
            const size_t index = static_cast<size_t>(first + b * stride[a]);
            count = static_cast<std::uint16_t>(count + (this->Empty[index] ? 0 : 1));
            filled[index] = count;
          }
        }
      });
  }
}

bool EmptyBlocks::ContainsCells(int a, const int cell[3], int first, int last) const
{
  int index[3] = { cell[0], cell[1], cell[2] };
  const std::vector<std::uint16_t>& filled = this->Filled[a];
  if (filled.empty())
  {
    index[a] = first;
    while (this->ContainsCell(index))
    {
      if (index[a] >= last)
      {
        return true;
      }
      index[a] = std::min(last, (index[a] / Cells + 1) * Cells);
    }
    return false;
  }
  // The blocks of the first and last cells, as ContainsCell finds them.
  long long block[3];
  for (int b = 0; b < 3; ++b)
  {
    block[b] = std::min(cell[b] / Cells, this->Blocks[b] - 1);
  }
  const long long stride = a == 0 ? 1 : this->Blocks[0];
  block[a] = 0;
  const long long row = block[0] + this->Blocks[0] * (block[1] + this->Blocks[1] * block[2]);
  const long long lastBlock = std::min(last / Cells, this->Blocks[a] - 1);
  const long long firstBlock = std::min(first / Cells, this->Blocks[a] - 1);
  const std::uint16_t before =
    firstBlock > 0 ? filled[static_cast<size_t>(row + (firstBlock - 1) * stride)] : 0;
  return filled[static_cast<size_t>(row + lastBlock * stride)] == before;
}

namespace
{
// The steps (0 .. n - 1, of length h from p along the unit direction d, sampled at their
// midpoints) whose samples may lie in the piece's cells: those on the part of the ray within
// one spacing of the cells, or beyond the grid where the piece's cells reach its side
// (samples there are clamped onto it); each sample's cell is then checked. False when there
// is none.
bool StepsNearPiece(const VolumePiece& piece, const double p[3], const double d[3], double h,
  long long n, long long& first, long long& last)
{
  const GridGeometry& g = piece.Whole;
  const double huge = std::numeric_limits<double>::max();
  double enter = 0.0, exit = n * h;
  for (int a = 0; a < 3; ++a)
  {
    double x0 = g.Origin[a] + (piece.FirstCell[a] - 1) * g.Spacing[a];
    double x1 = g.Origin[a] + (piece.LastCell[a] + 2) * g.Spacing[a];
    if (piece.FirstCell[a] <= 0)
    {
      x0 = g.Spacing[a] > 0.0 ? -huge : huge;
    }
    if (piece.LastCell[a] >= g.Dimensions[a] - 2)
    {
      x1 = g.Spacing[a] > 0.0 ? huge : -huge;
    }
    const double low = std::min(x0, x1), high = std::max(x0, x1);
    if (d[a] == 0.0)
    {
      if (p[a] < low || p[a] > high)
      {
        return false;
      }
      continue;
    }
    const double t0 = (low - p[a]) / d[a], t1 = (high - p[a]) / d[a];
    enter = std::max(enter, std::min(t0, t1));
    exit = std::min(exit, std::max(t0, t1));
  }
  if (enter > exit)
  {
    return false;
  }
  first = std::max(0LL, static_cast<long long>(std::floor(enter / h - 0.5)));
  last = std::min(n - 1, static_cast<long long>(std::ceil(exit / h - 0.5)));
  return first <= last;
}

// Add the optical depth of a step whose sample reads the cell at q (corner offsets dx, dy, dz,
// fractions fx, fy, fz) to out: extinction x hs (the step times the extinction's scale),
// times each channel's absorption when chromatic.
inline void AddStepDepth(const ClassifiedVolume& volume, const PackedValue* q, long long dx,
  long long dy, long long dz, float fx, float fy, float fz, double hs, bool chromatic, double* out)
{
  const double sigma = TrilinearInCellSkippingZeros(q, dx, dy, dz, fx, fy, fz) * hs;
  if (!chromatic)
  {
    out[0] += sigma;
    return;
  }
  for (int c = 0; c < 3; ++c)
  {
    out[c] +=
      sigma * TrilinearInCellSkippingZeros(q + 1 + c, dx, dy, dz, fx, fy, fz) * volume.Scale[1 + c];
  }
}

// Whether the sample at q lies in the piece's cells and outside its empty blocks; its cell
// in the piece's volume in cell.
bool SampleInPiece(
  const VolumePiece& piece, const double q[3], const EmptyBlocks* empty, TrilinearCell& cell)
{
  cell = CellAtPosition(piece.Whole, q);
  return piece.Takes(cell) && !(empty && empty->ContainsCell(cell.Index));
}
}

VolumePiece VolumePiece::WholeOf(const ClassifiedVolume& volume)
{
  VolumePiece piece;
  piece.Whole = volume.Geometry;
  for (int a = 0; a < 3; ++a)
  {
    piece.LastCell[a] = std::max(volume.Geometry.Dimensions[a] - 2, 0);
  }
  return piece;
}

bool VolumePiece::Takes(TrilinearCell& cell) const
{
  for (int a = 0; a < 3; ++a)
  {
    if (cell.Index[a] < this->FirstCell[a] || cell.Index[a] > this->LastCell[a])
    {
      return false;
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    cell.Index[a] -= this->Offset[a];
  }
  return true;
}

std::array<double, 3> PartialTransmittance(const ClassifiedVolume& volume, const VolumePiece& piece,
  const Incidence& inc, const double p[3], const RayMarchSettings& settings, double cut,
  const EmptyBlocks* empty)
{
  std::array<double, 3> t{ { 1.0, 1.0, 1.0 } };
  const GridGeometry& g = piece.Whole;
  double bounds[6];
  g.GetBounds(bounds);
  const double tMax = std::min(inc.Distance, DistanceToBoxExit(p, inc.ToLight.data(), bounds));
  const double step = settings.StepFraction * g.MinimumSpacing();
  const long long n = std::max(1LL, static_cast<long long>(std::ceil(tMax / step)));
  const double h = tMax / n;
  if (!(h > 0.0))
  {
    return t; // a step of length 0 lets all light through
  }
  long long first, last;
  if (!StepsNearPiece(piece, p, inc.ToLight.data(), h, n, first, last))
  {
    return t;
  }
  float s[4];
  for (long long i = first; i <= last; ++i)
  {
    const double d = (i + 0.5) * h;
    const double q[3] = { p[0] + d * inc.ToLight[0], p[1] + d * inc.ToLight[1],
      p[2] + d * inc.ToLight[2] };
    TrilinearCell cell;
    if (!SampleInPiece(piece, q, empty, cell))
    {
      continue;
    }
    volume.SampleCell(cell, s);
    const double a = StepOpacity(s[0], h);
    t[0] *= 1.0 - a * s[1];
    t[1] *= 1.0 - a * s[2];
    t[2] *= 1.0 - a * s[3];
    if (std::max(t[0], std::max(t[1], t[2])) < cut)
    {
      break;
    }
  }
  return t;
}

std::array<double, 3> DarkenedTransmittance(
  double cone, const std::array<double, 3>& product, const RayMarchSettings& settings)
{
  const std::array<double, 3> t{ { cone * product[0], cone * product[1], cone * product[2] } };
  if (std::max(t[0], std::max(t[1], t[2])) < settings.MinimumTransmittance)
  {
    return { { 0.0, 0.0, 0.0 } };
  }
  return t;
}

std::array<double, 3> RayMarchTransmittance(const ClassifiedVolume& volume, const LightState& light,
  const double p[3], const RayMarchSettings& settings, const EmptyBlocks* empty)
{
  const Incidence inc = ComputeIncidence(light, p);
  if (inc.ConeFactor == 0.0)
  {
    return { { 0.0, 0.0, 0.0 } };
  }
  // A cut below MinimumTransmittance / cone makes the ray dark whatever follows.
  const auto product = PartialTransmittance(volume, VolumePiece::WholeOf(volume), inc, p, settings,
    settings.MinimumTransmittance / inc.ConeFactor, empty);
  return DarkenedTransmittance(inc.ConeFactor, product, settings);
}

void SegmentOpticalDepth(const ClassifiedVolume& volume, const double p[3], const double d[3],
  double length, int channels, double depth[3], const EmptyBlocks* empty)
{
  RowSegmentOpticalDepths(volume, p, 1, p[1], p[2], d, length, channels, depth, empty);
}

void RowSegmentOpticalDepths(const ClassifiedVolume& volume, const double* x, int count, double y,
  double z, const double d[3], double length, int channels, double* depth, const EmptyBlocks* empty)
{
  std::fill(depth, depth + 3 * count, 0.0);
  if (length <= 0.0 || count <= 0)
  {
    return;
  }
  const auto& g = volume.Geometry;
  const int n =
    std::max(1, static_cast<int>(std::ceil(length / g.MinimumSpacing() - GeometricTolerance)));
  const double h = length / n;
  const double hs = h * volume.Scale[0]; // an unpacked extinction's optical depth over h
  // Steps in grid coordinates; only the channels asked for are interpolated.
  double step[3];
  for (int a = 0; a < 3; ++a)
  {
    step[a] = h * d[a] / g.Spacing[a];
  }
  const double firstY = (y + 0.5 * h * d[1] - g.Origin[1]) / g.Spacing[1];
  const double firstZ = (z + 0.5 * h * d[2] - g.Origin[2]) / g.Spacing[2];
  const bool chromatic = channels == 3 && volume.IsChromatic();
  const FieldLayout layout(g, volume.Channels);
  const long long dx = layout.Corner[0], dy = layout.Corner[1], dz = layout.Corner[2];
  // The samples' cells along y and z are the same for every point: they are found once a
  // step, for a chunk of points at a time, and each point adds its steps in order, as
  // SegmentOpticalDepth does. A point keeps its cell along x when the rays cross the row.
  constexpr int Chunk = 256;
  double firstX[Chunk];
  int ix[Chunk];
  float fx[Chunk];
  for (int begin = 0; begin < count; begin += Chunk)
  {
    const int size = std::min(Chunk, count - begin);
    for (int i = 0; i < size; ++i)
    {
      firstX[i] = (x[begin + i] + 0.5 * h * d[0] - g.Origin[0]) / g.Spacing[0];
      AxisCell(g.Dimensions[0], firstX[i], ix[i], fx[i]);
    }
    for (int m = 0; m < n; ++m)
    {
      int iy, iz;
      float fy, fz;
      AxisCell(g.Dimensions[1], firstY + m * step[1], iy, fy);
      AxisCell(g.Dimensions[2], firstZ + m * step[2], iz, fz);
      const PackedValue* row =
        volume.Properties.data() + iy * layout.Stride[1] + iz * layout.Stride[2];
      const long long blocks = empty ? empty->Row(iy, iz) : 0;
      for (int i = 0; i < size; ++i)
      {
        if (step[0] != 0.0) // else the ray stays in its cell along x
        {
          AxisCell(g.Dimensions[0], firstX[i] + m * step[0], ix[i], fx[i]);
        }
        if (empty && empty->RowContains(blocks, ix[i]))
        {
          continue;
        }
        AddStepDepth(volume, row + ix[i] * layout.Stride[0], dx, dy, dz, fx[i], fy, fz, hs,
          chromatic, depth + 3 * (begin + i));
      }
    }
  }
  if (channels == 3 && !volume.IsChromatic())
  {
    for (int i = 0; i < count; ++i)
    {
      depth[3 * i + 1] = depth[3 * i + 2] = depth[3 * i];
    }
  }
}

std::array<double, 3> RayMarchIlluminationAt(const ClassifiedVolume& volume,
  const std::vector<LightState>& lights, const double p[3], const RayMarchSettings& settings,
  const EmptyBlocks* empty)
{
  std::array<double, 3> sum{ { 0.0, 0.0, 0.0 } };
  for (const auto& light : lights)
  {
    if (!light.On)
    {
      continue;
    }
    const auto t = RayMarchTransmittance(volume, light, p, settings, empty);
    const auto r = light.Radiance();
    for (int c = 0; c < 3; ++c)
    {
      sum[c] += r[c] * t[c];
    }
  }
  return sum;
}

bool RayMarchIllumination(const ClassifiedVolume& volume, const std::vector<LightState>& lights,
  const GridGeometry& target, const RayMarchSettings& settings, float* rgb,
  const ProgressCallback& progress)
{
  const long long nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  const long long nz = target.Dimensions[2];
  std::fill(rgb, rgb + 3 * nx * ny * nz, 0.0f);
  if (std::none_of(lights.begin(), lights.end(), [](const LightState& l) { return l.On; }))
  {
    return true;
  }
  const EmptyBlocks empty(volume);
  // Rows are done in 256 chunks, progress reported from this thread after each: a stop
  // asked for is seen within 1/256 of the whole march (0.1 s of a 30 s reference).
  const long long rows = ny * nz;
  const long long chunk = std::max(1LL, rows / 256);
  for (long long r0 = 0; r0 < rows; r0 += chunk)
  {
    const long long r1 = std::min(rows, r0 + chunk);
    vtkSMPTools::For(r0, r1,
      [&](long long begin, long long end)
      {
        for (long long row = begin; row < end; ++row)
        {
          const long long j = row % ny;
          const long long k = row / ny;
          for (long long i = 0; i < nx; ++i)
          {
            double p[3];
            target.PointPosition(i, j, k, p);
            const auto sum = RayMarchIlluminationAt(volume, lights, p, settings, &empty);
            float* o = rgb + 3 * (i + nx * row);
            o[0] = static_cast<float>(sum[0]);
            o[1] = static_cast<float>(sum[1]);
            o[2] = static_cast<float>(sum[2]);
          }
        }
      });
    if (progress && !progress(static_cast<double>(r1) / rows))
    {
      return false;
    }
  }
  return true;
}

}
