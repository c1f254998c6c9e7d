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
int AutomaticLevel1Iterations(const TetrahedralMesh& mesh, const Level0Grid& grid)
{
  const auto& s = grid.Geometry.Spacing;
  const double cell = std::max(s[0], std::max(s[1], s[2]));
  if (!(mesh.MeanEdgeLength > 0.0))
  {
    return 1;
  }
  return std::max(1, static_cast<int>(std::ceil(cell / mesh.MeanEdgeLength)));
}

namespace
{
// Where the light at a vertex comes from after one semi-Lagrangian step: a point of a
// tetrahedron (weights of its vertices) or a fixed value, times the transmittance of the
// walked segment.
struct Departure
{
  int Tet = -1;
  float Weights[4] = { 0, 0, 0, 0 };
  float Fixed[3] = { 1, 1, 1 };
  float Transmittance[3] = { 1, 1, 1 };
  bool Inflow = false; // the light enters the mesh at the vertex itself
};

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

// Kept whole (issue 45): the per-vertex inner loop of the level-1 solver, a walk through the
// tetrahedra toward the light; its exits (finishAtLevel0, finish) share the walk's state (dep,
// depth, the tetrahedron and distance walked), so helpers would cost a call and that state
// per vertex and step of the walk.
Departure FindDeparture(const TetrahedralMesh& mesh, const std::vector<float>& extinction, int nc,
  const Level0Grid& grid, const std::vector<float>& level0, int vertex, const Vec3& toLight,
  double length, bool reachesLight)
{
  Departure dep;
  const Vec3 x = PointOf(mesh.Points, vertex);
  double depth[3] = { 0.0, 0.0, 0.0 };
  // The level-0 light at distance t toward the light: outside the mesh where the walk left
  // it, anywhere where the walk gave up.
  const auto finishAtLevel0 = [&](double t, bool leftTheMesh)
  {
    const double q[3] = { x[0] + t * toLight[0], x[1] + t * toLight[1], x[2] + t * toLight[2] };
    if (leftTheMesh)
    {
      SampleOutside(grid, level0, q, dep.Fixed);
    }
    else
    {
      TrilinearSample(grid.Geometry, level0.data(), nc, q, dep.Fixed);
    }
  };
  const auto finish = [&]()
  {
    for (int c = 0; c < nc; ++c)
    {
      dep.Transmittance[c] = static_cast<float>(std::exp(-depth[c]));
    }
    return dep;
  };

  // Start in the tetrahedron around the vertex that the direction enters.
  double best = 0.0;
  int tet = EntryTetrahedron(mesh, vertex, toLight, best);
  const double tolerance = GeometricTolerance / std::max(mesh.MeanEdgeLength, 1e-300);
  if (tet < 0 || best < -tolerance)
  {
    finishAtLevel0(0.0, true); // a boundary vertex the light enters the mesh at
    dep.Inflow = true;
    return finish();
  }

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
    if (ends)
    {
      if (reachesLight)
      {
        return finish(); // Fixed stays 1: the light itself
      }
      double sum = 0.0;
      for (int i = 0; i < 4; ++i)
      {
        bEnd[i] = std::max(bEnd[i], 0.0);
        sum += bEnd[i];
      }
      dep.Tet = tet;
      for (int i = 0; i < 4; ++i)
      {
        dep.Weights[i] = static_cast<float>(bEnd[i] / sum);
      }
      return finish();
    }
    t0 += dt;
    const int next = mesh.Neighbors[4 * tet + face];
    if (next < 0)
    {
      finishAtLevel0(t0, true); // left the mesh: the level-0 solution carries the rest
      return finish();
    }
    tet = next;
  }
  finishAtLevel0(t0, false);
  return finish();
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

// Every vertex's departure point for steps of length s toward the light.
//
// Interior vertices take the steps, and so do vertices on a face without a neighbour where
// the light enters the mesh there (their value is the light outside: the inflow boundary);
// the other boundary vertices (the light has crossed the mesh to them) keep the level-0
// light. A semi-Lagrangian step would interpolate the level-0 light linearly across the
// tetrahedra upstream, worse than level 0 itself where they are larger than its cells (on a
// box of 10-unit tetrahedra under a 1.3-unit level-0 grid, 0.14 RMS relative to the exact
// transmittance on the faces the light leaves through instead of 0.04).
std::vector<Departure> FindDepartures(const TetrahedralMesh& mesh,
  const std::vector<float>& extinction, const Level0Grid& grid, const std::vector<float>& level0,
  const LightState& light, double s)
{
  const int np = mesh.NumberOfPoints();
  const int nc = grid.Channels;
  std::vector<Departure> departures(np);
  vtkSMPTools::For(0, np,
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
        const bool reachesLight = inc.Distance <= s;
        departures[p] = FindDeparture(mesh, extinction, nc, grid, level0, p, inc.ToLight,
          reachesLight ? inc.Distance : s, reachesLight);
      }
    });
  return departures;
}

// One semi-Lagrangian step: each stepping vertex's light (next) from the light at its departure
// point (rho interpolated there, or fixed) times the transmittance to it; the others keep theirs.
void StepFromDepartures(const TetrahedralMesh& mesh, const std::vector<Departure>& departures,
  int nc, const std::vector<float>& rho, std::vector<float>& next)
{
  vtkSMPTools::For(0, mesh.NumberOfPoints(),
    [&](int begin, int end)
    {
      for (int p = begin; p < end; ++p)
      {
        float* out = next.data() + nc * static_cast<size_t>(p);
        if (!mesh.Interior[p] && !departures[p].Inflow)
        {
          std::copy_n(rho.data() + nc * static_cast<size_t>(p), nc, out);
          continue;
        }
        const Departure& dep = departures[p];
        for (int c = 0; c < nc; ++c)
        {
          float value = dep.Fixed[c];
          if (dep.Tet >= 0)
          {
            const int* v = mesh.Tets.data() + 4 * dep.Tet;
            value = 0.0f;
            for (int i = 0; i < 4; ++i)
            {
              value += dep.Weights[i] * rho[nc * static_cast<size_t>(v[i]) + c];
            }
          }
          out[c] = value * dep.Transmittance[c];
        }
      }
    });
}
}

//------------------------------------------------------------------------------
void PropagateLevel1(const TetrahedralMesh& mesh, const std::vector<float>& extinction,
  const Level0Grid& grid, const std::vector<float>& level0, const LightState& light,
  double stepLength, int iterations, std::vector<float>& rho,
  const std::function<void(std::vector<float>& rho)>& afterStep)
{
  SampleLevel0AtVertices(mesh, grid, level0, rho);
  if (iterations <= 0)
  {
    return;
  }
  const double s = stepLength > 0.0 ? stepLength : mesh.MeanEdgeLength;
  const std::vector<Departure> departures =
    FindDepartures(mesh, extinction, grid, level0, light, s);
  std::vector<float> next(rho.size());
  for (int n = 0; n < iterations; ++n)
  {
    StepFromDepartures(mesh, departures, grid.Channels, rho, next);
    rho.swap(next);
    if (afterStep)
    {
      afterStep(rho);
    }
  }
}
}
