#include "IlluminationFilterSupport.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellTypes.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
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
vtkDataArray* FindPointScalars(vtkAlgorithm* algorithm, vtkDataSet* input, std::string& error)
{
  vtkInformation* arrayInfo = algorithm->GetInputArrayInformation(0);
  const char* requested = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  if (!requested || !*requested)
  {
    vtkDataArray* active = input->GetPointData()->GetScalars();
    if (!active)
    {
      error = "The input has no point scalars to illuminate.";
    }
    return active;
  }
  const std::string name(requested);
  vtkAbstractArray* named = input->GetPointData()->GetAbstractArray(requested);
  if (!named)
  {
    error = input->GetCellData()->GetAbstractArray(requested)
      ? "The scalars '" + name + "' are not point data; choose a point array."
      : "The input has no point array '" + name + "' to illuminate.";
    return nullptr;
  }
  vtkDataArray* scalars = vtkDataArray::SafeDownCast(named);
  if (!scalars)
  {
    error = "The array '" + name + "' is not numeric; choose a numeric point array.";
  }
  return scalars;
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
  vtkDataArray* coordinates =
    pointSet && pointSet->GetPoints() ? pointSet->GetPoints()->GetData() : nullptr;
  if (coordinates)
  {
    for (vtkIdType p = 0; p < coordinates->GetNumberOfTuples(); ++p)
    {
      for (int a = 0; a < 3; ++a)
      {
        if (!std::isfinite(coordinates->GetComponent(p, a)))
        {
          message << "Point " << p << " has a coordinate that is not a finite number.";
          return message.str();
        }
      }
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
bool SetFiniteClamped(
  double& setting, double value, double lo, double hi, const char* name, std::string& error)
{
  if (!std::isfinite(value))
  {
    std::ostringstream message;
    message << name << " must be a finite number; it stays " << setting << ".";
    error = message.str();
    return false;
  }
  const double clamped = std::min(std::max(value, lo), hi);
  if (setting == clamped)
  {
    return false;
  }
  setting = clamped;
  return true;
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
vtkDataArray* CheckScalarsAndLights(
  vtkAlgorithm* algorithm, vtkDataSet* input, const LightList& lights, std::string& error)
{
  vtkDataArray* scalars = FindPointScalars(algorithm, input, error);
  if (scalars)
  {
    error = CheckPoints(input, scalars);
  }
  if (scalars && error.empty())
  {
    error = lights.Validate();
  }
  return error.empty() ? scalars : nullptr;
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
