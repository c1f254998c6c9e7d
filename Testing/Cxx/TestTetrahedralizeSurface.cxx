// Tests of vtkTetrahedralizeSurface (TetGen): valid, conforming meshes that fill the
// surface exactly and respect the volume bound; open and self-intersecting surfaces are
// errors.
#include "IlluminationTestUtilities.h"
#include "vtkTetrahedralizeSurface.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkMassProperties.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

using volillumtest::ErrorCounter;

namespace
{
vtkSmartPointer<vtkPolyData> Sphere(double x, double radius)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(x, 0, 0);
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(16);
  sphere->Update();
  return sphere->GetOutput();
}

double SignedVolume(vtkUnstructuredGrid* grid, vtkIdType cell)
{
  vtkIdType n;
  const vtkIdType* ids;
  grid->GetCellPoints(cell, n, ids);
  double p[4][3];
  for (int i = 0; i < 4; ++i)
  {
    grid->GetPoint(ids[i], p[i]);
  }
  double a[3], b[3], c[3];
  for (int k = 0; k < 3; ++k)
  {
    a[k] = p[1][k] - p[0][k];
    b[k] = p[2][k] - p[0][k];
    c[k] = p[3][k] - p[0][k];
  }
  return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0])) /
    6.0;
}
}

TEST(TetrahedralizeSurface, MeshIsValidConformingAndFillsTheSurface)
{
  auto surface = Sphere(0, 1.0);
  vtkNew<vtkTetrahedralizeSurface> mesher;
  mesher->SetInputData(surface);
  mesher->SetMaximumVolume(0.002);
  mesher->Update();
  vtkUnstructuredGrid* grid = mesher->GetOutput();
  ASSERT_GT(grid->GetNumberOfCells(), 100);

  double total = 0.0;
  int positive = 0, negative = 0;
  double largest = 0.0;
  std::map<std::array<vtkIdType, 3>, int> faces;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(grid->GetCellType(c), VTK_TETRA);
    const double v = SignedVolume(grid, c);
    (v > 0 ? positive : negative)++;
    total += std::abs(v);
    largest = std::max(largest, std::abs(v));
    vtkIdType n;
    const vtkIdType* ids;
    grid->GetCellPoints(c, n, ids);
    for (int skip = 0; skip < 4; ++skip)
    {
      std::array<vtkIdType, 3> face;
      int k = 0;
      for (int i = 0; i < 4; ++i)
      {
        if (i != skip)
        {
          face[k++] = ids[i];
        }
      }
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
  }
  // Every tetrahedron has volume, all with the same orientation.
  EXPECT_TRUE(positive == 0 || negative == 0);
  EXPECT_LE(largest, 0.002 * (1 + 1e-9));
  // Conforming: a face belongs to one tetrahedron (boundary) or two (interior).
  int boundary = 0;
  for (const auto& f : faces)
  {
    EXPECT_LE(f.second, 2);
    boundary += f.second == 1 ? 1 : 0;
  }
  EXPECT_GE(boundary, surface->GetNumberOfPolys());
  // The tetrahedra fill exactly the polyhedron the surface encloses.
  vtkNew<vtkMassProperties> mass;
  mass->SetInputData(surface);
  mass->Update();
  std::cout << grid->GetNumberOfCells() << " tetrahedra, volume " << total << " vs "
            << mass->GetVolume() << std::endl;
  EXPECT_NEAR(total, mass->GetVolume(), 1e-9 * mass->GetVolume());
}

TEST(TetrahedralizeSurface, OpenAndSelfIntersectingSurfacesAreErrors)
{
  // A sphere with one triangle removed.
  auto sphere = Sphere(0, 1.0);
  vtkNew<vtkPolyData> open;
  open->SetPoints(sphere->GetPoints());
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 1; c < sphere->GetNumberOfPolys(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    sphere->GetPolys()->GetCellAtId(c, n, ids);
    polys->InsertNextCell(n, ids);
  }
  open->SetPolys(polys);
  // Two overlapping spheres.
  vtkNew<vtkAppendPolyData> overlapping;
  overlapping->AddInputData(Sphere(0, 1.0));
  overlapping->AddInputData(Sphere(0.8, 1.0));
  overlapping->Update();
  for (vtkPolyData* bad : { open.Get(), overlapping->GetOutput() })
  {
    vtkNew<vtkTetrahedralizeSurface> mesher;
    vtkNew<ErrorCounter> errors;
    mesher->AddObserver(vtkCommand::ErrorEvent, errors);
    mesher->SetInputData(bad);
    mesher->Update();
    EXPECT_EQ(errors->Count, 1);
    std::cout << errors->LastMessage << std::endl;
    EXPECT_EQ(mesher->GetOutput()->GetNumberOfCells(), 0);
  }
}
