/**
 * @file IlluminationFilterSupport.h
 * @brief Pieces every illumination filter shares whatever its data type: the SMP backend
 * choice, finding the point scalars to classify and the field arrays that report an
 * update.
 */
#ifndef IlluminationFilterSupport_h
#define IlluminationFilterSupport_h

#include "IlluminationLightList.h"
#include "VolIllumFiltersModule.h"
#include "vtkDataArray.h"
#include "vtkSmartPointer.h"
#include "vtkWeakPointer.h"

#include <string>
#include <vector>

class vtkAbstractArray;
class vtkAlgorithm;
class vtkDataSet;
class vtkFieldData;
class vtkMatrix3x3;
class vtkObject;
class vtkUnstructuredGrid;

namespace volillum
{

/**
 * Debian's ParaView defaults to the Sequential SMP backend; unless the user chose one with
 * VTK_SMP_BACKEND_IN_USE, switch to STDThread so the filters use every core. Called once,
 * when the plugin is loaded (Plugin/VolumetricIlluminationStartup.cxx); the filters never
 * call it.
 * @warning It changes vtkSMPTools' backend for the whole process, every VTK filter included.
 */
VOLILLUMFILTERS_EXPORT void UseThreadedBackend();

/// The scalars a filter lights: one value per point.
struct PointScalars
{
  vtkSmartPointer<vtkDataArray> Array; // the chosen point array, or one derived from it
  vtkMTimeType Time = 0;               // changes when the array it comes from changes
  // What a derived Array was made from, so that the next update reuses it while that has
  // not changed (a light edit must not convert the scalars again).
  vtkWeakPointer<vtkDataArray> Source;
  bool OnCells = false;
  int Component = -1;
  vtkIdType Points = 0; // of the dataset whose cells were converted
};

/// Fill the one-component array out (as many tuples as array) with one component of array,
/// or with the magnitude of each tuple for component -1.
VOLILLUMFILTERS_EXPORT void FillSingleComponent(
  vtkDataArray* array, int component, vtkDataArray* out);

/**
 * The array the algorithm's input array 0 names (SetInputArrayToProcess), or the active
 * scalars when no array was chosen (ParaView leaves the name empty before the input first
 * updated); looked up first in the association the input array information names (points
 * when it names none), then in the other. Cell data become point data, each point the
 * average of the cells that use it (vtkCellDataToPointData). An array of several components
 * becomes one: the component `component` (0-based), or the magnitude for -1. A derived
 * array of `previous` made from the same, unchanged source is reused. Returns no Array,
 * with the reason in error, when there is none usable.
 */
VOLILLUMFILTERS_EXPORT PointScalars FindPointScalars(vtkAlgorithm* algorithm, vtkDataSet* input,
  int component, const PointScalars& previous, std::string& error);

/// The name of the array `algorithm`'s input array 0 names (nullptr when it names none: the
/// active scalars are lit).
VOLILLUMFILTERS_EXPORT const char* LitArrayName(vtkAlgorithm* algorithm);

/// The array FindPointScalars lights, before any conversion, and whether it is cell data;
/// nullptr with the reason in error when there is none.
VOLILLUMFILTERS_EXPORT vtkAbstractArray* ChooseScalars(
  vtkAlgorithm* algorithm, vtkDataSet* input, bool& onCells, std::string& error);

/// The conversions of FindPointScalars for an array already chosen (a cell array when
/// onCells).
VOLILLUMFILTERS_EXPORT PointScalars ToPointScalars(vtkDataSet* input, vtkAbstractArray* chosen,
  bool onCells, int component, const PointScalars& previous, std::string& error);

/// Point scalars of `input` from its cell array `cells` (ToPointScalars, `component` as there),
/// as volillum::CellsToPoints converts; nullptr with the reason in error.
VOLILLUMFILTERS_EXPORT vtkSmartPointer<vtkDataArray> CellScalarsToPoints(
  vtkDataSet* input, vtkDataArray* cells, int component, std::string& error);

/**
 * The lights in the frame of an image's axes, where the filters work: positions and focal
 * points p become origin + D^-1 (p - origin) for the image's direction matrix D (the
 * lights unchanged when D is the identity or null).
 */
VOLILLUMFILTERS_EXPORT std::vector<LightState> InImageFrame(
  const std::vector<LightState>& lights, vtkMatrix3x3* direction, const double origin[3]);

/// Largest coordinate magnitude of an input's bounds the filters accept (beyond it, lengths
/// and their squares would overflow).
constexpr double MaximumCoordinate = 1e100;

/// Most tetrahedra the meshing filters (TetGen, CGAL) may be asked to make.
constexpr double MaximumTetrahedra = 2e7;

/**
 * Setter body for a finite, clamped double setting of object: stores value clamped to
 * [lo, hi] in setting and calls Modified when that changes it. A value that is not a
 * finite number leaves the setting unchanged and raises an error naming the setting.
 */
VOLILLUMFILTERS_EXPORT void SetFiniteClamped(
  vtkObject* object, double& setting, double value, double lo, double hi, const char* name);

/// Whether the grid has a 3D cell (something to light).
VOLILLUMFILTERS_EXPORT bool HasSolidCells(vtkUnstructuredGrid* grid);

/// Empty when every cell's point ids lie within the grid's points; otherwise which does not.
VOLILLUMFILTERS_EXPORT std::string CheckPointIds(vtkUnstructuredGrid* grid);

/// The first point of `coordinates` (3 components a point) with a coordinate that is not a
/// finite number within +-bound, or -1 when there is none.
VOLILLUMFILTERS_EXPORT vtkIdType FirstBadCoordinate(vtkDataArray* coordinates, double bound);

/// Empty when the scalars have one value per point and every point coordinate is finite;
/// otherwise what is wrong.
VOLILLUMFILTERS_EXPORT std::string CheckPoints(vtkDataSet* input, vtkDataArray* scalars);

/// FindPointScalars, CheckPoints, then the lights' own check (LightList::Validate): no Array
/// with the reason in error when any fails.
VOLILLUMFILTERS_EXPORT PointScalars CheckScalarsAndLights(vtkAlgorithm* algorithm,
  vtkDataSet* input, int component, const PointScalars& previous, const LightList& lights,
  std::string& error);

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

/// Add a field array `name` holding one count (vtkIdTypeArray).
VOLILLUMFILTERS_EXPORT void AddCountFieldData(
  vtkFieldData* fieldData, const char* name, long long value);

/// Read what AddUpdateFieldData wrote (zero for an array that is missing).
VOLILLUMFILTERS_EXPORT void ReadUpdateFieldData(
  vtkFieldData* fieldData, UpdateReport& report, double& seconds);

}

#endif
