/**
 * @file IlluminationFilterSupport.h
 * @brief Pieces every illumination filter shares whatever its data type: the SMP backend
 * choice, finding the point scalars to classify and the field arrays that report an
 * update.
 */
#ifndef IlluminationFilterSupport_h
#define IlluminationFilterSupport_h

#include "IlluminationLights.h"
#include "VolIllumFiltersModule.h"

#include <string>

class vtkAlgorithm;
class vtkDataArray;
class vtkDataSet;
class vtkFieldData;
class vtkUnstructuredGrid;

namespace volillum
{

/// Debian's ParaView defaults to the Sequential SMP backend; unless the user chose one
/// with VTK_SMP_BACKEND_IN_USE, switch to STDThread so the filters use every core.
VOLILLUMFILTERS_EXPORT void UseThreadedBackend();

/**
 * The point array the algorithm's input array 0 names (SetInputArrayToProcess); the active point
 * scalars when no array was chosen (ParaView leaves the name empty before the input first updated).
 * Returns nullptr with the reason in error when there are none usable.
 */
VOLILLUMFILTERS_EXPORT vtkDataArray* FindPointScalars(
  vtkAlgorithm* algorithm, vtkDataSet* input, std::string& error);

/// Largest coordinate magnitude of an input's bounds the filters accept (beyond it, lengths
/// and their squares would overflow).
constexpr double MaximumCoordinate = 1e100;

/// Most tetrahedra the meshing filters (TetGen, CGAL) may be asked to make.
constexpr double MaximumTetrahedra = 2e7;

/**
 * Setter body for a finite, clamped double setting: stores value clamped to [lo, hi] in
 * setting and returns whether it changed. A value that is not a finite number leaves the
 * setting unchanged and returns false with a message in error.
 */
VOLILLUMFILTERS_EXPORT bool SetFiniteClamped(
  double& setting, double value, double lo, double hi, const char* name, std::string& error);

/// Whether the grid has a 3D cell (something to light).
VOLILLUMFILTERS_EXPORT bool HasSolidCells(vtkUnstructuredGrid* grid);

/// Empty when every cell's point ids lie within the grid's points; otherwise which does not.
VOLILLUMFILTERS_EXPORT std::string CheckPointIds(vtkUnstructuredGrid* grid);

/// Empty when the scalars have one value per point and every point coordinate is finite;
/// otherwise what is wrong.
VOLILLUMFILTERS_EXPORT std::string CheckPoints(vtkDataSet* input, vtkDataArray* scalars);

/// FindPointScalars, CheckPoints, then the lights' own check (LightList::Validate): nullptr
/// with the reason in error when any fails.
VOLILLUMFILTERS_EXPORT vtkDataArray* CheckScalarsAndLights(
  vtkAlgorithm* algorithm, vtkDataSet* input, const LightList& lights, std::string& error);

/// What one update did, reported in the output's field data.
struct UpdateReport
{
  int Mode = 0;          // 0 full, 1 selective
  int Passes = 0;        // propagation passes, sweeps or lights the update propagated
  int PendingPasses = 0; // passes left for a later update
};

/// Add the field arrays UpdateMode, PropagationPasses, PendingPasses and UpdateSeconds.
VOLILLUMFILTERS_EXPORT void AddUpdateFieldData(
  vtkFieldData* fieldData, const UpdateReport& report, double seconds);

/// Read what AddUpdateFieldData wrote (zero for an array that is missing).
VOLILLUMFILTERS_EXPORT void ReadUpdateFieldData(
  vtkFieldData* fieldData, UpdateReport& report, double& seconds);

}

#endif
