// Declarations shared by the sources of volillum-render: the options, the failure that ends a
// run with one error line, the JSON settings and the input.
#ifndef VolIllumRender_h
#define VolIllumRender_h

#include "vtkSmartPointer.h"

#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <stdexcept>
#include <string>
#include <vector>

class vtkColorTransferFunction;
class vtkDataArray;
class vtkDataSet;
class vtkLight;
class vtkPiecewiseFunction;

namespace volillum_render
{
using json = nlohmann::json;

struct Options
{
  std::string Input;
  std::string Phantom = "ct";
  int PhantomDims = 128;
  json Config = json::object();
};

// A failure: main prints its one line and exits with status 1 once everything the run
// made has been released.
struct Failure : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// Throw the Failure of one line.
[[noreturn]] void Fail(const std::string& message);

/// Lower-case copy of s; whether s ends with suffix.
std::string Lower(std::string s);
bool EndsWith(const std::string& s, const std::string& suffix);

/// The command line (VolIllumRenderOptions.cxx); --help prints the usage and exits.
Options ParseArguments(int argc, char* argv[]);

/// The volume or grid of the options, or the phantom, with its scalars checked and made point
/// data (VolIllumRenderInput.cxx).
vtkSmartPointer<vtkDataSet> LoadData(const Options& o);

/// Refuses (a Failure) a NRRD (.nrrd, .nhdr) or MetaImage (.mha, .mhd) file whose header the
/// VTK readers would crash, hang or misread on: an unknown type or encoding, sizes that are
/// missing, misplaced, not positive or absurd, fewer than 2 spatial axes, unreadable data
/// files (VolIllumRenderHeader.cxx). Other files pass.
void CheckVolumeHeader(const std::string& path);

/// JSON settings (VolIllumRenderSettings.cxx): a value of the expected type, fallback when the
/// key is absent, a Failure naming the key when it has another type.
std::vector<double> Numbers(const json& value, size_t count, const std::string& what);
double Number(const json& object, const char* key, double fallback);
bool Flag(const json& object, const char* key, bool fallback);
std::string Text(const json& object, const char* key, const std::string& fallback);

/// The lights of the settings ("lights"), or three default coloured lights.
std::vector<vtkSmartPointer<vtkLight>> BuildLights(const json& config, const double bounds[6]);

/// The transfer functions of the settings ("transfer_function"), or the default ones from the
/// scalars' histogram; unitDistance is set from the settings or the spacing.
void BuildTransferFunctions(const json& config, vtkDataArray* scalars, const double range[2],
  vtkColorTransferFunction* ctf, vtkPiecewiseFunction* otf, double& unitDistance,
  double minSpacing);
}

#endif
