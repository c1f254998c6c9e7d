// Level 0 of the tetrahedral light kernel: resampling onto a regular grid and the upwind solve.
#include "TetrahedralLightKernel.h"

#include "TetrahedralGeometry.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

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

// The order in which the upwind pass visits the indices along each axis: nearest to the
// light first.
std::array<std::vector<int>, 3> VisitingOrder(const GridGeometry& g, const LightState& light)
{
  const bool directional = light.Kind == LightKind::Directional;
  const Vec3 d = light.Direction();
  const Vec3& p = light.Position;
  std::array<std::vector<int>, 3> order;
  for (int a = 0; a < 3; ++a)
  {
    const int n = g.Dimensions[a];
    order[a].resize(n);
    std::iota(order[a].begin(), order[a].end(), 0);
    if (directional)
    {
      if (d[a] < 0.0)
      {
        std::reverse(order[a].begin(), order[a].end());
      }
    }
    else
    {
      const double l = (p[a] - g.Origin[a]) / g.Spacing[a];
      std::stable_sort(order[a].begin(), order[a].end(),
        [l](int x, int y) { return std::abs(x - l) < std::abs(y - l); });
    }
  }
  return order;
}

// The upwind update of point (i, j, k): the light arriving from its upwind neighbours (or
// through the grid's faces, or straight from a light inside its cell), attenuated over the
// step between them.
// The light: directional (direction d) or at p.
void UpwindPoint(const Level0Grid& grid, bool directional, const Vec3& d, const Vec3& p, int i,
  int j, int k, std::vector<float>& rho)
{
  const auto& g = grid.Geometry;
  const int nc = grid.Channels;
  const long long stride[3] = { 1, g.Dimensions[0],
    static_cast<long long>(g.Dimensions[0]) * g.Dimensions[1] };
  const int index[3] = { i, j, k };
  double x[3];
  g.PointPosition(i, j, k, x);
  Vec3 u = d;
  if (!directional)
  {
    u = Sub({ { x[0], x[1], x[2] } }, p);
    const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (len == 0.0)
    {
      return; // the light's own point keeps 1
    }
    u = { { u[0] / len, u[1] / len, u[2] / len } };
  }
  const long long id = i * stride[0] + j * stride[1] + k * stride[2];
  // An axis whose upwind neighbour lies across the light's plane has no upwind
  // value (the light is not between the points, only beside them): it is left out
  // and the other axes carry the light.
  bool across[3] = { false, false, false };
  double weightSum = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const int nb = index[a] + (u[a] > 0.0 ? -1 : 1);
    const double nbPosition = g.Origin[a] + nb * g.Spacing[a];
    across[a] = !directional && (nbPosition - p[a]) * (x[a] - p[a]) < 0.0;
    weightSum += across[a] ? 0.0 : std::abs(u[a]) / g.Spacing[a];
  }
  const float* sigmaHere = grid.Extinction.data() + nc * id;
  double in[3] = { 0.0, 0.0, 0.0 };
  if (weightSum == 0.0)
  {
    // The light is inside this point's cell: straight from the light.
    const double r = std::sqrt((x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) +
      (x[2] - p[2]) * (x[2] - p[2]));
    for (int c = 0; c < nc; ++c)
    {
      in[c] = std::exp(-r * sigmaHere[c]);
    }
  }
  const double ds = weightSum > 0.0 ? 1.0 / weightSum : 0.0;
  for (int a = 0; a < 3 && weightSum > 0.0; ++a)
  {
    const double w = std::abs(u[a]) / g.Spacing[a] * ds;
    if (w == 0.0 || across[a])
    {
      continue;
    }
    const int step = u[a] > 0.0 ? -1 : 1; // toward the light
    const int nb = index[a] + step;
    if (nb < 0 || nb >= g.Dimensions[a])
    {
      // Light enters through the grid face, where the mesh bounds are: nothing
      // absorbs before this point.
      for (int c = 0; c < nc; ++c)
      {
        in[c] += w;
      }
      continue;
    }
    const float* nbRho = rho.data() + nc * (id + step * stride[a]);
    const float* nbSigma = grid.Extinction.data() + nc * (id + step * stride[a]);
    for (int c = 0; c < nc; ++c)
    {
      in[c] += w * nbRho[c] * std::exp(-0.5 * ds * (sigmaHere[c] + nbSigma[c]));
    }
  }
  for (int c = 0; c < nc; ++c)
  {
    rho[nc * id + c] = static_cast<float>(in[c]);
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
  rho.assign(static_cast<size_t>(grid.Geometry.NumberOfPoints()) * grid.Channels, 1.0f);
  const auto order = VisitingOrder(grid.Geometry, light);
  const bool directional = light.Kind == LightKind::Directional;
  const Vec3 d = light.Direction();
  for (int k : order[2])
  {
    for (int j : order[1])
    {
      for (int i : order[0])
      {
        UpwindPoint(grid, directional, d, light.Position, i, j, k, rho);
      }
    }
  }
}

}
