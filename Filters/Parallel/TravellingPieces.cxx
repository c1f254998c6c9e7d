#include "TravellingPieces.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

#include <cstring>

namespace volillum
{

//------------------------------------------------------------------------------
void CopyLitArrays(const char* name, vtkDataSet* piece, vtkDataSet* out)
{
  for (int association : { vtkDataObject::POINT, vtkDataObject::CELL })
  {
    vtkDataSetAttributes* from = piece->GetAttributes(association);
    vtkDataSetAttributes* to = out->GetAttributes(association);
    if (name && *name)
    {
      if (vtkAbstractArray* named = from->GetAbstractArray(name))
      {
        to->AddArray(named);
      }
    }
    if (vtkDataArray* scalars = from->GetScalars())
    {
      to->SetScalars(scalars);
    }
    if (vtkDataArray* ids = from->GetGlobalIds())
    {
      to->SetGlobalIds(ids);
    }
  }
}

//------------------------------------------------------------------------------
std::uint64_t HashBytes(const void* data, size_t size, std::uint64_t hash)
{
  constexpr std::uint64_t prime = 1099511628211ULL;
  const auto* bytes = static_cast<const unsigned char*>(data);
  size_t i = 0;
  for (; i + 8 <= size; i += 8)
  {
    std::uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    hash = (hash ^ word) * prime;
  }
  for (; i < size; ++i)
  {
    hash = (hash ^ bytes[i]) * prime;
  }
  return hash;
}

//------------------------------------------------------------------------------
std::uint64_t HashArray(vtkAbstractArray* array, std::uint64_t hash)
{
  if (!array)
  {
    return HashBytes("-", 1, hash);
  }
  const int type = array->GetDataType();
  const vtkIdType values = array->GetNumberOfValues();
  hash = HashBytes(&type, sizeof(type), hash);
  hash = HashBytes(&values, sizeof(values), hash);
  if (const char* name = array->GetName())
  {
    hash = HashBytes(name, std::strlen(name), hash);
  }
  return HashBytes(array->GetVoidPointer(0), values * array->GetDataTypeSize(), hash);
}

//------------------------------------------------------------------------------
std::uint64_t Fingerprint(vtkDataSet* travelling)
{
  std::uint64_t hash = 14695981039346656037ULL;
  if (auto* image = vtkImageData::SafeDownCast(travelling))
  {
    hash = HashBytes(image->GetExtent(), 6 * sizeof(int), hash);
    hash = HashBytes(image->GetOrigin(), 3 * sizeof(double), hash);
    hash = HashBytes(image->GetSpacing(), 3 * sizeof(double), hash);
    hash = HashBytes(image->GetDirectionMatrix()->GetData(), 9 * sizeof(double), hash);
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(travelling))
  {
    hash = HashArray(grid->GetPoints() ? grid->GetPoints()->GetData() : nullptr, hash);
    if (vtkCellArray* cells = grid->GetCells())
    {
      hash = HashArray(cells->GetOffsetsArray(), hash);
      hash = HashArray(cells->GetConnectivityArray(), hash);
      hash = HashArray(grid->GetCellTypesArray(), hash);
    }
  }
  for (int association : { vtkDataObject::POINT, vtkDataObject::CELL })
  {
    vtkDataSetAttributes* attributes = travelling->GetAttributes(association);
    for (int a = 0; a < attributes->GetNumberOfArrays(); ++a)
    {
      hash = HashArray(attributes->GetAbstractArray(a), hash);
    }
  }
  return hash;
}

}
