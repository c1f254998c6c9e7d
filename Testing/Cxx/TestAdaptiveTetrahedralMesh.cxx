// Tests of vtkAdaptiveTetrahedralMesh (CGAL Mesh_3): a ball from a distance image is
// meshed with valid, conforming tetrahedra of the right total volume, the image's scalars
// come along, and images it cannot mesh are errors.
#include "IlluminationTestUtilities.h"
#include "vtkAdaptiveTetrahedralMesh.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using volillumtest::ErrorCounter;

namespace
{
// Radius minus distance to the centre of a 32^3 image: positive inside a ball of radius 10.
vtkSmartPointer<vtkImageData> Ball()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(32, 32, 32);
  vtkNew<vtkFloatArray> values;
  values->SetName("Distance");
  values->SetNumberOfTuples(32 * 32 * 32);
  for (vtkIdType id = 0; id < values->GetNumberOfTuples(); ++id)
  {
    const double p[3] = { id % 32 - 15.5, (id / 32) % 32 - 15.5, id / 1024 - 15.5 };
    values->SetValue(id, static_cast<float>(10.0 - vtkMath::Norm(p)));
  }
  image->GetPointData()->SetScalars(values);
  return image;
}
}

TEST(AdaptiveTetrahedralMesh, BallIsMeshedWithValidConformingTetrahedra)
{
  auto image = Ball();
  vtkNew<vtkAdaptiveTetrahedralMesh> mesher;
  mesher->SetInputData(image);
  mesher->SetIsoValue(0.0);
  mesher->SetCellSize(2.0);
  mesher->SetFacetDistance(0.15);
  mesher->Update();
  vtkUnstructuredGrid* grid = mesher->GetOutput();
  ASSERT_GT(grid->GetNumberOfCells(), 500);
  const auto mesh = volillumtest::SummarizeTetrahedra(grid);
  EXPECT_TRUE(mesh.AllTetrahedra);
  EXPECT_TRUE(mesh.Positive == 0 || mesh.Negative == 0) << mesh.Positive << " / " << mesh.Negative;
  EXPECT_LE(mesh.MostCellsPerFace, 2);
  const double total = mesh.TotalVolume;
  const double ball = 4.0 / 3.0 * vtkMath::Pi() * 1000.0;
  std::cout << grid->GetNumberOfCells() << " tetrahedra, volume " << total << " (ball " << ball
            << ")" << std::endl;
  // Boundary facets lie inside the sphere, at most FacetDistance from it.
  EXPECT_LE(total, ball);
  EXPECT_GE(total, ball - 0.15 * 4.0 * vtkMath::Pi() * 100.0);
  // The distance values came along: each point's value is its distance inside the ball
  // (away from the centre, where the distance has a kink trilinear interpolation rounds).
  vtkDataArray* carried = grid->GetPointData()->GetScalars();
  ASSERT_NE(carried, nullptr);
  EXPECT_STREQ(carried->GetName(), "Distance");
  double worst = 0.0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    const double q[3] = { p[0] - 15.5, p[1] - 15.5, p[2] - 15.5 };
    if (vtkMath::Norm(q) > 3.0)
    {
      worst = std::max(worst, std::abs(carried->GetTuple1(i) - (10.0 - vtkMath::Norm(q))));
    }
  }
  EXPECT_LE(worst, 0.1);
}

TEST(AdaptiveTetrahedralMesh, MeshingDoesNotDependOnTheImageScale)
{
  // The ball at spacing 1 and at extreme spacings and origins (sizes given in proportion)
  // gives the same mesh, scaled: CGAL sees the image at unit scale.
  auto mesh = [](double spacing, double origin)
  {
    auto image = Ball();
    image->SetSpacing(spacing, spacing, spacing);
    image->SetOrigin(origin, -origin, 0.0);
    vtkNew<vtkAdaptiveTetrahedralMesh> mesher;
    mesher->SetInputData(image);
    mesher->SetIsoValue(0.0);
    mesher->SetCellSize(2.0 * spacing);
    mesher->SetFacetDistance(0.15 * spacing);
    mesher->Update();
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    grid->ShallowCopy(mesher->GetOutput());
    return grid;
  };
  auto reference = mesh(1.0, 0.0);
  for (const double spacing : { 1e-30, 1e20 })
  {
    const double origin = 1e5 * spacing;
    auto scaled = mesh(spacing, origin);
    ASSERT_EQ(scaled->GetNumberOfCells(), reference->GetNumberOfCells()) << spacing;
    ASSERT_EQ(scaled->GetNumberOfPoints(), reference->GetNumberOfPoints()) << spacing;
    double worst = 0.0;
    for (vtkIdType i = 0; i < reference->GetNumberOfPoints(); ++i)
    {
      const double* p = reference->GetPoint(i);
      const double* q = scaled->GetPoint(i);
      const double expected[3] = { origin + spacing * p[0], -origin + spacing * p[1],
        spacing * p[2] };
      for (int a = 0; a < 3; ++a)
      {
        worst = std::max(worst, std::abs(q[a] - expected[a]) / spacing);
      }
    }
    std::cout << "spacing " << spacing << ": largest point difference " << worst << " cells"
              << std::endl;
    EXPECT_LE(worst, 1e-6) << spacing;
  }
}

TEST(AdaptiveTetrahedralMesh, ImagesItCannotMeshAreErrors)
{
  vtkNew<vtkImageData> empty3D;
  empty3D->SetDimensions(8, 8, 8);
  auto ball = Ball();
  // An empty image, an iso-value above the data and a cell size that would ask for far too
  // many tetrahedra (refused before meshing).
  for (int trial = 0; trial < 3; ++trial)
  {
    vtkNew<vtkAdaptiveTetrahedralMesh> mesher;
    vtkNew<ErrorCounter> errors;
    mesher->AddObserver(vtkCommand::ErrorEvent, errors);
    mesher->SetInputData(trial == 0 ? empty3D.Get() : ball.Get());
    mesher->SetIsoValue(trial == 1 ? 50.0 : 0.0); // the ball's values stay below 50
    mesher->SetCellSize(trial == 2 ? 1e-4 : 0.0);
    mesher->Update();
    EXPECT_EQ(errors->Count, 1);
    std::cout << errors->LastMessage << std::endl;
    EXPECT_EQ(mesher->GetOutput()->GetNumberOfCells(), 0);
  }
}
