// Tests of vtkTetrahedralizeSurface (TetGen): valid, conforming meshes that fill the
// surface exactly and respect the volume bound; open, self-intersecting, flat and
// non-finite surfaces and absurd volume bounds are errors.
#include "IlluminationTestUtilities.h"
#include "vtkTetrahedralizeSurface.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkMassProperties.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>

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

  const auto mesh = volillumtest::SummarizeTetrahedra(grid);
  EXPECT_TRUE(mesh.AllTetrahedra);
  // Every tetrahedron has volume, all with the same orientation.
  EXPECT_TRUE(mesh.Positive == 0 || mesh.Negative == 0);
  EXPECT_LE(mesh.LargestVolume, 0.002 * (1 + 1e-9));
  // Conforming: a face belongs to one tetrahedron (boundary) or two (interior).
  EXPECT_LE(mesh.MostCellsPerFace, 2);
  EXPECT_GE(mesh.BoundaryFaces, surface->GetNumberOfPolys());
  // The tetrahedra fill exactly the polyhedron the surface encloses.
  vtkNew<vtkMassProperties> mass;
  mass->SetInputData(surface);
  mass->Update();
  std::cout << grid->GetNumberOfCells() << " tetrahedra, volume " << mesh.TotalVolume << " vs "
            << mass->GetVolume() << std::endl;
  EXPECT_NEAR(mesh.TotalVolume, mass->GetVolume(), 1e-9 * mass->GetVolume());
}

TEST(TetrahedralizeSurface, SurfacesItCannotMeshAreErrors)
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
  // The sphere squashed flat (closed, but enclosing no volume), and one with a NaN point:
  // TetGen would abort the process on either.
  vtkNew<vtkPolyData> flat;
  flat->DeepCopy(sphere);
  vtkNew<vtkPolyData> nan;
  nan->DeepCopy(sphere);
  for (vtkIdType p = 0; p < flat->GetNumberOfPoints(); ++p)
  {
    double x[3];
    flat->GetPoint(p, x);
    flat->GetPoints()->SetPoint(p, x[0], x[1], 0.0);
  }
  nan->GetPoints()->SetPoint(5, std::nan(""), 0.0, 0.0);
  // A volume bound that would ask for about 4e9 tetrahedra (refused before meshing).
  struct Case
  {
    vtkPolyData* Surface;
    double MaximumVolume;
  };
  for (const Case& bad : { Case{ open, 0.0 }, Case{ overlapping->GetOutput(), 0.0 },
         Case{ flat, 0.0 }, Case{ nan, 0.0 }, Case{ sphere, 1e-9 } })
  {
    vtkNew<vtkTetrahedralizeSurface> mesher;
    vtkNew<ErrorCounter> errors;
    mesher->AddObserver(vtkCommand::ErrorEvent, errors);
    mesher->SetInputData(bad.Surface);
    mesher->SetMaximumVolume(bad.MaximumVolume);
    mesher->Update();
    EXPECT_EQ(errors->Count, 1);
    std::cout << errors->LastMessage << std::endl;
    EXPECT_EQ(mesher->GetOutput()->GetNumberOfCells(), 0);
  }
}
