// Level 0 of the tetrahedral light kernel: resampling onto a regular grid and the ray propagation.
#include "TetrahedralLightKernel.h"

#include "LightPropagationKernel.h"
#include "TetrahedralGeometry.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{

using namespace tetrahedral;

namespace
{
// The grid points along axis a of the level-0 grid between the coordinates lo and hi.
void IndexRange(const GridGeometry& g, double lo, double hi, int a, int& first, int& last)
{
  const double eps = GeometricTolerance;
  first = std::max(0, static_cast<int>(std::ceil((lo - g.Origin[a]) / g.Spacing[a] - eps)));
  last = std::min(
    g.Dimensions[a] - 1, static_cast<int>(std::floor((hi - g.Origin[a]) / g.Spacing[a] + eps)));
}

// Each tetrahedron's bounding box, and the tetrahedra spanning each z plane of the grid.
void BucketByPlane(const TetrahedralMesh& mesh, const GridGeometry& g,
  std::vector<std::array<double, 6>>& boxes, std::vector<std::vector<int>>& planes)
{
  const int nTets = mesh.OwnTets;
  boxes.resize(nTets);
  planes.assign(g.Dimensions[2], {});
  for (int t = 0; t < nTets; ++t)
  {
    auto& box = boxes[t];
    for (int a = 0; a < 3; ++a)
    {
      box[2 * a] = std::numeric_limits<double>::max();
      box[2 * a + 1] = -std::numeric_limits<double>::max();
    }
    for (int i = 0; i < 4; ++i)
    {
      const int id = mesh.Tets[4 * t + i];
      for (int a = 0; a < 3; ++a)
      {
        box[2 * a] = std::min(box[2 * a], mesh.Points[3 * id + a]);
        box[2 * a + 1] = std::max(box[2 * a + 1], mesh.Points[3 * id + a]);
      }
    }
    int k0, k1;
    IndexRange(g, box[4], box[5], 2, k0, k1);
    for (int k = k0; k <= k1; ++k)
    {
      planes[k].push_back(t);
    }
  }
}

// The points of plane k inside tetrahedron t (box: its bounds) get its barycentric
// interpolation of the extinction and are marked inside.
void FillFromTetrahedron(const TetrahedralMesh& mesh, const std::vector<float>& extinction, int t,
  const std::array<double, 6>& box, int k, Level0Grid& grid)
{
  const auto& g = grid.Geometry;
  const int channels = grid.Channels;
  const long long nx = g.Dimensions[0];
  const long long nxy = nx * g.Dimensions[1];
  const Barycentric frame(mesh, t);
  const int* v = mesh.Tets.data() + 4 * t;
  int j0, j1, i0, i1;
  IndexRange(g, box[2], box[3], 1, j0, j1);
  IndexRange(g, box[0], box[1], 0, i0, i1);
  for (int j = j0; j <= j1; ++j)
  {
    for (int i = i0; i <= i1; ++i)
    {
      double p[3];
      g.PointPosition(i, j, k, p);
      double b[4];
      frame.Evaluate({ { p[0], p[1], p[2] } }, false, b);
      if (std::min(std::min(b[0], b[1]), std::min(b[2], b[3])) < -GeometricTolerance)
      {
        continue;
      }
      const long long id = i + j * nx + k * nxy;
      grid.Inside[id] = 1;
      for (int c = 0; c < channels; ++c)
      {
        double s = 0.0;
        for (int q = 0; q < 4; ++q)
        {
          s += b[q] * extinction[channels * static_cast<size_t>(v[q]) + c];
        }
        grid.Extinction[channels * id + c] = static_cast<float>(std::max(s, 0.0));
      }
    }
  }
}
}

//------------------------------------------------------------------------------
GridGeometry Level0Geometry(const double bounds[6], const std::array<int, 3>& dimensions)
{
  GridGeometry g;
  for (int a = 0; a < 3; ++a)
  {
    g.Dimensions[a] = std::max(dimensions[a], 2);
    g.Origin[a] = bounds[2 * a];
    const double extent = bounds[2 * a + 1] - bounds[2 * a];
    g.Spacing[a] = extent > 0.0 ? extent / (g.Dimensions[a] - 1) : 1.0;
  }
  return g;
}

//------------------------------------------------------------------------------
void ResampleLevel0(const TetrahedralMesh& mesh, const std::vector<float>& extinction, int channels,
  const std::array<int, 3>& dimensions, Level0Grid& grid)
{
  ResampleLevel0Onto(mesh, extinction, channels, Level0Geometry(mesh.Bounds, dimensions), grid);
}

//------------------------------------------------------------------------------
void ResampleLevel0Onto(const TetrahedralMesh& mesh, const std::vector<float>& extinction,
  int channels, const GridGeometry& geometry, Level0Grid& grid)
{
  grid.Channels = channels;
  grid.Geometry = geometry;
  const auto& g = grid.Geometry;
  const long long n = g.NumberOfPoints();
  grid.Extinction.assign(static_cast<size_t>(n) * channels, 0.0f);
  grid.Inside.assign(static_cast<size_t>(n), 0);
  // Tetrahedra bucketed by the z planes they span, so that planes fill in parallel.
  std::vector<std::array<double, 6>> boxes;
  std::vector<std::vector<int>> planes;
  BucketByPlane(mesh, g, boxes, planes);
  vtkSMPTools::For(0, g.Dimensions[2],
    [&](int kBegin, int kEnd)
    {
      for (int k = kBegin; k < kEnd; ++k)
      {
        for (int t : planes[k])
        {
          FillFromTetrahedron(mesh, extinction, t, boxes[t], k, grid);
        }
      }
    });
}

//------------------------------------------------------------------------------
void PropagateLevel0(const Level0Grid& grid, const LightState& light, std::vector<float>& rho)
{
  // The transmittance alone: a white light of intensity 1 without a spot cone.
  LightState white = light;
  white.Kind = light.Kind == LightKind::Directional ? LightKind::Directional : LightKind::Point;
  white.Color = { { 1.0, 1.0, 1.0 } };
  white.Intensity = 1.0;
  white.On = true;
  double bounds[6];
  grid.Geometry.GetBounds(bounds);
  const std::vector<PropagationTask> tasks = TasksForLight(white, +1, bounds);
  const long long np = grid.Geometry.NumberOfPoints();
  const int nc = grid.Channels;
  rho.resize(static_cast<size_t>(np) * nc);
  std::vector<float> sigma(nc == 1 ? 0 : np);
  for (int c = 0; c < nc; ++c)
  {
    ClassifiedVolume volume;
    volume.Geometry = grid.Geometry;
    volume.Channels = 1;
    if (nc == 1)
    {
      volume.Store(grid.Extinction);
    }
    else
    {
      for (long long q = 0; q < np; ++q)
      {
        sigma[q] = grid.Extinction[nc * q + c];
      }
      volume.Store(sigma);
    }
    FixedPointIllumination light1;
    light1.Reset(np, FixedPointIllumination::ScaleFor(1.0));
    std::vector<PropagationTask> remaining;
    PropagationStatistics statistics;
    PropagateTasks(volume, grid.Geometry, tasks, true, 0, light1, remaining, statistics, nullptr);
    // Every channel of the white light holds the transmittance: the first is read.
    FixedPointIllumination::ToFloat(
      light1.Values.data(), static_cast<size_t>(np), light1.Scale, rho.data() + c, 3, nc);
  }
}

}
