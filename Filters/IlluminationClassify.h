/**
 * @file IlluminationClassify.h
 * @brief Classification of VTK scalars with a filter's transfer functions into the
 * ClassifiedVolume the kernels light (IlluminationClassification.h).
 */
#ifndef IlluminationClassify_h
#define IlluminationClassify_h

#include "IlluminationClassification.h"
#include "VolIllumFiltersModule.h"

#include <string>

class vtkColorTransferFunction;
class vtkDataArray;
class vtkPiecewiseFunction;

namespace volillum
{

/// Settings of classification.
struct ClassificationSettings
{
  vtkColorTransferFunction* Color = nullptr;
  vtkPiecewiseFunction* Opacity = nullptr;
  double UnitDistance = 1.0;
  bool Chromatic = true;
  int Component = 0;
  /// The scalar range the default ramp and the transfer functions' tables span (a parallel
  /// run's range over all pieces); nullptr: the scalars' own (FiniteRange).
  const double* Range = nullptr;
};

/// The range of the finite values of a component of the scalars (NaN and infinities left
/// out); false when there is none.
VOLILLUMFILTERS_EXPORT bool FiniteRange(vtkDataArray* scalars, int component, double range[2]);

/**
 * Classify the scalars (any numeric type; NaN counts as empty space). Without transfer
 * functions a grey ramp over the scalar range applies: colour and opacity rise linearly
 * from 0 at the minimum to 1 at the maximum. Returns false with a message in error when
 * the input cannot be classified.
 */
VOLILLUMFILTERS_EXPORT bool Classify(vtkDataArray* scalars, const GridGeometry& geometry,
  const ClassificationSettings& settings, ClassifiedVolume& out, std::string& error,
  long long* nanCount = nullptr);

}

#endif
