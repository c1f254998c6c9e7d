/**
 * @file TetrahedralGeometry.h
 * @brief Small geometric helpers shared by the tetrahedral light kernel's sources (private).
 */
#ifndef TetrahedralGeometry_h
#define TetrahedralGeometry_h

#include "TetrahedralLightKernel.h"

#include <array>
#include <vector>

namespace volillum
{
namespace tetrahedral
{
using Vec3 = std::array<double, 3>;

inline Vec3 PointOf(const std::vector<double>& points, int id)
{
  return { { points[3 * id], points[3 * id + 1], points[3 * id + 2] } };
}

inline Vec3 Sub(const Vec3& a, const Vec3& b)
{
  return { { a[0] - b[0], a[1] - b[1], a[2] - b[2] } };
}

inline double Det(const Vec3& a, const Vec3& b, const Vec3& c)
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
}

#endif
