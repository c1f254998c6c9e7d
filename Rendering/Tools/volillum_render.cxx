// volillum-render: read a volume (or generate a phantom), compute its illumination volume
// with a chosen method, render it with vtkIlluminatedVolumeMapper and write a PNG.
//
//   volillum-render [options] [volume file]
//
// Run with --help for the options and the JSON format. Any failure prints one line that
// starts with "volillum-render: error:" and exits with status 1.
#include "IlluminationFilterSupport.h"
#include "vtkFilteredVolumetricShadows.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkIlluminationPhantomSource.h"
#include "vtkMultiLightIlluminationVolume.h"
#include "vtkRayMarchedIllumination.h"
#include "vtkUnstructuredGridIllumination.h"

#include "vtkAppendFilter.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDataSetReader.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkExodusIIReader.h"
#include "vtkFieldData.h"
#include "vtkGPUVolumeRayCastMapper.h"
#include "vtkImageAppend.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkLight.h"
#include "vtkMetaImageReader.h"
#include "vtkNIFTIImageReader.h"
#include "vtkNew.h"
#include "vtkNrrdReader.h"
#include "vtkOutputWindow.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkProjectedTetrahedraMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSLCReader.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTimerLog.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLImageDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"

#include "vtk_nlohmannjson.h"
#include VTK_NLOHMANN_JSON(json.hpp)

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using json = nlohmann::json;

namespace
{
const char* const Usage = R"(usage: volillum-render [options] [volume or grid]

Reads a volume (.vti .vtk .mha .mhd .nrrd .nhdr .slc .nii .nii.gz) or an unstructured
grid (.vtu .vtk .ex2 .exo .e), computes its illumination, renders it lit and writes a
PNG. Volumes use --method; grids the two-level unstructured solver and projected
tetrahedra. Without an input, --phantom chooses a generated volume.

options:
  --phantom NAME     ct (default), spheres, slab or chirp: generate the volume instead
  --dims N           phantom size (points per axis, default 128)
  --config FILE      JSON settings (see below); flags given after it override it
  --output FILE      PNG to write (default volillum.png)
  --method NAME      illumination method: propagation (multi-light illumination
                     volume, default), filtered (soft shadows from summed-area tables)
                     or reference (brute-force ray marching)
  --scale S          illumination resolution scale 1, 0.5 or 0.25 (default 1)
  --size W H         image size in pixels (default 512 512)
  --help             this text

JSON (every key optional; the value shown is the default):
  {"method": "propagation", "resolution_scale": 1, "image_size": [512, 512],
   "output": "volillum.png", "ambient": 0.1, "diffuse": 1.0, "background": [0,0,0],
   "gradient_shading": false, "chromatic_attenuation": false, "filter_width": 3,
   "side_by_side": false, "component": -1,
   "lights": [{"type": "directional" | "point" | "spot",
               "position": [0.5,0.5,2], "focal_point": [0.5,0.5,0.5], "relative": false,
               "color": [1,1,1], "intensity": 1, "cone_angle": 30, "exponent": 1,
               "on": true}],
   "transfer_function": {"color": [[s,r,g,b], ...], "opacity": [[s,a], ...],
                         "unit_distance": 2 x smallest spacing, "relative": true},
   "camera": {"azimuth": 30, "elevation": 20, "roll": 0, "zoom": 1.0},
   grids only: "level0_resolution": 128, "absorption": 1, "scattering": [0,0,0]}
A light's "relative" (default false) gives its position and focal point as fractions of
the volume's bounding box (0..1 inside, outside beyond); a light without a position or
focal point gets the default above, always relative. A transfer function's "relative"
(default true) gives its scalars as fractions of the scalar range. Without lights, three
coloured lights are used (a warm key, a cool fill and a white rim light). Scalars are the
active point scalars or the first point array, else the cell scalars or the first cell
array (cell data are lit as point data, each point the mean of its cells); an array of
several components is lit by its magnitude ("component": -1) or the component given.
Without a transfer function (or without its "color" or "opacity" list) the default one
starts above the background: opacity is 0 up to Otsu's threshold of the scalar histogram (the value
that best separates air around a scan from the object) and rises above it, colours from
warm to white. The camera frames the points whose opacity is above 0 (the object, not
the empty box around it); "zoom" scales from there. "side_by_side" writes the same view twice
side by side, lit with local shading only (left) and with the illumination (right).
)";

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

[[noreturn]] void Fail(const std::string& message)
{
  throw Failure(message);
}

std::string Lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool EndsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() &&
    s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Options ParseArguments(int argc, char* argv[])
{
  Options o;
  auto next = [&](int& i) -> std::string
  {
    if (i + 1 >= argc)
    {
      Fail(std::string("option ") + argv[i] + " needs a value");
    }
    return argv[++i];
  };
  auto number = [&](const std::string& text) -> double
  {
    try
    {
      size_t used = 0;
      const double v = std::stod(text, &used);
      if (used != text.size() || !std::isfinite(v))
      {
        throw std::invalid_argument(text);
      }
      return v;
    }
    catch (const std::exception&)
    {
      Fail("'" + text + "' is not a number");
    }
  };
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h")
    {
      std::cout << Usage;
      std::exit(0);
    }
    else if (a == "--config")
    {
      const std::string path = next(i);
      std::ifstream in(path);
      if (!in)
      {
        Fail("cannot open the settings file " + path);
      }
      try
      {
        json parsed = json::parse(in);
        if (!parsed.is_object())
        {
          Fail("the settings file " + path + " must hold a JSON object");
        }
        o.Config.update(parsed);
      }
      catch (const json::exception& e)
      {
        Fail("the settings file " + path + " is not valid JSON: " + e.what());
      }
    }
    else if (a == "--output")
    {
      o.Config["output"] = next(i);
    }
    else if (a == "--method")
    {
      o.Config["method"] = next(i);
    }
    else if (a == "--scale")
    {
      o.Config["resolution_scale"] = number(next(i));
    }
    else if (a == "--size")
    {
      const double w = number(next(i));
      const double h = number(next(i));
      o.Config["image_size"] = { w, h };
    }
    else if (a == "--phantom")
    {
      o.Phantom = next(i);
    }
    else if (a == "--dims")
    {
      o.PhantomDims = static_cast<int>(number(next(i)));
    }
    else if (!a.empty() && a[0] == '-')
    {
      Fail("unknown option " + a + " (see --help)");
    }
    else if (o.Input.empty())
    {
      o.Input = a;
    }
    else
    {
      Fail("more than one volume given (" + o.Input + ", " + a + ")");
    }
  }
  return o;
}

template <typename ReaderType>
vtkSmartPointer<vtkAlgorithm> MakeReader(const std::string& fileName)
{
  auto reader = vtkSmartPointer<ReaderType>::New();
  reader->SetFileName(fileName.c_str());
  return reader;
}

vtkSmartPointer<vtkAlgorithm> MakeExodusReader(const std::string& fileName)
{
  auto reader = vtkSmartPointer<vtkExodusIIReader>::New();
  reader->SetFileName(fileName.c_str());
  reader->UpdateInformation();
  reader->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
  return reader;
}

// The unstructured grids of a composite dataset (an Exodus file's blocks) as one grid,
// points shared between blocks merged.
vtkSmartPointer<vtkUnstructuredGrid> MergeBlocks(vtkCompositeDataSet* blocks)
{
  vtkNew<vtkAppendFilter> append;
  append->MergePointsOn();
  auto it = vtk::TakeSmartPointer(blocks->NewIterator());
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    if (auto grid = vtkUnstructuredGrid::SafeDownCast(it->GetCurrentDataObject()))
    {
      append->AddInputData(grid);
    }
  }
  if (append->GetNumberOfInputConnections(0) == 0)
  {
    return nullptr;
  }
  append->Update();
  return append->GetOutput();
}

// The reader for each file ending (lower case).
const struct
{
  const char* Extension;
  vtkSmartPointer<vtkAlgorithm> (*Make)(const std::string&);
} ReaderFormats[] = { { ".vti", &MakeReader<vtkXMLImageDataReader> },
  { ".vtu", &MakeReader<vtkXMLUnstructuredGridReader> }, { ".ex2", &MakeExodusReader },
  { ".exo", &MakeExodusReader }, { ".e", &MakeExodusReader },
  { ".vtk", &MakeReader<vtkDataSetReader> }, { ".mha", &MakeReader<vtkMetaImageReader> },
  { ".mhd", &MakeReader<vtkMetaImageReader> }, { ".nrrd", &MakeReader<vtkNrrdReader> },
  { ".nhdr", &MakeReader<vtkNrrdReader> }, { ".slc", &MakeReader<vtkSLCReader> },
  { ".nii", &MakeReader<vtkNIFTIImageReader> }, { ".nii.gz", &MakeReader<vtkNIFTIImageReader> } };

// Largest volume the CLI reads: the illumination filters' own limit on output points.
constexpr long long MaximumVolumePoints = vtkIlluminationVolumeAlgorithm::MaximumOutputPoints;

// Remembers the first error or warning a reader reports (a truncated or corrupt file).
class ReaderProblem : public vtkCommand
{
public:
  static ReaderProblem* New() { return new ReaderProblem; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (this->Message.empty() && data)
    {
      this->Message = static_cast<const char*>(data);
      this->Message.erase(this->Message.find_last_not_of(" \n") + 1);
      const size_t line = this->Message.rfind('\n');
      if (line != std::string::npos)
      {
        this->Message = this->Message.substr(line + 1);
      }
    }
  }
  std::string Message;
};

// Whether a single-file .mha, .nrrd or .vti stores its voxels uncompressed (then the file
// must hold them all).
bool RawSingleFile(const std::string& path)
{
  const std::string name = Lower(path);
  const bool mha = EndsWith(name, ".mha"), nrrd = EndsWith(name, ".nrrd"),
             vti = EndsWith(name, ".vti");
  if (!mha && !nrrd && !vti)
  {
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  std::string header(4096, '\0');
  in.read(&header[0], static_cast<std::streamsize>(header.size()));
  header = Lower(header.substr(0, static_cast<size_t>(in.gcount())));
  if (mha)
  {
    return header.find("compresseddata = true") == std::string::npos &&
      header.find("elementdatafile = local") != std::string::npos;
  }
  if (vti)
  {
    return header.find("compressor=") == std::string::npos &&
      header.find("<appendeddata encoding=\"raw\"") != std::string::npos;
  }
  return header.find("data file:") == std::string::npos &&
    header.find("datafile:") == std::string::npos &&
    (header.find("encoding: raw") != std::string::npos);
}

// Checks what an image file's header declares before anything is allocated: its extent
// against the size limit and, for uncompressed single files, the file's length.
void CheckImageHeader(vtkAlgorithm* reader, const std::string& path)
{
  reader->UpdateInformation();
  vtkInformation* info = reader->GetOutputInformation(0);
  if (!info || !info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return; // not an image: unstructured grids are checked after reading
  }
  int extent[6];
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  long long points = 1;
  for (int a = 0; a < 3; ++a)
  {
    const long long n = static_cast<long long>(extent[2 * a + 1]) - extent[2 * a] + 1;
    if (n < 1 || n > MaximumVolumePoints)
    {
      Fail(path + " declares an invalid extent (" + std::to_string(n) + " points along axis " +
        std::to_string(a) + ")");
    }
    points *= n;
    if (points > MaximumVolumePoints)
    {
      Fail(path + " declares more than " + std::to_string(MaximumVolumePoints) +
        " points, the limit this tool reads");
    }
  }
  vtkInformation* scalars = vtkDataObject::GetActiveFieldInformation(
    info, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
  if (scalars && RawSingleFile(path))
  {
    const int components = scalars->Has(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS())
      ? scalars->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS())
      : 1;
    const long long bytes = points * components *
      vtkDataArray::GetDataTypeSize(scalars->Get(vtkDataObject::FIELD_ARRAY_TYPE()));
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const long long length = static_cast<long long>(in.tellg());
    if (length < bytes)
    {
      Fail(path + " is truncated: its header declares " + std::to_string(bytes) +
        " bytes of voxels, the file has " + std::to_string(length) + " bytes in all");
    }
  }
}

double Number(const json& object, const char* key, double fallback);

// Reads the volume or unstructured grid (or generates the phantom); fails with one line on
// any problem.
vtkSmartPointer<vtkDataSet> LoadData(const Options& o)
{
  vtkSmartPointer<vtkAlgorithm> reader;
  if (o.Input.empty())
  {
    auto source = vtkSmartPointer<vtkIlluminationPhantomSource>::New();
    const std::string name = Lower(o.Phantom);
    if (name == "ct")
    {
      source->SetScene(vtkIlluminationPhantomSource::CTPhantom);
    }
    else if (name == "spheres")
    {
      source->SetScene(vtkIlluminationPhantomSource::ThreeSpheres);
    }
    else if (name == "chirp")
    {
      source->SetScene(vtkIlluminationPhantomSource::Chirp);
    }
    else if (name == "slab")
    {
      source->SetScene(vtkIlluminationPhantomSource::Slab);
      source->SetSlabBegin(o.PhantomDims / 4);
      source->SetSlabEnd(3 * o.PhantomDims / 4);
    }
    else
    {
      Fail("unknown phantom '" + o.Phantom + "' (ct, spheres, slab or chirp)");
    }
    if (o.PhantomDims < 2 || o.PhantomDims > 1024)
    {
      Fail("--dims must be between 2 and 1024");
    }
    source->SetDimensions(o.PhantomDims, o.PhantomDims, o.PhantomDims);
    reader = source;
  }
  else
  {
    std::ifstream probe(o.Input, std::ios::binary);
    if (!probe)
    {
      Fail("cannot read " + o.Input);
    }
    const std::string name = Lower(o.Input);
    for (const auto& format : ReaderFormats)
    {
      if (EndsWith(name, format.Extension))
      {
        reader = format.Make(o.Input);
        break;
      }
    }
    if (!reader)
    {
      Fail("unsupported file type: " + o.Input +
        " (.vti .vtk .mha .mhd .nrrd .nhdr .slc .nii .nii.gz .vtu .ex2 .exo .e)");
    }
  }
  vtkNew<ReaderProblem> problem;
  if (!o.Input.empty())
  {
    // Readers delegate to helpers (legacy readers, XML parsers) whose messages reach only
    // the output window: listen there too.
    for (vtkObject* source :
      { static_cast<vtkObject*>(reader), static_cast<vtkObject*>(vtkOutputWindow::GetInstance()) })
    {
      source->AddObserver(vtkCommand::ErrorEvent, problem);
      source->AddObserver(vtkCommand::WarningEvent, problem);
    }
    CheckImageHeader(reader, o.Input);
  }
  reader->Update();
  vtkOutputWindow::GetInstance()->RemoveObserver(problem);
  if (!problem->Message.empty())
  {
    Fail("cannot read " + o.Input + ": " + problem->Message);
  }
  vtkSmartPointer<vtkDataSet> image = vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (auto blocks = vtkCompositeDataSet::SafeDownCast(reader->GetOutputDataObject(0)))
  {
    image = MergeBlocks(blocks);
  }
  if (!vtkImageData::SafeDownCast(image) && !vtkUnstructuredGrid::SafeDownCast(image))
  {
    Fail("no image data or unstructured grid could be read from " +
      (o.Input.empty() ? o.Phantom : o.Input));
  }
  if (image->GetNumberOfPoints() == 0)
  {
    Fail((o.Input.empty() ? o.Phantom : o.Input) + " is empty");
  }
  // The active scalars, else the first numeric array, as ParaView would offer them: point
  // data first, then cell data (lit as point data, each point the mean of its cells).
  const auto firstNumeric = [](vtkDataSetAttributes* attributes) -> vtkDataArray*
  {
    if (attributes->GetScalars())
    {
      return attributes->GetScalars();
    }
    for (int i = 0; i < attributes->GetNumberOfArrays(); ++i)
    {
      if (attributes->GetArray(i))
      {
        return attributes->GetArray(i);
      }
    }
    return nullptr;
  };
  vtkDataArray* chosen = firstNumeric(image->GetPointData());
  const bool onCells = !chosen;
  chosen = chosen ? chosen : firstNumeric(image->GetCellData());
  if (!chosen)
  {
    Fail((o.Input.empty() ? o.Phantom : o.Input) + " has no point or cell scalars to render");
  }
  const int components = chosen->GetNumberOfComponents();
  const int component = static_cast<int>(Number(o.Config, "component", -1));
  std::string unusable;
  vtkSmartPointer<vtkDataArray> scalars =
    volillum::ToPointScalars(image, chosen, onCells, component, {}, unusable).Array;
  if (!scalars)
  {
    Fail(o.Input + ": " + unusable);
  }
  const std::string name = chosen->GetName() && *chosen->GetName() ? chosen->GetName() : "scalars";
  if (onCells)
  {
    std::cout << "scalars '" << name
              << "' are cell data: lit as point data, each point the mean of its cells\n";
  }
  if (components > 1)
  {
    std::cout << "scalars '" << name << "' have " << components << " components: lit by "
              << (component < 0 ? std::string("their magnitude")
                                : "component " + std::to_string(component))
              << "\n";
  }
  scalars->SetName(name.c_str());
  image->GetPointData()->AddArray(scalars);
  image->GetPointData()->SetActiveScalars(name.c_str());
  // Inconsistent datasets are refused before any filter or mapper reads them.
  std::string inconsistency = volillum::CheckPoints(image, scalars);
  if (auto grid = vtkUnstructuredGrid::SafeDownCast(image))
  {
    inconsistency = inconsistency.empty() ? volillum::CheckPointIds(grid) : inconsistency;
  }
  if (!inconsistency.empty())
  {
    Fail(o.Input + ": " + inconsistency);
  }
  if (auto volume = vtkImageData::SafeDownCast(image))
  {
    const double* spacing = volume->GetSpacing();
    if (!(spacing[0] > 0.0 && spacing[1] > 0.0 && spacing[2] > 0.0))
    {
      Fail(o.Input + ": the spacing must be positive along each axis");
    }
  }
  else if (!volillum::HasSolidCells(vtkUnstructuredGrid::SafeDownCast(image)))
  {
    Fail(o.Input + " has no 3D cells to light");
  }
  if (!vtkIlluminatedVolumeMapper::WithinReach(image->GetBounds()))
  {
    std::ostringstream message;
    message << o.Input << ": its bounds reach beyond the +-"
            << vtkIlluminatedVolumeMapper::MaximumCoordinate
            << " this tool renders; rescale its spacing or origin";
    Fail(message.str());
  }
  return image;
}

std::vector<double> Numbers(const json& value, size_t count, const std::string& what)
{
  if (!value.is_array() || value.size() != count)
  {
    Fail(what + " must be a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  for (const auto& v : value)
  {
    if (!v.is_number())
    {
      Fail(what + " must be a list of " + std::to_string(count) + " numbers");
    }
    out.push_back(v.get<double>());
  }
  return out;
}

// A setting of the JSON object: fallback when absent, one error line naming the key and
// the expected type when it has another.
template <typename T>
T Setting(const json& object, const char* key, const T& fallback,
  bool (json::*isExpected)() const noexcept, const char* expected)
{
  if (!object.contains(key))
  {
    return fallback;
  }
  if (!(object[key].*isExpected)())
  {
    Fail(std::string("'") + key + "' must be " + expected);
  }
  return object[key].get<T>();
}

double Number(const json& object, const char* key, double fallback)
{
  return Setting(object, key, fallback, &json::is_number, "a number");
}

bool Flag(const json& object, const char* key, bool fallback)
{
  return Setting(object, key, fallback, &json::is_boolean, "true or false");
}

std::string Text(const json& object, const char* key, const std::string& fallback)
{
  return Setting(object, key, fallback, &json::is_string, "a string");
}

// The default lights: a warm key light above-left-front, a cool fill light from the
// right and a white rim light from behind, all outside the volume.
json DefaultLights()
{
  return json::parse(R"([
    {"type": "point", "position": [-0.6, 1.4, 1.5], "relative": true,
     "color": [1.0, 0.85, 0.6], "intensity": 1.3},
    {"type": "directional", "position": [1.5, 0.4, 0.7], "focal_point": [0.5, 0.5, 0.5],
     "relative": true, "color": [0.45, 0.6, 1.0], "intensity": 0.7},
    {"type": "directional", "position": [0.5, -0.5, -1.0], "focal_point": [0.5, 0.5, 0.5],
     "relative": true, "color": [1.0, 1.0, 1.0], "intensity": 0.4}
  ])");
}

std::vector<vtkSmartPointer<vtkLight>> BuildLights(const json& config, const double bounds[6])
{
  const json lights = config.contains("lights") ? config["lights"] : DefaultLights();
  if (!lights.is_array())
  {
    Fail("'lights' must be a list");
  }
  std::vector<vtkSmartPointer<vtkLight>> out;
  for (const auto& l : lights)
  {
    if (!l.is_object())
    {
      Fail("each light must be a JSON object");
    }
    const std::string type = Text(l, "type", "directional");
    const bool relative = Flag(l, "relative", false);
    auto place = [&](const char* key, std::vector<double> fallback)
    {
      std::vector<double> p = l.contains(key) ? Numbers(l[key], 3, key) : fallback;
      if (relative || !l.contains(key))
      {
        for (int a = 0; a < 3; ++a)
        {
          p[a] = bounds[2 * a] + p[a] * (bounds[2 * a + 1] - bounds[2 * a]);
        }
      }
      return p;
    };
    auto light = vtkSmartPointer<vtkLight>::New();
    const auto position = place("position", { 0.5, 0.5, 2.0 });
    const auto focal = place("focal_point", { 0.5, 0.5, 0.5 });
    light->SetPosition(position.data());
    light->SetFocalPoint(focal.data());
    if (type == "directional")
    {
      light->SetPositional(false);
    }
    else if (type == "point" || type == "spot")
    {
      light->SetPositional(true);
      light->SetConeAngle(type == "point" ? 180.0 : Number(l, "cone_angle", 30.0));
      light->SetExponent(Number(l, "exponent", 1.0));
    }
    else
    {
      Fail("unknown light type '" + type + "' (directional, point or spot)");
    }
    const auto color =
      l.contains("color") ? Numbers(l["color"], 3, "color") : std::vector<double>{ 1.0, 1.0, 1.0 };
    light->SetDiffuseColor(color.data());
    light->SetIntensity(Number(l, "intensity", 1.0));
    light->SetSwitch(Flag(l, "on", true));
    out.push_back(light);
  }
  return out;
}

// Otsu's threshold of the scalars (first component, 256 bins over the range, NaN skipped):
// the value that best separates the two classes of the histogram, for a scan the air
// around it and the object.
double OtsuThreshold(vtkDataArray* scalars, const double range[2])
{
  constexpr int bins = 256;
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  std::vector<double> histogram(bins, 0.0);
  const vtkIdType n = scalars->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double v = scalars->GetComponent(i, 0);
    if (std::isfinite(v))
    {
      const int b = static_cast<int>((v - range[0]) / width * bins);
      histogram[std::min(std::max(b, 0), bins - 1)] += 1.0;
    }
  }
  double total = 0.0, weighted = 0.0;
  for (int b = 0; b < bins; ++b)
  {
    total += histogram[b];
    weighted += b * histogram[b];
  }
  double below = 0.0, belowWeighted = 0.0, best = -1.0;
  int split = 0;
  for (int b = 0; b < bins - 1; ++b)
  {
    below += histogram[b];
    belowWeighted += b * histogram[b];
    const double above = total - below;
    if (below <= 0.0 || above <= 0.0)
    {
      continue;
    }
    const double meanBelow = belowWeighted / below;
    const double meanAbove = (weighted - belowWeighted) / above;
    const double between = below * above * (meanBelow - meanAbove) * (meanBelow - meanAbove);
    if (between > best)
    {
      best = between;
      split = b;
    }
  }
  return range[0] + (split + 1) * width / bins;
}

// The default transfer function over [threshold, max]: opacity 0 below the threshold, then
// a ramp (u is the fraction of the way from the threshold to the maximum); colours from a
// warm tone to white, so that the lights' colours show on the object.
void DefaultTransferFunction(double threshold, const double range[2], vtkColorTransferFunction* ctf,
  vtkPiecewiseFunction* otf, bool color, bool opacity)
{
  const double width = range[1] > threshold ? range[1] - threshold : 1.0;
  auto at = [&](double u) { return threshold + u * width; };
  if (color)
  {
    ctf->AddRGBPoint(range[0], 0.9, 0.6, 0.45);
    ctf->AddRGBPoint(at(0.0), 0.9, 0.6, 0.45);
    ctf->AddRGBPoint(at(0.35), 0.95, 0.85, 0.75);
    ctf->AddRGBPoint(at(1.0), 1.0, 1.0, 1.0);
  }
  if (opacity)
  {
    otf->AddPoint(range[0], 0.0);
    otf->AddPoint(at(0.0), 0.0);
    otf->AddPoint(at(0.1), 0.15);
    otf->AddPoint(at(0.5), 0.5);
    otf->AddPoint(at(1.0), 0.8);
  }
}

void BuildTransferFunctions(const json& config, vtkDataArray* scalars, const double range[2],
  vtkColorTransferFunction* ctf, vtkPiecewiseFunction* otf, double& unitDistance, double minSpacing)
{
  const json tf =
    config.contains("transfer_function") ? config["transfer_function"] : json::object();
  if (!tf.is_object())
  {
    Fail("'transfer_function' must be a JSON object");
  }
  const bool relative = Flag(tf, "relative", true);
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  auto scalar = [&](double s) { return relative ? range[0] + s * width : s; };
  if (!tf.contains("color") || !tf.contains("opacity"))
  {
    DefaultTransferFunction(OtsuThreshold(scalars, range), range, ctf, otf, !tf.contains("color"),
      !tf.contains("opacity"));
  }
  // The lists given: points of `count` numbers, the first a scalar.
  const auto readPoints = [&](const char* key, size_t count, const char* what,
                            const std::function<void(const std::vector<double>&)>& add)
  {
    if (!tf.contains(key))
    {
      return;
    }
    const json& points = tf[key];
    if (!points.is_array() || points.empty())
    {
      Fail(std::string("the transfer function's '") + key + "' must be a non-empty list");
    }
    for (const auto& p : points)
    {
      auto v = Numbers(p, count, what);
      v[0] = scalar(v[0]);
      add(v);
    }
  };
  readPoints("color", 4, "a colour point [s,r,g,b]",
    [&](const std::vector<double>& v) { ctf->AddRGBPoint(v[0], v[1], v[2], v[3]); });
  readPoints("opacity", 2, "an opacity point [s,a]",
    [&](const std::vector<double>& v) { otf->AddPoint(v[0], v[1]); });
  unitDistance = Number(tf, "unit_distance", 2.0 * minSpacing);
  if (!(unitDistance > 0.0))
  {
    Fail("'unit_distance' must be positive");
  }
}

// Bounds of the points whose opacity is above 0 (the data's bounds when there are none).
void ObjectBounds(vtkDataSet* data, vtkPiecewiseFunction* otf, double bounds[6])
{
  data->GetBounds(bounds);
  vtkDataArray* scalars = data->GetPointData()->GetScalars();
  double found[6] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MIN, VTK_DOUBLE_MAX, VTK_DOUBLE_MIN,
    VTK_DOUBLE_MAX, VTK_DOUBLE_MIN };
  bool any = false;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    const double v = scalars->GetComponent(i, 0);
    if (std::isfinite(v) && otf->GetValue(v) > 0.0)
    {
      double p[3];
      data->GetPoint(i, p);
      for (int a = 0; a < 3; ++a)
      {
        found[2 * a] = std::min(found[2 * a], p[a]);
        found[2 * a + 1] = std::max(found[2 * a + 1], p[a]);
      }
      any = true;
    }
  }
  if (any)
  {
    std::copy(found, found + 6, bounds);
  }
}

// The frame the render window shows now.
vtkSmartPointer<vtkImageData> Grab(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto frame = vtkSmartPointer<vtkImageData>::New();
  frame->DeepCopy(grab->GetOutput());
  return frame;
}

// The same view with local shading only: VTK's ray caster with gradient shading, lit by the
// same lights.
vtkSmartPointer<vtkImageData> RenderLocalShading(const json& config, vtkImageData* image,
  vtkVolume* volume, vtkRenderer* renderer, vtkRenderWindow* window,
  const std::vector<vtkSmartPointer<vtkLight>>& lights)
{
  vtkNew<vtkGPUVolumeRayCastMapper> mapper;
  mapper->SetInputData(image);
  vtkNew<vtkVolumeProperty> property;
  property->DeepCopy(volume->GetProperty());
  property->ShadeOn();
  property->SetAmbient(Number(config, "ambient", 0.1));
  property->SetDiffuse(Number(config, "diffuse", 1.0));
  property->SetSpecular(0.0);
  vtkNew<vtkVolume> local;
  local->SetMapper(mapper);
  local->SetProperty(property);
  renderer->RemoveVolume(volume);
  renderer->AddVolume(local);
  renderer->AutomaticLightCreationOff();
  renderer->RemoveAllLights();
  for (const auto& l : lights)
  {
    vtkNew<vtkLight> copy;
    copy->DeepCopy(l);
    copy->SetLightTypeToSceneLight();
    renderer->AddLight(copy);
  }
  window->Render();
  auto frame = Grab(window);
  renderer->RemoveVolume(local);
  renderer->AddVolume(volume);
  return frame;
}
}

// Computes the illumination volume of an image and sets up the lit ray-cast mapper.
double LightImage(const json& config, const std::string& method, vtkImageData* image,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, vtkColorTransferFunction* ctf,
  vtkPiecewiseFunction* otf, double unitDistance, vtkVolume* volume)
{
  vtkSmartPointer<vtkIlluminationVolumeAlgorithm> illumination;
  if (method == "propagation")
  {
    illumination = vtkSmartPointer<vtkMultiLightIlluminationVolume>::New();
  }
  else if (method == "reference")
  {
    illumination = vtkSmartPointer<vtkRayMarchedIllumination>::New();
  }
  else if (method == "filtered")
  {
    auto filtered = vtkSmartPointer<vtkFilteredVolumetricShadows>::New();
    filtered->SetFilterWidth(Number(config, "filter_width", 3.0));
    illumination = filtered;
  }
  else
  {
    Fail("unknown method '" + method + "' (available: propagation, filtered, reference)");
  }
  illumination->SetInputData(image);
  for (const auto& l : lights)
  {
    illumination->AddLight(l);
  }
  illumination->SetColorTransferFunction(ctf);
  illumination->SetOpacityFunction(otf);
  illumination->SetScalarOpacityUnitDistance(unitDistance);
  illumination->SetResolutionScale(Number(config, "resolution_scale", 1.0));
  illumination->SetChromaticAttenuation(Flag(config, "chromatic_attenuation", false));
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  illumination->Update();
  timer->StopTimer();
  vtkImageData* lit = illumination->GetOutput();
  if (!lit || !lit->GetPointData()->GetArray("Illumination"))
  {
    Fail("the illumination could not be computed (see the message above)");
  }
  vtkNew<vtkIlluminatedVolumeMapper> mapper;
  mapper->SetInputData(image);
  mapper->SetIlluminationData(lit);
  mapper->SetAmbient(Number(config, "ambient", 0.1));
  mapper->SetDiffuse(Number(config, "diffuse", 1.0));
  mapper->SetGradientShading(Flag(config, "gradient_shading", false));
  volume->SetMapper(mapper);
  return timer->GetElapsedTime();
}

// Lights an unstructured grid with the two-level solver and sets up projected tetrahedra
// on its lit vertex colours (per-vertex lighting).
double LightGrid(const json& config, vtkUnstructuredGrid* grid,
  const std::vector<vtkSmartPointer<vtkLight>>& lights, vtkColorTransferFunction* ctf,
  vtkPiecewiseFunction* otf, double unitDistance, vtkVolume* volume)
{
  // Projected tetrahedra draw tetrahedra only: split other cells first (the filter would
  // split them the same way, but its output keeps the input's cells).
  vtkSmartPointer<vtkUnstructuredGrid> tetrahedra = grid;
  if (!grid->IsHomogeneous() || (grid->GetNumberOfCells() > 0 && grid->GetCellType(0) != VTK_TETRA))
  {
    vtkNew<vtkDataSetTriangleFilter> split;
    split->TetrahedraOnlyOn();
    split->SetInputData(grid);
    split->Update();
    tetrahedra = split->GetOutput();
  }
  vtkNew<vtkUnstructuredGridIllumination> illumination;
  illumination->SetInputData(tetrahedra);
  for (const auto& l : lights)
  {
    illumination->AddLight(l);
  }
  illumination->SetColorTransferFunction(ctf);
  illumination->SetOpacityFunction(otf);
  illumination->SetScalarOpacityUnitDistance(unitDistance);
  illumination->SetChromaticAttenuation(Flag(config, "chromatic_attenuation", false));
  const int resolution = static_cast<int>(Number(config, "level0_resolution", 128));
  illumination->SetLevel0Resolution(resolution, resolution, resolution);
  illumination->SetAbsorption(Number(config, "absorption", 1.0));
  if (config.contains("scattering"))
  {
    const auto s = Numbers(config["scattering"], 3, "scattering");
    illumination->SetScatteringStrength(s[0], s[1], s[2]);
  }
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  illumination->Update();
  timer->StopTimer();
  vtkUnstructuredGrid* lit = illumination->GetOutput();
  if (!lit || !lit->GetPointData()->GetArray("LitColors"))
  {
    Fail("the illumination could not be computed (see the message above)");
  }
  // The lit colours are direct RGBA: dependent components, no transfer-function lookup.
  vtkNew<vtkProjectedTetrahedraMapper> mapper;
  mapper->SetInputData(lit);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectScalarArray("LitColors");
  volume->SetMapper(mapper);
  volume->GetProperty()->IndependentComponentsOff();
  return timer->GetElapsedTime();
}

int Run(int argc, char* argv[])
{
  vtkSMPTools::SetBackend("STDThread");
  const Options options = ParseArguments(argc, argv);
  const json& config = options.Config;
  // Checked before any work: a bad value must not cost a whole render first (and VTK's
  // PNG writer leaks when it cannot open its file).
  const std::string output = Text(config, "output", "volillum.png");
  {
    const bool existed = std::ifstream(output).good();
    if (!std::ofstream(output, std::ios::binary | std::ios::app))
    {
      Fail("cannot write " + output);
    }
    if (!existed)
    {
      std::remove(output.c_str());
    }
  }

  // VTK's own warnings still reach stderr; its error pop-ups do not exist here.
  vtkSmartPointer<vtkDataSet> data = LoadData(options);
  double bounds[6], range[2];
  data->GetBounds(bounds);
  data->GetPointData()->GetScalars()->GetRange(range);
  auto image = vtkImageData::SafeDownCast(data);
  double minSpacing = 0.0;
  if (image)
  {
    double spacing[3];
    image->GetSpacing(spacing);
    minSpacing = std::min(spacing[0], std::min(spacing[1], spacing[2]));
  }
  else
  {
    // A grid has no spacing: the default unit distance is 1/128 of its diagonal.
    minSpacing = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
                   (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
                   (bounds[5] - bounds[4]) * (bounds[5] - bounds[4])) /
      128.0;
  }

  vtkNew<vtkColorTransferFunction> ctf;
  vtkNew<vtkPiecewiseFunction> otf;
  double unitDistance = 1.0;
  BuildTransferFunctions(
    config, data->GetPointData()->GetScalars(), range, ctf, otf, unitDistance, minSpacing);
  const bool sideBySide = Flag(config, "side_by_side", false);
  if (sideBySide && !image)
  {
    Fail("'side_by_side' is available for volumes (image data), not for grids");
  }
  const auto lights = BuildLights(config, bounds);

  vtkNew<vtkVolumeProperty> property;
  property->SetColor(ctf);
  property->SetScalarOpacity(otf);
  property->SetScalarOpacityUnitDistance(unitDistance);
  property->SetInterpolationTypeToLinear();
  property->ShadeOff();
  vtkNew<vtkVolume> volume;
  volume->SetProperty(property);
  vtkNew<vtkTimerLog> timer;
  std::string method;
  double illuminationSeconds = 0.0;
  if (image)
  {
    method = Text(config, "method", "propagation");
    illuminationSeconds = LightImage(config, method, image, lights, ctf, otf, unitDistance, volume);
  }
  else
  {
    method = "two-level";
    illuminationSeconds = LightGrid(
      config, vtkUnstructuredGrid::SafeDownCast(data), lights, ctf, otf, unitDistance, volume);
  }

  const json size =
    config.contains("image_size") ? config["image_size"] : json::array({ 512, 512 });
  const auto wh = Numbers(size, 2, "image_size");
  if (!(wh[0] >= 16 && wh[1] >= 16 && wh[0] <= 8192 && wh[1] <= 8192))
  {
    Fail("image_size must be between 16 and 8192 pixels per side");
  }

  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  const json background =
    config.contains("background") ? config["background"] : json::array({ 0.0, 0.0, 0.0 });
  const auto bg = Numbers(background, 3, "background");
  renderer->SetBackground(bg.data());
  renderer->ResetCamera();
  const json camera = config.contains("camera") ? config["camera"] : json::object();
  if (!camera.is_object())
  {
    Fail("'camera' must be a JSON object");
  }
  renderer->GetActiveCamera()->Azimuth(Number(camera, "azimuth", 30.0));
  renderer->GetActiveCamera()->Elevation(Number(camera, "elevation", 20.0));
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->GetActiveCamera()->Roll(Number(camera, "roll", 0.0));
  double object[6];
  ObjectBounds(data, otf, object);
  renderer->ResetCamera(object);
  renderer->GetActiveCamera()->Zoom(Number(camera, "zoom", 1.0));
  renderer->ResetCameraClippingRange();

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(static_cast<int>(wh[0]), static_cast<int>(wh[1]));
  window->AddRenderer(renderer);
  // The image is taken from the very first frame: it must already be lit.
  timer->StartTimer();
  window->Render();
  timer->StopTimer();
  const double firstFrameSeconds = timer->GetElapsedTime();
  vtkSmartPointer<vtkImageData> picture = Grab(window);
  timer->StartTimer();
  window->Render();
  timer->StopTimer();
  const double frameSeconds = timer->GetElapsedTime();
  if (sideBySide)
  {
    vtkNew<vtkImageAppend> both;
    both->SetAppendAxis(0);
    both->AddInputData(RenderLocalShading(config, image, volume, renderer, window, lights));
    both->AddInputData(picture);
    both->Update();
    picture = both->GetOutput();
  }

  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(output.c_str());
  writer->SetInputData(picture);
  writer->Write();
  if (writer->GetErrorCode() != 0)
  {
    Fail("cannot write " + output);
  }
  std::cout << "illumination (" << method << ", " << lights.size()
            << " lights): " << illuminationSeconds << " s\n"
            << "first frame: " << firstFrameSeconds << " s\n"
            << "frame: " << frameSeconds << " s\n"
            << "wrote " << output << std::endl;
  return 0;
}

int main(int argc, char* argv[])
{
  // Every failure ends with one line and status 1, also the ones a library throws.
  std::string message;
  try
  {
    return Run(argc, argv);
  }
  catch (const Failure& e)
  {
    message = e.what();
  }
  catch (const json::exception& e)
  {
    message = std::string("invalid settings: ") + e.what();
  }
  catch (const std::bad_alloc&)
  {
    message = "out of memory";
  }
  catch (const std::exception& e)
  {
    message = e.what();
  }
  std::cerr << "volillum-render: error: " << message << std::endl;
  return 1;
}
