/**
 * @file DistributedClassification.h
 * @brief The classification of an image distributed over the processes, gathered where a
 * distributed method reads it: each process classifies its block, and any part of the whole
 * grid (a band, a wedge's slices, a grown block) comes from the processes whose blocks own
 * its points.
 */
#ifndef DistributedClassification_h
#define DistributedClassification_h

#include "IlluminationClassification.h"
#include "RayMarchKernel.h"
#include "VolIllumParallelModule.h"

class vtkMultiProcessController;

namespace volillum
{

/**
 * Collective: the classification of the points `wanted` of the whole data grid (index ranges;
 * empty: none) into `into` (its geometry, channels, scales and values), each point from the
 * process whose block owns it (`volume` and `piece`: this process's). Returns the bytes this
 * process sent.
 */
VOLILLUMPARALLEL_EXPORT long long GatherClassification(vtkMultiProcessController* controller,
  const ClassifiedVolume& volume, const VolumePiece& piece, const int wanted[6],
  ClassifiedVolume& into);

/// GatherClassification's values only: `into` holds the points of `wanted`, x fastest,
/// `volume`'s channels a point.
VOLILLUMPARALLEL_EXPORT long long GatherClassificationValues(vtkMultiProcessController* controller,
  const ClassifiedVolume& volume, const VolumePiece& piece, const int wanted[6], PackedValue* into);

}

#endif
