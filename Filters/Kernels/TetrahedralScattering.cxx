// Combination of the lights and the scattering step of the tetrahedral light kernel.
#include "TetrahedralLightKernel.h"

#include "vtkSMPTools.h"

#include <algorithm>
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
