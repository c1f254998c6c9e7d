// Inputs as simulations and scanners write them: scalars as cell data, multi-component
// arrays, quadratic cells and images with a direction matrix, each checked against the same
// scene given the plain way (point scalars computed here by hand, one-component arrays,
// linear cells, an axis-aligned image).
#include "IlluminationFilterSupport.h"
#include "IlluminationTestUtilities.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"
#include "vtkUnstructuredGridIllumination.h"

#include "vtkCellData.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkMatrix3x3.h"
#include "vtkPointData.h"
#include "vtkQuadraticTetra.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <utility>

using volillumtest::DirectionalLight;
using volillumtest::ErrorCounter;
using volillumtest::PhantomScene;
using volillumtest::Result;
using volillumtest::RmsRelative;

namespace
{
// The largest absolute difference of two arrays of the same length.
double MaxDifference(vtkFloatArray* a, vtkFloatArray* b)
{
  double worst = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    worst = std::max(worst, std::abs(double(a->GetValue(i)) - b->GetValue(i)));
  }
  return worst;
}

// Illumination of an image by one of the image filters (propagation by default) with a ramp
// opacity up to rangeMax and one oblique light.
vtkSmartPointer<vtkFloatArray> LightImage(vtkImageData* image, double rangeMax,
  const std::array<double, 3>& travel, int component = -1, int* errorCount = nullptr,
  vtkSmartPointer<vtkIlluminationVolumeAlgorithm> filter =
    vtkSmartPointer<vtkMultiLightIlluminationVolume>::New())
{
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(rangeMax, 0.4);
  vtkNew<ErrorCounter> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(image);
  filter->SetOpacityFunction(otf);
  filter->SetScalarComponent(component);
  filter->AddLight(DirectionalLight(travel[0], travel[1], travel[2]));
  filter->Update();
  if (errorCount)
  {
    *errorCount = errors->Count;
  }
  return filter->GetOutput()->GetNumberOfPoints() > 0 ? Result(filter) : nullptr;
}

// The scalars of the three-spheres phantom (n points per axis) as a double array.
vtkSmartPointer<vtkDoubleArray> SphereValues(int n)
{
  auto phantom = PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, n);
  auto values = vtkSmartPointer<vtkDoubleArray>::New();
  values->DeepCopy(phantom->GetPointData()->GetScalars());
  values->SetName("density");
  return values;
}

vtkSmartPointer<vtkImageData> Image(int n)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  return image;
}

// An n^3-point image with the given spacing split into linear tetrahedra.
vtkSmartPointer<vtkUnstructuredGrid> TetrahedralBox(int n, double spacing)
{
  auto image = Image(n);
  image->SetSpacing(spacing, spacing, spacing);
  vtkNew<vtkDataSetTriangleFilter> split;
  split->SetInputData(image);
  split->TetrahedraOnlyOn();
  split->Update();
  return split->GetOutput();
}

// Illumination of a grid by the two-level solver with a ramp opacity up to (rangeMax,
// maximum), a level-0 grid of `resolution` points per axis and one directional light; null
// when the filter refused the grid (any error fails the test).
vtkSmartPointer<vtkFloatArray> LightGrid(vtkUnstructuredGrid* grid, double rangeMax, double maximum,
  int resolution, const std::array<double, 3>& travel)
{
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(rangeMax, maximum);
  vtkNew<vtkUnstructuredGridIllumination> filter;
  vtkNew<ErrorCounter> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(grid);
  filter->SetOpacityFunction(otf);
  filter->SetLevel0Resolution(resolution, resolution, resolution);
  filter->AddLight(DirectionalLight(travel[0], travel[1], travel[2]));
  filter->Update();
  EXPECT_EQ(errors->Count, 0);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), grid->GetNumberOfPoints());
  return filter->GetOutput()->GetNumberOfPoints() > 0 ? Result(filter) : nullptr;
}
}

TEST(RealWorldInputs, CellDataImageIsLitAsTheAverageOfTheCellsAroundEachPoint)
{
  // Cell (i,j,k) of a 24^3-point image holds the phantom value of point (i,j,k) of a 23^3
  // phantom; each point's value is then worked out here as the mean of its cells.
  const int n = 24;
  auto cellValues = SphereValues(n - 1);
  auto cells = Image(n);
  cells->GetCellData()->SetScalars(cellValues);
  auto points = Image(n);
  vtkNew<vtkDoubleArray> pointValues;
  pointValues->SetNumberOfTuples(points->GetNumberOfPoints());
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        double sum = 0.0;
        int count = 0;
        for (int dk = -1; dk <= 0; ++dk)
          for (int dj = -1; dj <= 0; ++dj)
            for (int di = -1; di <= 0; ++di)
            {
              const int ci = i + di, cj = j + dj, ck = k + dk;
              if (ci >= 0 && cj >= 0 && ck >= 0 && ci < n - 1 && cj < n - 1 && ck < n - 1)
              {
                sum += cellValues->GetValue(ci + (n - 1) * (cj + (n - 1) * ck));
                ++count;
              }
            }
        pointValues->SetValue(i + n * (j + n * k), sum / count);
      }
  points->GetPointData()->SetScalars(pointValues);
  const std::array<double, 3> travel{ { -0.3, -0.5, -1.0 } };
  using Make = vtkSmartPointer<vtkIlluminationVolumeAlgorithm> (*)();
  const std::pair<const char*, Make> filters[] = {
    { "propagation",
      []
      {
        return vtkSmartPointer<vtkIlluminationVolumeAlgorithm>(
          vtkSmartPointer<vtkMultiLightIlluminationVolume>::New());
      } },
    { "filtered shadows",
      []
      {
        return vtkSmartPointer<vtkIlluminationVolumeAlgorithm>(
          vtkSmartPointer<vtkFilteredVolumetricShadows>::New());
      } },
    { "reference",
      []
      {
        return vtkSmartPointer<vtkIlluminationVolumeAlgorithm>(
          vtkSmartPointer<vtkRayMarchedIllumination>::New());
      } }
  };
  for (const auto& f : filters)
  {
    int errors = 0;
    auto fromCells = LightImage(cells, 200.0, travel, -1, &errors, f.second());
    ASSERT_TRUE(fromCells) << f.first;
    EXPECT_EQ(errors, 0) << f.first;
    auto fromPoints = LightImage(points, 200.0, travel, -1, nullptr, f.second());
    const double difference = MaxDifference(fromCells, fromPoints);
    std::cout << f.first << ", cell-data image vs hand-averaged point data: largest difference "
              << difference << std::endl;
    EXPECT_LE(difference, 1e-6) << f.first;
  }
}

TEST(RealWorldInputs, DerivedScalarsAreReusedUntilTheirSourceChanges)
{
  // Point data derived from cell data are made once per change of the cell array: a light
  // edit reuses them; changed cell values give new ones, and the filter lights those.
  const int n = 12;
  auto cells = Image(n);
  cells->GetCellData()->SetScalars(SphereValues(n - 1));
  vtkDataArray* source = cells->GetCellData()->GetScalars();
  std::string error;
  const volillum::PointScalars first =
    volillum::ToPointScalars(cells, source, true, -1, volillum::PointScalars(), error);
  ASSERT_TRUE(first.Array) << error;
  const volillum::PointScalars again =
    volillum::ToPointScalars(cells, source, true, -1, first, error);
  EXPECT_EQ(again.Array.Get(), first.Array.Get());
  for (vtkIdType i = 0; i < source->GetNumberOfTuples(); ++i)
  {
    source->SetTuple1(i, 200.0 - source->GetTuple1(i));
  }
  source->Modified();
  const volillum::PointScalars changed =
    volillum::ToPointScalars(cells, source, true, -1, again, error);
  EXPECT_NE(changed.Array.Get(), first.Array.Get());
  EXPECT_NE(changed.Array->GetTuple1(0), first.Array->GetTuple1(0));

  // Through the filter: light, change the cells, light again; a fresh filter agrees.
  const std::array<double, 3> travel{ { -0.3, -0.5, -1.0 } };
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(0.0, 0.0);
  otf->AddPoint(200.0, 0.4);
  vtkNew<vtkMultiLightIlluminationVolume> filter;
  filter->SetInputData(cells);
  filter->SetOpacityFunction(otf);
  filter->AddLight(DirectionalLight(travel[0], travel[1], travel[2]));
  filter->Update();
  for (vtkIdType i = 0; i < source->GetNumberOfTuples(); ++i)
  {
    source->SetTuple1(i, 200.0 - source->GetTuple1(i));
  }
  source->Modified();
  filter->Update();
  EXPECT_LE(MaxDifference(Result(filter), LightImage(cells, 200.0, travel)), 1e-6);
}

TEST(RealWorldInputs, CellDataTetrahedraAreLitAsTheAverageOfTheCellsAroundEachPoint)
{
  // A 9^3 image split into tetrahedra; cell scalars from the phantom at each cell's first
  // point, point scalars the mean over the tetrahedra that use the point.
  const int n = 9;
  auto tets = TetrahedralBox(n, 8.0);
  auto phantom = SphereValues(n);
  vtkNew<vtkDoubleArray> cellValues;
  cellValues->SetName("density");
  cellValues->SetNumberOfTuples(tets->GetNumberOfCells());
  std::vector<double> sum(tets->GetNumberOfPoints(), 0.0);
  std::vector<int> count(tets->GetNumberOfPoints(), 0);
  for (vtkIdType c = 0; c < tets->GetNumberOfCells(); ++c)
  {
    vtkIdType np;
    const vtkIdType* ids;
    tets->GetCellPoints(c, np, ids);
    const double v = phantom->GetValue(ids[0]);
    cellValues->SetValue(c, v);
    for (vtkIdType i = 0; i < np; ++i)
    {
      sum[ids[i]] += v;
      ++count[ids[i]];
    }
  }
  vtkNew<vtkUnstructuredGrid> cellGrid, pointGrid;
  cellGrid->CopyStructure(tets);
  cellGrid->GetCellData()->SetScalars(cellValues);
  pointGrid->CopyStructure(tets);
  vtkNew<vtkDoubleArray> pointValues;
  pointValues->SetName("density");
  pointValues->SetNumberOfTuples(tets->GetNumberOfPoints());
  for (vtkIdType p = 0; p < tets->GetNumberOfPoints(); ++p)
  {
    pointValues->SetValue(p, sum[p] / count[p]);
  }
  pointGrid->GetPointData()->SetScalars(pointValues);
  const std::array<double, 3> travel{ { -0.3, -0.5, -1.0 } };
  std::vector<vtkSmartPointer<vtkFloatArray>> results;
  for (vtkUnstructuredGrid* grid : { cellGrid.Get(), pointGrid.Get() })
  {
    results.push_back(LightGrid(grid, 200.0, 0.4, 32, travel));
    ASSERT_TRUE(results.back());
  }
  const double difference = MaxDifference(results[0], results[1]);
  std::cout << "cell-data tetrahedra vs hand-averaged point data: largest difference " << difference
            << std::endl;
  EXPECT_LE(difference, 1e-6);
}

TEST(RealWorldInputs, MultiComponentScalarsUseTheMagnitudeOrTheChosenComponent)
{
  const int n = 24;
  auto values = SphereValues(n);
  const std::array<double, 3> travel{ { 0.4, -0.2, -1.0 } };
  auto plain = Image(n);
  plain->GetPointData()->SetScalars(values);
  auto reference = LightImage(plain, 200.0, travel);

  // (-v, 0, 0): the magnitude is v. (7, v, 3): component 1 is v.
  auto vectors = Image(n);
  vtkNew<vtkDoubleArray> minus, mixed;
  minus->SetNumberOfComponents(3);
  mixed->SetNumberOfComponents(3);
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    const double v = values->GetValue(i);
    minus->InsertNextTuple3(-v, 0.0, 0.0);
    mixed->InsertNextTuple3(7.0, v, 3.0);
  }
  vectors->GetPointData()->SetScalars(minus);
  EXPECT_LE(MaxDifference(LightImage(vectors, 200.0, travel, -1), reference), 1e-6);
  vectors->GetPointData()->SetScalars(mixed);
  EXPECT_LE(MaxDifference(LightImage(vectors, 200.0, travel, 1), reference), 1e-6);
  // A component the array does not have is an error and an empty output.
  int errors = 0;
  EXPECT_FALSE(LightImage(vectors, 200.0, travel, 3, &errors));
  EXPECT_EQ(errors, 1);
}

TEST(RealWorldInputs, RotatedImageIsLitInItsOwnFrame)
{
  // The same voxels with a direction matrix that turns the x axis onto y (and y onto -x),
  // lit by the light turned the same way, must get the same illumination per voxel.
  const int n = 24;
  auto values = SphereValues(n);
  auto plain = Image(n);
  plain->SetOrigin(3.0, -2.0, 1.0);
  plain->GetPointData()->SetScalars(values);
  auto rotated = Image(n);
  rotated->SetOrigin(3.0, -2.0, 1.0);
  const double turn[9] = { 0, -1, 0, 1, 0, 0, 0, 0, 1 };
  rotated->SetDirectionMatrix(turn);
  rotated->GetPointData()->SetScalars(values);
  const std::array<double, 3> travel{ { 0.5, -0.3, -1.0 } };
  const std::array<double, 3> turned{ { -travel[1], travel[0], travel[2] } };
  auto reference = LightImage(plain, 200.0, travel);
  auto lit = LightImage(rotated, 200.0, turned);
  ASSERT_TRUE(lit);
  const double difference = MaxDifference(lit, reference);
  // Without the turn the light would cross the voxels another way.
  const double unturned = MaxDifference(LightImage(rotated, 200.0, travel), reference);
  std::cout << "rotated image vs axis-aligned: largest difference " << difference
            << " (light not turned: " << unturned << ")" << std::endl;
  EXPECT_LE(difference, 1e-5);
  EXPECT_GE(unturned, 0.05);
}

TEST(RealWorldInputs, QuadraticTetrahedraAreSplitAndLit)
{
  // Quadratic tetrahedra (mid-edge nodes) of a box with a linear density; the illumination
  // at the corner nodes must agree with the same box meshed by linear tetrahedra.
  auto linear = TetrahedralBox(7, 10.0);
  const auto density = [](const double* x) { return 2.0 * x[0] + x[1] + 0.5 * x[2]; };

  vtkNew<vtkUnstructuredGrid> quadratic;
  vtkNew<vtkPoints> points;
  points->DeepCopy(linear->GetPoints());
  std::map<std::pair<vtkIdType, vtkIdType>, vtkIdType> middle;
  const auto midpoint = [&](vtkIdType a, vtkIdType b)
  {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    auto found = middle.find(key);
    if (found != middle.end())
    {
      return found->second;
    }
    double pa[3], pb[3];
    points->GetPoint(a, pa);
    points->GetPoint(b, pb);
    const vtkIdType id =
      points->InsertNextPoint(0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2]));
    middle[key] = id;
    return id;
  };
  quadratic->Allocate(linear->GetNumberOfCells());
  static const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  for (vtkIdType c = 0; c < linear->GetNumberOfCells(); ++c)
  {
    vtkIdType np;
    const vtkIdType* ids;
    linear->GetCellPoints(c, np, ids);
    vtkIdType q[10] = { ids[0], ids[1], ids[2], ids[3] };
    for (int e = 0; e < 6; ++e)
    {
      q[4 + e] = midpoint(ids[edges[e][0]], ids[edges[e][1]]);
    }
    quadratic->InsertNextCell(VTK_QUADRATIC_TETRA, 10, q);
  }
  quadratic->SetPoints(points);
  for (vtkUnstructuredGrid* grid : { linear.Get(), quadratic.Get() })
  {
    vtkNew<vtkDoubleArray> values;
    values->SetName("density");
    for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
    {
      double x[3];
      grid->GetPoint(p, x);
      values->InsertNextValue(density(x));
    }
    grid->GetPointData()->SetScalars(values);
  }
  const std::array<double, 3> travel{ { -0.2, -0.4, -1.0 } };
  std::vector<vtkSmartPointer<vtkFloatArray>> results;
  for (vtkUnstructuredGrid* grid : { linear.Get(), quadratic.Get() })
  {
    results.push_back(LightGrid(grid, 210.0, 0.3, 48, travel));
    ASSERT_TRUE(results.back());
  }
  // The corner nodes are the linear mesh's points, in the same order.
  vtkNew<vtkFloatArray> corners;
  corners->SetNumberOfComponents(3);
  for (vtkIdType p = 0; p < linear->GetNumberOfPoints(); ++p)
  {
    corners->InsertNextTuple(results[1]->GetTuple(p));
  }
  const double rms = RmsRelative(corners, results[0]);
  std::cout << "quadratic vs linear tetrahedra at the corner nodes: RMS relative " << rms
            << std::endl;
  EXPECT_LE(rms, 0.02);
}
