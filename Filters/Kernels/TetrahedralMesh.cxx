// Mesh preparation of the tetrahedral light kernel (TetrahedralLightKernel.h).
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
// Tetrahedra with |volume| <= 1e-9 x (longest edge)^3 are dropped: the determinant of their
// edge vectors (6 x volume) is at most DegenerateDeterminant x (longest edge)^3.
constexpr double DegenerateDeterminant = 6e-9;

// The usable tetrahedra, positively oriented: those with valid point ids and a non-degenerate
// volume (in parallel), then compacted in their order (counting the dropped and
// reoriented ones).
void KeepUsableTetrahedra(const std::vector<long long>& tets, long long own, TetrahedralMesh& mesh)
{
  const long long nPoints = mesh.NumberOfPoints();
  const int nTets = static_cast<int>(tets.size() / 4);
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
        if (!std::isfinite(det) ||
          std::abs(det) <= DegenerateDeterminant * longest * longest * longest)
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
    if (own < 0 || t < own)
    {
      ++mesh.OwnTets;
    }
  }
}

// The tetrahedra around each point.
void LinkPointsToTetrahedra(TetrahedralMesh& mesh)
{
  const int np = mesh.NumberOfPoints();
  const int usable = mesh.NumberOfTets();
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
}

// Face neighbours: the other tetrahedron around the face's first vertex that holds all
// three of its vertices.
void FindFaceNeighbors(TetrahedralMesh& mesh)
{
  const int usable = mesh.NumberOfTets();
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
}

// Mesh neighbours of each point (two passes: count, then fill), the mean edge length and
// the scattering weights (mean edge / length)^2.
void FindEdgeNeighbors(TetrahedralMesh& mesh)
{
  const int np = mesh.NumberOfPoints();
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
      mesh.EdgeWeights[k] = static_cast<float>(1.0 / std::max(len2, 1e-300));
      lengthSum += std::sqrt(len2);
      ++edges;
    }
  }
  // The weights are those of a mean edge of 1 until SetMeanEdgeLength scales them.
  mesh.MeanEdgeLength = 1.0;
  SetMeanEdgeLength(mesh, lengthSum / static_cast<double>(std::max<long long>(edges, 1)));
}

// Bounds of the points used by an own tetrahedron.
void ComputeBounds(TetrahedralMesh& mesh)
{
  for (int a = 0; a < 3; ++a)
  {
    mesh.Bounds[2 * a] = std::numeric_limits<double>::max();
    mesh.Bounds[2 * a + 1] = -std::numeric_limits<double>::max();
  }
  for (size_t k = 0; k < 4 * static_cast<size_t>(mesh.OwnTets); ++k)
  {
    const int id = mesh.Tets[k];
    for (int a = 0; a < 3; ++a)
    {
      mesh.Bounds[2 * a] = std::min(mesh.Bounds[2 * a], mesh.Points[3 * id + a]);
      mesh.Bounds[2 * a + 1] = std::max(mesh.Bounds[2 * a + 1], mesh.Points[3 * id + a]);
    }
  }
}
}

//------------------------------------------------------------------------------
bool BuildTetrahedralMesh(std::vector<double> points, const std::vector<long long>& tets,
  TetrahedralMesh& mesh, std::string& error, long long own)
{
  mesh = TetrahedralMesh();
  if (static_cast<long long>(points.size() / 3) >= std::numeric_limits<int>::max() ||
    static_cast<long long>(tets.size() / 4) >= std::numeric_limits<int>::max())
  {
    error = "the mesh has more than 2^31 points or tetrahedra";
    return false;
  }
  mesh.Points = std::move(points);
  KeepUsableTetrahedra(tets, own, mesh);
  if (mesh.NumberOfTets() == 0 && own < 0)
  {
    error = "the mesh has no tetrahedron with a non-zero volume";
    return false;
  }
  LinkPointsToTetrahedra(mesh);
  FindFaceNeighbors(mesh);
  FindEdgeNeighbors(mesh);
  ComputeBounds(mesh);
  return true;
}

//------------------------------------------------------------------------------
void SetMeanEdgeLength(TetrahedralMesh& mesh, double mean)
{
  // A weight is (mean edge / length)^2: scaled by the square of the ratio of the means.
  const double ratio = mean / mesh.MeanEdgeLength;
  const double factor = std::isfinite(ratio) ? ratio * ratio : 1.0;
  for (float& w : mesh.EdgeWeights)
  {
    w = static_cast<float>(factor * w);
  }
  mesh.MeanEdgeLength = mean;
}

}
