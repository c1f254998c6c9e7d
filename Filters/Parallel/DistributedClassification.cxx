#include "DistributedClassification.h"

#include "ImageExtents.h"

#include <algorithm>

namespace volillum
{

//------------------------------------------------------------------------------
long long GatherClassification(vtkMultiProcessController* controller,
  const ClassifiedVolume& volume, const VolumePiece& piece, const int wanted[6],
  ClassifiedVolume& into)
{
  into.Geometry = piece.Whole;
  into.Channels = volume.Channels;
  into.Scale = volume.Scale;
  for (int a = 0; a < 3; ++a)
  {
    into.Geometry.Dimensions[a] = std::max(0, wanted[2 * a + 1] - wanted[2 * a] + 1);
    into.Geometry.Origin[a] += wanted[2 * a] * piece.Whole.Spacing[a];
  }
  into.Properties.resize(into.Channels * static_cast<size_t>(ExtentPoints(wanted)));
  return GatherClassificationValues(controller, volume, piece, wanted, into.Properties.data());
}

//------------------------------------------------------------------------------
long long GatherClassificationValues(vtkMultiProcessController* controller,
  const ClassifiedVolume& volume, const VolumePiece& piece, const int wanted[6], PackedValue* into)
{
  // This process's classification covers `held` (indices in the whole data grid); it sends the
  // points of its block, less the boundary planes it shares with the blocks before it.
  int held[6] = { 0, -1, 0, -1, 0, -1 }, owned[6] = { 0, -1, 0, -1, 0, -1 };
  if (volume.Geometry.NumberOfPoints() > 0)
  {
    for (int a = 0; a < 3; ++a)
    {
      held[2 * a] = piece.Offset[a];
      held[2 * a + 1] = piece.Offset[a] + volume.Geometry.Dimensions[a] - 1;
      owned[2 * a] = piece.FirstCell[a] + (piece.FirstCell[a] > 0 ? 1 : 0);
      owned[2 * a + 1] = piece.LastCell[a] + 1;
    }
  }
  return ExchangeExtents<PackedValue>(
    controller, held, owned, volume.Properties.data(), wanted, into, volume.Channels, false);
}

}
