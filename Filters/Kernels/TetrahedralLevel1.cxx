// Level 1 of the tetrahedral light kernel: semi-Lagrangian steps on the tetrahedra.
#include "TetrahedralLightKernel.h"

#include "TetrahedralGeometry.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volillum
{

using namespace tetrahedral;

//------------------------------------------------------------------------------
int AutomaticLevel1Iterations(const TetrahedralMesh& mesh, const GridGeometry& level0)
{
  const auto& s = level0.Spacing;
  const double cell = std::max(s[0], std::max(s[1], s[2]));
  if (!(mesh.MeanEdgeLength > 0.0))
  {
    return 1;
  }
  return std::max(1, static_cast<int>(std::ceil(Level1Cells * cell / mesh.MeanEdgeLength)));
}

//------------------------------------------------------------------------------
double Level1Length(const TetrahedralMesh& mesh, const GridGeometry& level0, int iterations)
{
  return (iterations < 0 ? AutomaticLevel1Iterations(mesh, level0) : iterations) *
    mesh.MeanEdgeLength;
}

namespace
{
constexpr int MaximumWalk = 512;

// The tetrahedron around the vertex that the direction enters: the one whose barycentric
// coordinates of the other vertices decrease least along it (best: that smallest rate).
int EntryTetrahedron(const TetrahedralMesh& mesh, int vertex, const Vec3& direction, double& best)
{
  int tet = -1;
  best = -std::numeric_limits<double>::infinity();
  for (int k = mesh.PointTetOffsets[vertex]; k < mesh.PointTetOffsets[vertex + 1]; ++k)
  {
    const int t = mesh.PointTets[k];
    const Barycentric frame(mesh, t);
    double db[4];
    frame.Evaluate(direction, true, db);
    double score = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i)
    {
      if (mesh.Tets[4 * t + i] != vertex)
      {
        score = std::min(score, db[i]);
      }
    }
    if (score > best)
    {
      best = score;
      tet = t;
    }
  }
  return tet;
}

// Adds the optical depth of a segment of length dt inside the tetrahedron of vertices v,
// from barycentric coordinates b to bEnd: the trapezoid rule, exact for the linear extinction.
void AddSegmentDepth(const std::vector<float>& extinction, int nc, const int* v, const double b[4],
  const double bEnd[4], double dt, double depth[3])
{
  for (int c = 0; c < nc; ++c)
  {
    double s0 = 0.0, s1 = 0.0;
    for (int i = 0; i < 4; ++i)
    {
      const double sigma = extinction[nc * static_cast<size_t>(v[i]) + c];
      s0 += b[i] * sigma;
      s1 += bEnd[i] * sigma;
    }
    depth[c] += 0.5 * dt * (std::max(s0, 0.0) + std::max(s1, 0.0));
  }
}

// The light arriving at q from outside the mesh (q on its boundary): the level-0 solution
// interpolated from the blank corners of the grid cell around q alone. Corners inside the mesh
// hold light already attenuated by up to a cell of material, which would darken the lit
// boundary by an amount that depends on where the boundary cuts the grid: scallops along a
// curved surface. A cell without a blank corner (the boundary on a face of the grid, or thinner
// than a cell) is interpolated whole.
void SampleOutside(
  const Level0Grid& grid, const std::vector<float>& level0, const double q[3], float* out)
{
  const auto& g = grid.Geometry;
  const int nc = grid.Channels;
  const TrilinearCell cell = CellAtPosition(g, q);
  const long long nx = g.Dimensions[0];
  const long long nxy = nx * g.Dimensions[1];
  double sum[3] = { 0.0, 0.0, 0.0 };
  double weightSum = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    int index[3];
    double weight = 1.0;
    for (int a = 0; a < 3; ++a)
    {
      const int upper = (corner >> a) & 1;
      index[a] = std::min(cell.Index[a] + upper, g.Dimensions[a] - 1);
      weight *= upper ? cell.Fraction[a] : 1.0 - cell.Fraction[a];
    }
    const long long id = index[0] + index[1] * nx + index[2] * nxy;
    if (weight <= 0.0 || grid.Inside[id])
    {
      continue;
    }
    weightSum += weight;
    for (int c = 0; c < nc; ++c)
    {
      sum[c] += weight * level0[nc * id + c];
    }
  }
  if (weightSum <= 0.0)
  {
    TrilinearSample(g, level0.data(), nc, q, out);
    return;
  }
  for (int c = 0; c < nc; ++c)
  {
    out[c] = static_cast<float>(sum[c] / weightSum);
  }
}

// The light at a vertex from the level-0 light `length` away toward the light: the walk through
// the tetrahedra toward it (from `tet`, the one around the vertex the direction enters) with the
// exact optical depth of the piecewise-linear extinction along it, and the level-0 light where
// the walk ends (1 where it reaches the light) or leaves the mesh. Kept whole (issue 45): the
// per-vertex inner loop of the level-1 solver, whose exits share the walk's state.
void WalkTowardLight(const TetrahedralMesh& mesh, const std::vector<float>& extinction, int nc,
  const Level0Grid& grid, const std::vector<float>& level0, int vertex, int tet,
  const Vec3& toLight, double length, bool reachesLight, float* out)
{
  const Vec3 x = PointOf(mesh.Points, vertex);
  double depth[3] = { 0.0, 0.0, 0.0 };
  float arriving[3] = { 1.0f, 1.0f, 1.0f };
  bool atLight = false;
  double t0 = 0.0;
  for (int step = 0; step < MaximumWalk; ++step)
  {
    const Barycentric frame(mesh, tet);
    const int* v = mesh.Tets.data() + 4 * tet;
    double b[4], db[4];
    frame.Evaluate(
      { { x[0] + t0 * toLight[0], x[1] + t0 * toLight[1], x[2] + t0 * toLight[2] } }, false, b);
    frame.Evaluate(toLight, true, db);
    double tExit = std::numeric_limits<double>::infinity();
    int face = -1;
    for (int i = 0; i < 4; ++i)
    {
      if (db[i] < 0.0)
      {
        const double ti = std::max(0.0, b[i]) / -db[i];
        if (ti < tExit)
        {
          tExit = ti;
          face = i;
        }
      }
    }
    const double remaining = length - t0;
    const bool ends = tExit >= remaining;
    const double dt = ends ? remaining : tExit;
    double bEnd[4];
    for (int i = 0; i < 4; ++i)
    {
      bEnd[i] = b[i] + dt * db[i];
    }
    AddSegmentDepth(extinction, nc, v, b, bEnd, dt, depth);
    t0 += dt;
    if (ends && reachesLight)
    {
      atLight = true; // arriving stays 1: the light itself
      break;
    }
    if (ends || mesh.Neighbors[4 * tet + face] < 0)
    {
      break;
    }
    tet = mesh.Neighbors[4 * tet + face];
  }
  // Where the walk ended, left the mesh or gave up (a step length far above the
  // tetrahedra's): level 0 carries the rest.
  if (!atLight)
  {
    const double q[3] = { x[0] + t0 * toLight[0], x[1] + t0 * toLight[1], x[2] + t0 * toLight[2] };
    TrilinearSample(grid.Geometry, level0.data(), nc, q, arriving);
  }
  for (int c = 0; c < nc; ++c)
  {
    out[c] = static_cast<float>(arriving[c] * std::exp(-depth[c]));
  }
}

// The level-0 light at the mesh's vertices (rho: Channels values a vertex).
void SampleLevel0AtVertices(const TetrahedralMesh& mesh, const Level0Grid& grid,
  const std::vector<float>& level0, std::vector<float>& rho)
{
  const int np = mesh.NumberOfPoints();
  const int nc = grid.Channels;
  rho.resize(static_cast<size_t>(np) * nc);
  vtkSMPTools::For(0, np,
    [&](int begin, int end)
    {
      for (int p = begin; p < end; ++p)
      {
        TrilinearSample(grid.Geometry, level0.data(), nc,
          mesh.Points.data() + 3 * static_cast<size_t>(p),
          rho.data() + nc * static_cast<size_t>(p));
      }
    });
}

}

//------------------------------------------------------------------------------
void PropagateLevel1(const TetrahedralMesh& mesh, const std::vector<float>& extinction,
  const Level0Grid& grid, const std::vector<float>& level0, const LightState& light,
  double stepLength, int iterations, std::vector<float>& rho,
  const std::function<void(std::vector<float>& rho)>& exchange)
{
  SampleLevel0AtVertices(mesh, grid, level0, rho);
  if (iterations <= 0)
  {
    return;
  }
  const double length = iterations * (stepLength > 0.0 ? stepLength : mesh.MeanEdgeLength);
  const double tolerance = GeometricTolerance / std::max(mesh.MeanEdgeLength, 1e-300);
  const int nc = grid.Channels;
  vtkSMPTools::For(0, mesh.NumberOfPoints(),
    [&](int begin, int end)
    {
      for (int p = begin; p < end; ++p)
      {
        if (mesh.PointTetOffsets[p] == mesh.PointTetOffsets[p + 1])
        {
          continue; // in no tetrahedron: the level-0 light
        }
        const Incidence inc =
          ComputeIncidence(light, mesh.Points.data() + 3 * static_cast<size_t>(p));
        double best = 0.0;
        const int tet = EntryTetrahedron(mesh, p, inc.ToLight, best);
        float* out = rho.data() + nc * static_cast<size_t>(p);
        if (tet < 0 || best < -tolerance)
        {
          // A boundary vertex the light enters the mesh at: the light outside.
          SampleOutside(grid, level0, mesh.Points.data() + 3 * static_cast<size_t>(p), out);
        }
        else
        {
          const bool reachesLight = inc.Distance <= length;
          WalkTowardLight(mesh, extinction, nc, grid, level0, p, tet, inc.ToLight,
            reachesLight ? inc.Distance : length, reachesLight, out);
        }
      }
    });
  if (exchange)
  {
    exchange(rho);
  }
}
}
