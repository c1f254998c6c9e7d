// Combination of the lights and the scattering step of the tetrahedral light kernel.
#include "TetrahedralLightKernel.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>

namespace volillum
{

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

namespace
{
// A 64-bit mix of a point's coordinates (their bits): the pseudo-random rank of the
// colouring order.
std::uint64_t CoordinateHash(const double* x)
{
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (int a = 0; a < 3; ++a)
  {
    std::uint64_t bits;
    std::memcpy(&bits, x + a, sizeof bits);
    h ^= bits + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 29;
  }
  return h;
}

// The order in which ColorVertices colours the vertices: by a hash of their coordinates, then
// the coordinates, then the ids of coincident vertices.
std::vector<int> ColoringOrder(const TetrahedralMesh& mesh)
{
  const int np = mesh.NumberOfPoints();
  const double* x = mesh.Points.data();
  std::vector<std::uint64_t> hash(np);
  vtkSMPTools::For(0, np,
    [&](int begin, int end)
    {
      for (int p = begin; p < end; ++p)
      {
        hash[p] = CoordinateHash(x + 3 * static_cast<size_t>(p));
      }
    });
  std::vector<int> visit(np);
  std::iota(visit.begin(), visit.end(), 0);
  std::sort(visit.begin(), visit.end(),
    [&hash, x](int a, int b)
    {
      if (hash[a] != hash[b])
      {
        return hash[a] < hash[b];
      }
      return std::lexicographical_compare(x + 3 * a, x + 3 * a + 3, x + 3 * b, x + 3 * b + 3) ||
        (std::equal(x + 3 * a, x + 3 * a + 3, x + 3 * b) && a < b);
    });
  return visit;
}

// One round of the colouring: each pending vertex whose earlier neighbours (by position in
// the order) all have their colours gets the smallest colour none of them has (colors: the
// number of colours used, updated); the others stay pending, in order.
void ColorReadyVertices(const TetrahedralMesh& mesh, const std::vector<int>& position,
  std::vector<int>& pending, std::vector<int>& color, int& colors)
{
  std::vector<char> taken;
  size_t waiting = 0;
  for (int p : pending)
  {
    taken.assign(colors + 1, 0);
    bool ready = true;
    for (int k = mesh.EdgeOffsets[p]; k < mesh.EdgeOffsets[p + 1] && ready; ++k)
    {
      const int q = mesh.EdgeNeighbors[k];
      if (position[q] < position[p])
      {
        ready = color[q] >= 0;
        if (ready)
        {
          // Another process's vertex may have a colour this one has not used yet.
          taken.resize(std::max(taken.size(), static_cast<size_t>(color[q]) + 2), 0);
          taken[color[q]] = 1;
        }
      }
    }
    if (!ready)
    {
      pending[waiting++] = p;
      continue;
    }
    const int c = static_cast<int>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    color[p] = c;
    colors = std::max(colors, c + 1);
  }
  pending.resize(waiting);
}

// The vertices `mine` grouped by their colours (of `colors`), in their order.
VertexColoring GroupByColor(const std::vector<int>& mine, const std::vector<int>& color, int colors)
{
  VertexColoring coloring;
  coloring.Offsets.assign(colors + 1, 0);
  // (A vertex the exchange stopped before it was coloured is left out.)
  for (int p : mine)
  {
    coloring.Offsets[color[p] + 1] += color[p] >= 0 ? 1 : 0;
  }
  std::partial_sum(coloring.Offsets.begin(), coloring.Offsets.end(), coloring.Offsets.begin());
  coloring.Order.resize(coloring.Offsets.back());
  std::vector<int> fill(coloring.Offsets.begin(), coloring.Offsets.end() - 1);
  for (int p : mine)
  {
    if (color[p] >= 0)
    {
      coloring.Order[fill[color[p]]++] = p;
    }
  }
  return coloring;
}
}

//------------------------------------------------------------------------------
VertexColoring ColorVertices(const TetrahedralMesh& mesh, const std::vector<unsigned char>* owned,
  const std::function<bool(std::vector<int>& color)>& exchange)
{
  const int np = mesh.NumberOfPoints();
  const std::vector<int> visit = ColoringOrder(mesh);
  std::vector<int> position(np);
  for (int k = 0; k < np; ++k)
  {
    position[visit[k]] = k;
  }
  // The vertices to colour here, in order; each round colours those whose earlier
  // neighbours all have their colours.
  std::vector<int> pending;
  pending.reserve(np);
  for (int p : visit)
  {
    if (!owned || (*owned)[p])
    {
      pending.push_back(p);
    }
  }
  const std::vector<int> mine = pending;
  std::vector<int> color(np, -1);
  int colors = 0;
  for (bool more = true; more;)
  {
    ColorReadyVertices(mesh, position, pending, color, colors);
    more = exchange ? exchange(color) : false;
  }
  return GroupByColor(mine, color, colors);
}

//------------------------------------------------------------------------------
void Scatter(const TetrahedralMesh& mesh, const VertexColoring& coloring,
  const std::array<double, 3>& strength, int iterations, std::vector<float>& rgb,
  const std::function<void(int color)>& afterColor)
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
      if (afterColor)
      {
        afterColor(c);
      }
    }
  }
}

}
