// volillum-render: reading the volume or grid (or generating the phantom) and checking it.
#include "VolIllumRender.h"

#include "IlluminationFilterSupport.h"
#include "vtkIlluminatedVolumeMapper.h"
#include "vtkIlluminationPhantomSource.h"

#include "vtkAppendFilter.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDataSetReader.h"
#include "vtkExodusIIReader.h"
#include "vtkIlluminationVolumeAlgorithm.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMetaImageReader.h"
#include "vtkNIFTIImageReader.h"
#include "vtkNew.h"
#include "vtkNrrdReader.h"
#include "vtkOutputWindow.h"
#include "vtkPointData.h"
#include "vtkSLCReader.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLImageDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace volillum_render
{

namespace
{
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
}

namespace
{
// The reader of the file, or the phantom source.
vtkSmartPointer<vtkAlgorithm> MakeSource(const Options& o)
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
        CheckVolumeHeader(o.Input);
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
  return reader;
}

// Runs the reader, reporting its first error or warning; composite output (an Exodus file's
// blocks) is merged into one grid. Fails unless it gives a non-empty image or grid.
vtkSmartPointer<vtkDataSet> Read(vtkAlgorithm* reader, const Options& o)
{
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
  return image;
}

// The active scalars, else the first numeric array, as ParaView would offer them, made the
// active point scalars (cell data lit as point data; several components by magnitude or the
// configured component).
vtkDataArray* ChooseScalars(vtkDataSet* image, const Options& o)
{
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
  return scalars;
}

// Refuses what the filters or the mapper cannot take: inconsistent points or ids, a
// non-positive spacing, a grid without 3D cells, bounds beyond the mapper's reach.
void CheckDataset(vtkDataSet* image, vtkDataArray* scalars, const Options& o)
{
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
}
}

// Reads the volume or unstructured grid (or generates the phantom); fails with one line on
// any problem.
vtkSmartPointer<vtkDataSet> LoadData(const Options& o)
{
  vtkSmartPointer<vtkDataSet> image = Read(MakeSource(o), o);
  CheckDataset(image, ChooseScalars(image, o), o);
  return image;
}

}
