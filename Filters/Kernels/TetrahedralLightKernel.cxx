#include "TetrahedralLightKernel.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace volillum
{

namespace
{
using Vec3 = std::array<double, 3>;

Vec3 PointOf(const std::vector<double>& points, int id)
{
  return { { points[3 * id], points[3 * id + 1], points[3 * id + 2] } };
}

Vec3 Sub(const Vec3& a, const Vec3& b)
{
  return { { a[0] - b[0], a[1] - b[1], a[2] - b[2] } };
}

double Det(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
    a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// Barycentric frame of one tetrahedron: coordinates b1..b3 = M (q - p0), b0 = 1 - sum.
struct Barycentric
{
  Vec3 P0;
  double M[3][3];

  Barycentric(const TetrahedralMesh& mesh, int tet)
  {
    const int* v = mesh.Tets.data() + 4 * tet;
    this->P0 = PointOf(mesh.Points, v[0]);
    const Vec3 e1 = Sub(PointOf(mesh.Points, v[1]), this->P0);
    const Vec3 e2 = Sub(PointOf(mesh.Points, v[2]), this->P0);
    const Vec3 e3 = Sub(PointOf(mesh.Points, v[3]), this->P0);
    const double inv = 1.0 / Det(e1, e2, e3);
    // Rows of the inverse of the matrix with columns e1 e2 e3: cross products / det.
    const Vec3 r1{ { e2[1] * e3[2] - e2[2] * e3[1], e2[2] * e3[0] - e2[0] * e3[2],
      e2[0] * e3[1] - e2[1] * e3[0] } };
    const Vec3 r2{ { e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
      e3[0] * e1[1] - e3[1] * e1[0] } };
    const Vec3 r3{ { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
      e1[0] * e2[1] - e1[1] * e2[0] } };
    for (int a = 0; a < 3; ++a)
    {
      this->M[0][a] = r1[a] * inv;
      this->M[1][a] = r2[a] * inv;
      this->M[2][a] = r3[a] * inv;
    }
  }

  // Coordinates of a point (offset = false) or the change along a direction (true).
  void Evaluate(const Vec3& q, bool direction, double b[4]) const
  {
    const Vec3 d = direction ? q : Sub(q, this->P0);
    double sum = 0.0;
    for (int r = 0; r < 3; ++r)
    {
      b[r + 1] = this->M[r][0] * d[0] + this->M[r][1] * d[1] + this->M[r][2] * d[2];
      sum += b[r + 1];
    }
    b[0] = (direction ? 0.0 : 1.0) - sum;
  }
};
}

//------------------------------------------------------------------------------
bool BuildTetrahedralMesh(std::vector<double> points, const std::vector<long long>& tets,
  TetrahedralMesh& mesh, std::string& error)
{
  mesh = TetrahedralMesh();
  const long long nPoints = static_cast<long long>(points.size() / 3);
  if (nPoints >= std::numeric_limits<int>::max() ||
    static_cast<long long>(tets.size() / 4) >= std::numeric_limits<int>::max())
  {
    error = "the mesh has more than 2^31 points or tetrahedra";
    return false;
  }
  mesh.Points = std::move(points);
  const int nTets = static_cast<int>(tets.size() / 4);

  // Orientation and degeneracy of every tetrahedron (in parallel), then compaction.
  std::vector<signed char> status(nTets, 0); // 0 drop, 1 keep, -1 keep reoriented
  vtkSMPTools::For(0, nTets,
    [&](int begin, int end)
    {
      for (int t = begin; t < end; ++t)
      {
        const long long* v = tets.data() + 4 * static_cast<size_t>(t);
        bool valid = true;
        for (int i = 0; i < 4; ++i)
        {
          valid = valid && v[i] >= 0 && v[i] < nPoints;
        }
        if (!valid)
        {
          continue;
        }
        Vec3 p[4];
        for (int i = 0; i < 4; ++i)
        {
          p[i] = PointOf(mesh.Points, static_cast<int>(v[i]));
        }
        double longest = 0.0;
        for (int i = 0; i < 4; ++i)
        {
          for (int j = i + 1; j < 4; ++j)
          {
            const Vec3 e = Sub(p[i], p[j]);
            longest = std::max(longest, e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
          }
        }
        longest = std::sqrt(longest);
        const double det = Det(Sub(p[1], p[0]), Sub(p[2], p[0]), Sub(p[3], p[0]));
        if (!std::isfinite(det) || std::abs(det) <= 6e-9 * longest * longest * longest)
        {
          continue;
        }
        status[t] = det > 0.0 ? 1 : -1;
      }
    });
  mesh.Tets.reserve(tets.size());
  for (int t = 0; t < nTets; ++t)
  {
    if (status[t] == 0)
    {
      ++mesh.Degenerate;
      continue;
    }
    const long long* v = tets.data() + 4 * static_cast<size_t>(t);
    int ids[4] = { static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]),
      static_cast<int>(v[3]) };
    if (status[t] < 0)
    {
      std::swap(ids[0], ids[1]);
      ++mesh.Inverted;
    }
    mesh.Tets.insert(mesh.Tets.end(), ids, ids + 4);
  }
  const int usable = mesh.NumberOfTets();
  if (usable == 0)
  {
    error = "the mesh has no tetrahedron with a non-zero volume";
    return false;
  }

  // Tetrahedra around each point.
  const int np = mesh.NumberOfPoints();
  mesh.PointTetOffsets.assign(np + 1, 0);
  for (int id : mesh.Tets)
  {
    ++mesh.PointTetOffsets[id + 1];
  }
  std::partial_sum(
    mesh.PointTetOffsets.begin(), mesh.PointTetOffsets.end(), mesh.PointTetOffsets.begin());
  mesh.PointTets.resize(mesh.Tets.size());
  {
    std::vector<int> fill(mesh.PointTetOffsets.begin(), mesh.PointTetOffsets.end() - 1);
    for (int t = 0; t < usable; ++t)
    {
      for (int i = 0; i < 4; ++i)
      {
        mesh.PointTets[fill[mesh.Tets[4 * t + i]]++] = t;
      }
    }
  }

  // Face neighbours: the other tetrahedron around the face's first vertex that holds all
  // three of its vertices.
  mesh.Neighbors.assign(mesh.Tets.size(), -1);
  vtkSMPTools::For(0, usable,
    [&](int begin, int end)
    {
      for (int t = begin; t < end; ++t)
      {
        const int* v = mesh.Tets.data() + 4 * t;
        for (int i = 0; i < 4; ++i)
        {
          const int a = v[(i + 1) % 4], b = v[(i + 2) % 4], c = v[(i + 3) % 4];
          for (int k = mesh.PointTetOffsets[a]; k < mesh.PointTetOffsets[a + 1]; ++k)
          {
            const int other = mesh.PointTets[k];
            if (other == t)
            {
              continue;
            }
            const int* w = mesh.Tets.data() + 4 * other;
            const auto has = [w](int id)
            { return w[0] == id || w[1] == id || w[2] == id || w[3] == id; };
            if (has(b) && has(c))
            {
              mesh.Neighbors[4 * t + i] = other;
              break;
            }
          }
        }
      }
    });

  // Interior vertices: used by a tetrahedron and on no boundary face.
  mesh.Interior.assign(np, 0);
  for (int t = 0; t < usable; ++t)
  {
    for (int i = 0; i < 4; ++i)
    {
      mesh.Interior[mesh.Tets[4 * t + i]] = 1;
    }
  }
  for (int t = 0; t < usable; ++t)
  {
    for (int i = 0; i < 4; ++i)
    {
      if (mesh.Neighbors[4 * t + i] < 0)
      {
        for (int k = 1; k < 4; ++k)
        {
          mesh.Interior[mesh.Tets[4 * t + (i + k) % 4]] = 0;
        }
      }
    }
  }

  // Mesh neighbours of each point (two passes: count, then fill) and the mean edge.
  mesh.EdgeOffsets.assign(np + 1, 0);
  const auto gather = [&mesh](int p, std::vector<int>& out)
  {
    out.clear();
    for (int k = mesh.PointTetOffsets[p]; k < mesh.PointTetOffsets[p + 1]; ++k)
    {
      const int* v = mesh.Tets.data() + 4 * mesh.PointTets[k];
      for (int i = 0; i < 4; ++i)
      {
        if (v[i] != p)
        {
          out.push_back(v[i]);
        }
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  };
  vtkSMPTools::For(0, np,
    [&](int begin, int end)
    {
      std::vector<int> local;
      for (int p = begin; p < end; ++p)
      {
        gather(p, local);
        mesh.EdgeOffsets[p + 1] = static_cast<int>(local.size());
      }
    });
  std::partial_sum(mesh.EdgeOffsets.begin(), mesh.EdgeOffsets.end(), mesh.EdgeOffsets.begin());
  mesh.EdgeNeighbors.resize(mesh.EdgeOffsets[np]);
  mesh.EdgeWeights.resize(mesh.EdgeOffsets[np]);
  vtkSMPTools::For(0, np,
    [&](int begin, int end)
    {
      std::vector<int> local;
      for (int p = begin; p < end; ++p)
      {
        gather(p, local);
        std::copy(local.begin(), local.end(), mesh.EdgeNeighbors.begin() + mesh.EdgeOffsets[p]);
      }
    });
  double lengthSum = 0.0;
  long long edges = 0;
  for (int p = 0; p < np; ++p)
  {
    const Vec3 x = PointOf(mesh.Points, p);
    for (int k = mesh.EdgeOffsets[p]; k < mesh.EdgeOffsets[p + 1]; ++k)
    {
      const Vec3 d = Sub(PointOf(mesh.Points, mesh.EdgeNeighbors[k]), x);
      const double len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      mesh.EdgeWeights[k] = static_cast<float>(len2);
      lengthSum += std::sqrt(len2);
      ++edges;
    }
  }
  mesh.MeanEdgeLength = lengthSum / static_cast<double>(std::max<long long>(edges, 1));
  const double mean2 = mesh.MeanEdgeLength * mesh.MeanEdgeLength;
  for (float& w : mesh.EdgeWeights)
  {
    w = static_cast<float>(mean2 / std::max(static_cast<double>(w), 1e-300));
  }

  for (int a = 0; a < 3; ++a)
  {
    mesh.Bounds[2 * a] = std::numeric_limits<double>::max();
    mesh.Bounds[2 * a + 1] = -std::numeric_limits<double>::max();
  }
  for (int id : mesh.Tets)
  {
    for (int a = 0; a < 3; ++a)
    {
      mesh.Bounds[2 * a] = std::min(mesh.Bounds[2 * a], mesh.Points[3 * id + a]);
      mesh.Bounds[2 * a + 1] = std::max(mesh.Bounds[2 * a + 1], mesh.Points[3 * id + a]);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
void ResampleLevel0(const TetrahedralMesh& mesh, const std::vector<float>& extinction, int channels,
  const std::array<int, 3>& dimensions, Level0Grid& grid)
{
  grid.Channels = channels;
  auto& g = grid.Geometry;
  for (int a = 0; a < 3; ++a)
  {
    g.Dimensions[a] = std::max(dimensions[a], 2);
    g.Origin[a] = mesh.Bounds[2 * a];
    const double extent = mesh.Bounds[2 * a + 1] - mesh.Bounds[2 * a];
    g.Spacing[a] = extent > 0.0 ? extent / (g.Dimensions[a] - 1) : 1.0;
  }
  const long long n = g.NumberOfPoints();
  grid.Extinction.assign(static_cast<size_t>(n) * channels, 0.0f);
  grid.Inside.assign(static_cast<size_t>(n), 0);

  // Tetrahedra bucketed by the z planes they span, so that planes fill in parallel.
  const int nz = g.Dimensions[2];
  const auto indexRange = [&g](double lo, double hi, int a, int& first, int& last)
  {
    const double eps = 1e-9;
    first = std::max(0, static_cast<int>(std::ceil((lo - g.Origin[a]) / g.Spacing[a] - eps)));
    last = std::min(
      g.Dimensions[a] - 1, static_cast<int>(std::floor((hi - g.Origin[a]) / g.Spacing[a] + eps)));
  };
  const int nTets = mesh.NumberOfTets();
  std::vector<std::array<double, 6>> boxes(nTets);
  std::vector<std::vector<int>> planes(nz);
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
    indexRange(box[4], box[5], 2, k0, k1);
    for (int k = k0; k <= k1; ++k)
    {
      planes[k].push_back(t);
    }
  }
  const long long nx = g.Dimensions[0];
  const long long nxy = nx * g.Dimensions[1];
  vtkSMPTools::For(0, nz,
    [&](int kBegin, int kEnd)
    {
      for (int k = kBegin; k < kEnd; ++k)
      {
        for (int t : planes[k])
        {
          const Barycentric frame(mesh, t);
          const int* v = mesh.Tets.data() + 4 * t;
          int j0, j1, i0, i1;
          indexRange(boxes[t][2], boxes[t][3], 1, j0, j1);
          indexRange(boxes[t][0], boxes[t][1], 0, i0, i1);
          for (int j = j0; j <= j1; ++j)
          {
            for (int i = i0; i <= i1; ++i)
            {
              double p[3];
              g.PointPosition(i, j, k, p);
              double b[4];
              frame.Evaluate({ { p[0], p[1], p[2] } }, false, b);
              if (std::min(std::min(b[0], b[1]), std::min(b[2], b[3])) < -1e-9)
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
    });
}

//------------------------------------------------------------------------------
void PropagateLevel0(const Level0Grid& grid, const LightState& light, std::vector<float>& rho)
{
  const auto& g = grid.Geometry;
  const int nc = grid.Channels;
  rho.assign(static_cast<size_t>(g.NumberOfPoints()) * nc, 1.0f);
  const bool directional = light.Kind == LightKind::Directional;
  const Vec3 d = light.Direction();
  const Vec3& p = light.Position;

  // Visiting order along each axis: nearest to the light first.
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
  const long long stride[3] = { 1, g.Dimensions[0],
    static_cast<long long>(g.Dimensions[0]) * g.Dimensions[1] };
  for (int k : order[2])
  {
    for (int j : order[1])
    {
      for (int i : order[0])
      {
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
            continue; // the light's own point keeps 1
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
  }
}

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
};

constexpr int MaximumWalk = 512;

Departure FindDeparture(const TetrahedralMesh& mesh, const std::vector<float>& extinction, int nc,
  const Level0Grid& grid, const std::vector<float>& level0, int vertex, const Vec3& toLight,
  double length, bool reachesLight)
{
  Departure dep;
  const Vec3 x = PointOf(mesh.Points, vertex);
  double depth[3] = { 0.0, 0.0, 0.0 };
  const auto finishAtLevel0 = [&](double t)
  {
    const double q[3] = { x[0] + t * toLight[0], x[1] + t * toLight[1], x[2] + t * toLight[2] };
    TrilinearSample(grid.Geometry, level0.data(), nc, q, dep.Fixed);
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
  int tet = -1;
  double best = -std::numeric_limits<double>::infinity();
  for (int k = mesh.PointTetOffsets[vertex]; k < mesh.PointTetOffsets[vertex + 1]; ++k)
  {
    const int t = mesh.PointTets[k];
    const Barycentric frame(mesh, t);
    double db[4];
    frame.Evaluate(toLight, true, db);
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
  const double tolerance = 1e-9 / std::max(mesh.MeanEdgeLength, 1e-300);
  if (tet < 0 || best < -tolerance)
  {
    finishAtLevel0(0.0); // the direction leaves the mesh right away
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
      finishAtLevel0(t0); // left the mesh: the level-0 solution carries the rest
      return finish();
    }
    tet = next;
  }
  finishAtLevel0(t0);
  return finish();
}
}

//------------------------------------------------------------------------------
void PropagateLevel1(const TetrahedralMesh& mesh, const std::vector<float>& extinction,
  const Level0Grid& grid, const std::vector<float>& level0, const LightState& light,
  double stepLength, int iterations, std::vector<float>& rho)
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
  if (iterations <= 0)
  {
    return;
  }
  const double s = stepLength > 0.0 ? stepLength : mesh.MeanEdgeLength;
  std::vector<Departure> departures(np);
  vtkSMPTools::For(0, np,
    [&](int begin, int end)
    {
      for (int p = begin; p < end; ++p)
      {
        if (!mesh.Interior[p])
        {
          continue;
        }
        const Incidence inc =
          ComputeIncidence(light, mesh.Points.data() + 3 * static_cast<size_t>(p));
        const bool reachesLight = inc.Distance <= s;
        departures[p] = FindDeparture(mesh, extinction, nc, grid, level0, p, inc.ToLight,
          reachesLight ? inc.Distance : s, reachesLight);
      }
    });
  std::vector<float> next(rho.size());
  for (int n = 0; n < iterations; ++n)
  {
    vtkSMPTools::For(0, np,
      [&](int begin, int end)
      {
        for (int p = begin; p < end; ++p)
        {
          float* out = next.data() + nc * static_cast<size_t>(p);
          if (!mesh.Interior[p])
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
    rho.swap(next);
  }
}

//------------------------------------------------------------------------------
void CombineLights(const TetrahedralMesh& mesh, const std::vector<LightState>& lights,
  const std::vector<const std::vector<float>*>& rho, int channels, std::vector<float>& rgb)
{
  const int np = mesh.NumberOfPoints();
  rgb.assign(3 * static_cast<size_t>(np), 0.0f);
  vtkSMPTools::For(0, np,
    [&](int begin, int end)
    {
      for (size_t l = 0; l < lights.size(); ++l)
      {
        if (!lights[l].On || !rho[l])
        {
          continue;
        }
        const auto radiance = lights[l].Radiance();
        const std::vector<float>& r = *rho[l];
        for (int p = begin; p < end; ++p)
        {
          const double cone = lights[l].Kind == LightKind::Spot
            ? ComputeIncidence(lights[l], mesh.Points.data() + 3 * static_cast<size_t>(p))
                .ConeFactor
            : 1.0;
          for (int c = 0; c < 3; ++c)
          {
            const float t = r[channels * static_cast<size_t>(p) + (channels == 3 ? c : 0)];
            rgb[3 * static_cast<size_t>(p) + c] += static_cast<float>(radiance[c] * cone * t);
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
VertexColoring ColorVertices(const TetrahedralMesh& mesh)
{
  const int np = mesh.NumberOfPoints();
  // Greedy colouring in the order of the vertices' coordinates (ids break ties between
  // coincident vertices): the colours, and so the Gauss-Seidel iterations of Scatter, depend
  // on the mesh's geometry, not on how its points are numbered (a grid assembled from
  // parallel pieces is lit as the serial one).
  std::vector<int> visit(np);
  std::iota(visit.begin(), visit.end(), 0);
  const double* x = mesh.Points.data();
  std::sort(visit.begin(), visit.end(),
    [x](int a, int b)
    {
      return std::lexicographical_compare(x + 3 * a, x + 3 * a + 3, x + 3 * b, x + 3 * b + 3) ||
        (std::equal(x + 3 * a, x + 3 * a + 3, x + 3 * b) && a < b);
    });
  std::vector<int> color(np, -1);
  std::vector<char> taken;
  int colors = 0;
  for (int p : visit)
  {
    taken.assign(colors + 1, 0);
    for (int k = mesh.EdgeOffsets[p]; k < mesh.EdgeOffsets[p + 1]; ++k)
    {
      const int c = color[mesh.EdgeNeighbors[k]];
      if (c >= 0)
      {
        taken[c] = 1;
      }
    }
    int c = 0;
    while (taken[c])
    {
      ++c;
    }
    color[p] = c;
    colors = std::max(colors, c + 1);
  }
  VertexColoring coloring;
  coloring.Offsets.assign(colors + 1, 0);
  for (int c : color)
  {
    ++coloring.Offsets[c + 1];
  }
  std::partial_sum(coloring.Offsets.begin(), coloring.Offsets.end(), coloring.Offsets.begin());
  coloring.Order.resize(np);
  std::vector<int> fill(coloring.Offsets.begin(), coloring.Offsets.end() - 1);
  for (int p : visit)
  {
    coloring.Order[fill[color[p]]++] = p;
  }
  return coloring;
}

//------------------------------------------------------------------------------
void Scatter(const TetrahedralMesh& mesh, const VertexColoring& coloring,
  const std::array<double, 3>& strength, int iterations, std::vector<float>& rgb)
{
  if (iterations <= 0 || (strength[0] <= 0.0 && strength[1] <= 0.0 && strength[2] <= 0.0))
  {
    return;
  }
  const std::vector<float> previous = rgb; // the right-hand side of the implicit step
  for (int n = 0; n < iterations; ++n)
  {
    for (int c = 0; c < coloring.NumberOfColors(); ++c)
    {
      vtkSMPTools::For(coloring.Offsets[c], coloring.Offsets[c + 1],
        [&](int begin, int end)
        {
          for (int k = begin; k < end; ++k)
          {
            const int p = coloring.Order[k];
            double weightSum = 0.0;
            double sum[3] = { 0.0, 0.0, 0.0 };
            for (int e = mesh.EdgeOffsets[p]; e < mesh.EdgeOffsets[p + 1]; ++e)
            {
              const double w = mesh.EdgeWeights[e];
              const float* q = rgb.data() + 3 * static_cast<size_t>(mesh.EdgeNeighbors[e]);
              weightSum += w;
              sum[0] += w * q[0];
              sum[1] += w * q[1];
              sum[2] += w * q[2];
            }
            for (int ch = 0; ch < 3; ++ch)
            {
              const double s = strength[ch];
              const size_t i = 3 * static_cast<size_t>(p) + ch;
              rgb[i] = static_cast<float>((previous[i] + s * sum[ch]) / (1.0 + s * weightSum));
            }
          }
        });
    }
  }
}

}
