#include "IlluminationFilterSupport.h"

#include "IlluminationLightList.h"
#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellDataToPointData.h"
#include "vtkCellTypes.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

namespace volillum
{

//------------------------------------------------------------------------------
void UseThreadedBackend()
{
  static const bool chosen = []
  {
    if (!std::getenv("VTK_SMP_BACKEND_IN_USE") &&
      std::string(vtkSMPTools::GetBackend()) == "Sequential")
    {
      vtkSMPTools::SetBackend("STDThread");
    }
    return true;
  }();
  (void)chosen;
}

//------------------------------------------------------------------------------
void FillSingleComponent(vtkDataArray* array, int component, vtkDataArray* out)
{
  const int components = array->GetNumberOfComponents();
  component = std::min(component, components - 1);
  vtkSMPTools::For(0, array->GetNumberOfTuples(),
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType i = begin; i < end; ++i)
      {
        double value = 0.0;
        if (component >= 0)
        {
          value = array->GetComponent(i, component);
        }
        else
        {
          for (int c = 0; c < components; ++c)
          {
            const double v = array->GetComponent(i, c);
            value += v * v;
          }
          value = std::sqrt(value);
        }
        out->SetComponent(i, 0, value);
      }
    });
  out->Modified();
}

//------------------------------------------------------------------------------
namespace
{
// Point data from a cell array: each point gets the average of the cells that use it.
vtkSmartPointer<vtkDataArray> CellToPoint(vtkDataSet* input, vtkDataArray* cells)
{
  auto structure = vtk::TakeSmartPointer(input->NewInstance());
  structure->CopyStructure(input);
  structure->GetCellData()->AddArray(cells);
  vtkNew<vtkCellDataToPointData> convert;
  convert->SetInputData(structure);
  convert->Update();
  return convert->GetOutput()->GetPointData()->GetArray(cells->GetName());
}

// One component of a multi-component array, or its magnitude for component -1.
vtkSmartPointer<vtkDataArray> SingleComponent(vtkDataArray* array, int component)
{
  auto out = vtkSmartPointer<vtkDoubleArray>::New();
  out->SetName(array->GetName());
  out->SetNumberOfTuples(array->GetNumberOfTuples());
  volillum::FillSingleComponent(array, component, out);
  return out;
}
}

//------------------------------------------------------------------------------
const char* LitArrayName(vtkAlgorithm* algorithm)
{
  vtkInformation* arrayInfo = algorithm->GetInputArrayInformation(0);
  return arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
}

//------------------------------------------------------------------------------
vtkAbstractArray* ChooseScalars(
  vtkAlgorithm* algorithm, vtkDataSet* input, bool& onCells, std::string& error)
{
  vtkInformation* arrayInfo = algorithm->GetInputArrayInformation(0);
  const char* requested = LitArrayName(algorithm);
  vtkAbstractArray* chosen = nullptr;
  onCells = false;
  if (!requested || !*requested)
  {
    chosen = input->GetPointData()->GetScalars();
    if (!chosen)
    {
      chosen = input->GetCellData()->GetScalars();
      onCells = chosen != nullptr;
    }
    if (!chosen)
    {
      error = "The input has no point or cell scalars to illuminate.";
    }
  }
  else
  {
    // The association asked for first (points unless cells are named), then the other.
    onCells = arrayInfo->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
      arrayInfo->Get(vtkDataObject::FIELD_ASSOCIATION()) == vtkDataObject::FIELD_ASSOCIATION_CELLS;
    chosen = input->GetAttributes(onCells ? vtkDataObject::CELL : vtkDataObject::POINT)
               ->GetAbstractArray(requested);
    if (!chosen)
    {
      onCells = !onCells;
      chosen = input->GetAttributes(onCells ? vtkDataObject::CELL : vtkDataObject::POINT)
                 ->GetAbstractArray(requested);
    }
    if (!chosen)
    {
      error =
        std::string("The input has no point or cell array '") + requested + "' to illuminate.";
    }
  }
  return chosen;
}

//------------------------------------------------------------------------------
PointScalars FindPointScalars(vtkAlgorithm* algorithm, vtkDataSet* input, int component,
  const PointScalars& previous, std::string& error)
{
  bool onCells = false;
  vtkAbstractArray* chosen = ChooseScalars(algorithm, input, onCells, error);
  if (!chosen)
  {
    return PointScalars();
  }
  return ToPointScalars(input, chosen, onCells, component, previous, error);
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkDataArray> CellScalarsToPoints(
  vtkDataSet* input, vtkDataArray* cells, int component, std::string& error)
{
  return ToPointScalars(input, cells, true, component, PointScalars(), error).Array;
}

//------------------------------------------------------------------------------
PointScalars ToPointScalars(vtkDataSet* input, vtkAbstractArray* chosen, bool onCells,
  int component, const PointScalars& previous, std::string& error)
{
  PointScalars found;
  const std::string name = chosen->GetName() ? chosen->GetName() : "";
  vtkDataArray* source = vtkDataArray::SafeDownCast(chosen);
  if (!source)
  {
    error = "The array '" + name + "' is not numeric; choose a numeric array.";
    return found;
  }
  const int components = source->GetNumberOfComponents();
  if (components > 1 && (component < -1 || component >= components))
  {
    std::ostringstream message;
    message << "The scalars '" << name << "' have " << components
            << " components; ScalarComponent must be -1 (magnitude) or 0 to " << components - 1
            << "; it is " << component << ".";
    error = message.str();
    return found;
  }
  if (onCells && source->GetNumberOfTuples() != input->GetNumberOfCells())
  {
    std::ostringstream message;
    message << "The cell scalars '" << name << "' have " << source->GetNumberOfTuples()
            << " values for " << input->GetNumberOfCells()
            << " cells; the dataset is inconsistent.";
    error = message.str();
    return found;
  }
  found.Array = source;
  found.Time = source->GetMTime();
  if (onCells)
  {
    // Points average the cells that use them: the cells' connectivity counts too (an image's
    // is its extent, which sizes the array). Not the dataset's own time, which the pipeline
    // advances at every update (a light edit must keep the conversion).
    auto* grid = vtkUnstructuredGrid::SafeDownCast(input);
    found.Time = std::max(found.Time, grid && grid->GetCells() ? grid->GetCells()->GetMTime() : 0);
    found.Points = input->GetNumberOfPoints();
  }
  if (components == 1 && !onCells)
  {
    return found;
  }
  found.Source = source;
  found.OnCells = onCells;
  found.Component = components > 1 ? component : -1;
  if (previous.Array && previous.Source == found.Source && previous.OnCells == onCells &&
    previous.Component == found.Component && previous.Time == found.Time &&
    previous.Points == found.Points)
  {
    return previous;
  }
  if (components > 1)
  {
    found.Array = SingleComponent(found.Array, component);
  }
  if (onCells)
  {
    found.Array = CellToPoint(input, found.Array);
  }
  return found;
}

//------------------------------------------------------------------------------
std::vector<LightState> InImageFrame(
  const std::vector<LightState>& lights, vtkMatrix3x3* direction, const double origin[3])
{
  if (!direction || direction->IsIdentity())
  {
    return lights;
  }
  vtkNew<vtkMatrix3x3> inverse;
  vtkMatrix3x3::Invert(direction, inverse);
  std::vector<LightState> local = lights;
  const auto toLocal = [&](std::array<double, 3>& p)
  {
    const double d[3] = { p[0] - origin[0], p[1] - origin[1], p[2] - origin[2] };
    double r[3];
    inverse->MultiplyPoint(d, r);
    for (int a = 0; a < 3; ++a)
    {
      p[a] = origin[a] + r[a];
    }
  };
  for (auto& light : local)
  {
    toLocal(light.Position);
    toLocal(light.FocalPoint);
  }
  return local;
}

//------------------------------------------------------------------------------
std::string CheckPoints(vtkDataSet* input, vtkDataArray* scalars)
{
  std::ostringstream message;
  if (scalars->GetNumberOfTuples() != input->GetNumberOfPoints())
  {
    message << "The scalars '" << (scalars->GetName() ? scalars->GetName() : "") << "' have "
            << scalars->GetNumberOfTuples() << " values for " << input->GetNumberOfPoints()
            << " points; the dataset is inconsistent.";
    return message.str();
  }
  vtkPointSet* pointSet = vtkPointSet::SafeDownCast(input);
  const vtkIdType bad = FirstBadCoordinate(
    pointSet && pointSet->GetPoints() ? pointSet->GetPoints()->GetData() : nullptr,
    std::numeric_limits<double>::max());
  if (bad >= 0)
  {
    message << "Point " << bad << " has a coordinate that is not a finite number.";
    return message.str();
  }
  return std::string();
}

//------------------------------------------------------------------------------
vtkIdType FirstBadCoordinate(vtkDataArray* coordinates, double bound)
{
  for (vtkIdType p = 0; coordinates && p < coordinates->GetNumberOfTuples(); ++p)
  {
    for (int a = 0; a < 3; ++a)
    {
      if (!(std::abs(coordinates->GetComponent(p, a)) <= bound))
      {
        return p;
      }
    }
  }
  return -1;
}

//------------------------------------------------------------------------------
void SetFiniteClamped(
  vtkObject* object, double& setting, double value, double lo, double hi, const char* name)
{
  if (!std::isfinite(value))
  {
    vtkErrorWithObjectMacro(
      object, << name << " must be a finite number; it stays " << setting << ".");
    return;
  }
  const double clamped = std::min(std::max(value, lo), hi);
  if (setting != clamped)
  {
    setting = clamped;
    object->Modified();
  }
}

//------------------------------------------------------------------------------
bool HasSolidCells(vtkUnstructuredGrid* grid)
{
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    if (vtkCellTypes::GetDimension(grid->GetCellType(c)) == 3)
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
std::string CheckPointIds(vtkUnstructuredGrid* grid)
{
  const vtkIdType numberOfPoints = grid->GetNumberOfPoints();
  auto cells = vtk::TakeSmartPointer(grid->GetCells()->NewIterator());
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    cells->GetCurrentCell(n, ids);
    for (vtkIdType i = 0; i < n; ++i)
    {
      if (ids[i] < 0 || ids[i] >= numberOfPoints)
      {
        std::ostringstream message;
        message << "Cell " << cells->GetCurrentCellId() << " refers to point " << ids[i]
                << ", but the grid has " << numberOfPoints << " points.";
        return message.str();
      }
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
PointScalars CheckScalarsAndLights(vtkAlgorithm* algorithm, vtkDataSet* input, int component,
  const PointScalars& previous, const LightList& lights, std::string& error)
{
  PointScalars scalars = FindPointScalars(algorithm, input, component, previous, error);
  if (scalars.Array)
  {
    error = CheckPoints(input, scalars.Array);
  }
  if (scalars.Array && error.empty())
  {
    error = lights.Validate();
  }
  if (!error.empty())
  {
    scalars.Array = nullptr;
  }
  return scalars;
}

//------------------------------------------------------------------------------
void AddUpdateFieldData(vtkFieldData* fieldData, const UpdateReport& report, double seconds)
{
  const auto addInt = [fieldData](const char* name, int value)
  {
    vtkNew<vtkIntArray> array;
    array->SetName(name);
    array->InsertNextValue(value);
    fieldData->AddArray(array);
  };
  addInt("UpdateMode", report.Mode);
  addInt("PropagationPasses", report.Passes);
  addInt("PendingPasses", report.PendingPasses);
  vtkNew<vtkDoubleArray> time;
  time->SetName("UpdateSeconds");
  time->InsertNextValue(seconds);
  fieldData->AddArray(time);
}

//------------------------------------------------------------------------------
void AddCountFieldData(vtkFieldData* fieldData, const char* name, long long value)
{
  vtkNew<vtkIdTypeArray> array;
  array->SetName(name);
  array->InsertNextValue(static_cast<vtkIdType>(value));
  fieldData->AddArray(array);
}

//------------------------------------------------------------------------------
void ReadUpdateFieldData(vtkFieldData* fieldData, UpdateReport& report, double& seconds)
{
  const auto value = [fieldData](const char* name)
  {
    vtkDataArray* a = fieldData ? fieldData->GetArray(name) : nullptr;
    return a && a->GetNumberOfTuples() > 0 ? a->GetTuple1(0) : 0.0;
  };
  report.Mode = static_cast<int>(value("UpdateMode"));
  report.Passes = static_cast<int>(value("PropagationPasses"));
  report.PendingPasses = static_cast<int>(value("PendingPasses"));
  seconds = value("UpdateSeconds");
}

}
