#include "vtkFilteredVolumetricShadows.h"

#include "DistributedClassification.h"
#include "DistributedShadowTables.h"
#include "FilteredShadowsKernel.h"
#include "IlluminationFilterSupport.h"
#include "ImageExtents.h"
#include "ParallelCollectives.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

vtkStandardNewMacro(vtkFilteredVolumetricShadows);

namespace
{
bool SameFrame(const volillum::SatFrame& a, const volillum::SatFrame& b)
{
  return a.Axes == b.Axes;
}

// The tables for `count` keys, moved out of previous: the one that matches a key (found),
// else a table no key matches, whose memory the rebuild reuses (a new table's first writes
// cost a page fault every 4 KiB: ~0.3 s for the table of a 512^3 volume), else a new one. A
// table goes to one key only (two lights at one position get a table each).
template <typename Table, typename Matches>
std::vector<Table> TakeTables(
  std::vector<Table>& previous, size_t count, Matches matches, std::vector<bool>& found)
{
  std::vector<Table> tables(count);
  found.assign(count, false);
  for (size_t i = 0; i < count; ++i)
  {
    auto match =
      std::find_if(previous.begin(), previous.end(), [&](const Table& t) { return matches(i, t); });
    if (match != previous.end())
    {
      tables[i] = std::move(*match);
      previous.erase(match);
      found[i] = true;
    }
  }
  for (size_t i = 0; i < count && !previous.empty(); ++i)
  {
    if (!found[i])
    {
      tables[i] = std::move(previous.back());
      previous.pop_back();
    }
  }
  return tables;
}

}

//------------------------------------------------------------------------------
bool vtkFilteredVolumetricShadows::ComputeIllumination(const volillum::ClassifiedVolume& volume,
  const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
  bool inputModified, float* rgb, UpdateReport& report)
{
  const double scale = this->SATResolutionScale;
  if (scale != 1.0 && scale != 0.5 && scale != 0.25)
  {
    vtkErrorMacro("SATResolutionScale must be 1, 0.5 or 0.25; it is " << scale << ".");
    return false;
  }
  const double minSpacing = volume.Geometry.MinimumSpacing();
  const int channels = this->ChromaticAttenuation ? 3 : 1;
  std::vector<volillum::SatFrame> frames;
  std::vector<volillum::ShadowLookup> lookups;
  std::vector<volillum::SphericalLookup> sphericalLookups;
  volillum::GroupShadowLights(lights, frames, lookups, sphericalLookups);
  report.Passes = 0;
  this->DistributedUpdate = false;
  if (!this->UpdateTables(volume, frames, sphericalLookups, minSpacing / scale, channels,
        inputModified, report.Passes, this->GetEmptyBlocks()))
  {
    return false;
  }

  double bounds[6];
  volume.Geometry.GetBounds(bounds);
  const volillum::PointShading shading = this->Shading(volume, bounds, lookups, sphericalLookups,
    this->AllocateTransmittances(lights, channels, target.NumberOfPoints()),
    this->GetEmptyBlocks());
  if (!volillum::ShadePoints(shading, target, rgb,
        [this](double fraction) { return this->ReportProgress(0.5 + 0.5 * fraction); }))
  {
    return false;
  }
  report.Mode = 0;
  return true;
}

//------------------------------------------------------------------------------
volillum::PointShading vtkFilteredVolumetricShadows::Shading(
  const volillum::ClassifiedVolume& volume, const double bounds[6],
  const std::vector<volillum::ShadowLookup>& lookups,
  const std::vector<volillum::SphericalLookup>& sphericalLookups,
  std::vector<float*> transmittances, const volillum::EmptyBlocks* empty)
{
  const Patch patch = this->PatchFor(volume.Geometry.MinimumSpacing());
  volillum::PointShading shading{ volume, nullptr, {}, this->ChromaticAttenuation ? 3 : 1, lookups,
    this->Tables, sphericalLookups, this->SphericalTables, patch.Half, patch.HalfWidth, patch.Near,
    {}, this->FilterKernel == Gaussian ? volillum::GaussianWeights(5) : std::vector<double>(),
    std::move(transmittances) };
  std::copy_n(bounds, 6, shading.Bounds);
  // The near segment is measured in the table's own cells (a capped spherical table's are
  // coarser).
  for (const auto& table : this->SphericalTables)
  {
    shading.SphericalNear.push_back(volillum::NearSegmentLength(table.GetCellSize(), patch.Half));
  }
  // Empty blocks speed up the near segments; soft shadows have none.
  if (shading.NearLength > 0.0 ||
    std::any_of(
      shading.SphericalNear.begin(), shading.SphericalNear.end(), [](double l) { return l > 0.0; }))
  {
    shading.Empty = empty;
  }
  return shading;
}

//------------------------------------------------------------------------------
vtkFilteredVolumetricShadows::Patch vtkFilteredVolumetricShadows::PatchFor(double minSpacing) const
{
  // Half the patch side. A hard shadow (FilterWidth 0) reads a patch one data spacing wide
  // (a table cell's piecewise-constant content blurs it by at most a cell more); a
  // spherical table widens it to its own cell.
  const double half = 0.5 * this->FilterWidth * minSpacing;
  // The near segment stands in for the table where the table's own cell is the filter (hard
  // shadows); soft shadows are read from the table along the whole ray.
  return { half, std::max(half, 0.5 * minSpacing),
    volillum::NearSegmentLength(minSpacing / this->SATResolutionScale, half) };
}

//------------------------------------------------------------------------------
bool vtkFilteredVolumetricShadows::LightsDistributedPieces() const
{
  // A cone toward a light of finite size is cut at distances along the light that the
  // columns summed beyond a window do not keep: such lights read whole tables.
  const auto states = this->GetLightStates();
  return this->DistributedTables &&
    std::none_of(states.begin(), states.end(),
      [](const volillum::LightState& l) { return l.On && l.Radius > 0.0; });
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::TableReach(const volillum::GridGeometry& data, double cell,
  const std::vector<volillum::SphericalLookup>& sphericalLookups, double& reach,
  double& margin) const
{
  // The table cells that the shadows of a process's points end in lie within `reach` of them
  // (CartesianSAT::LocalReach and SphericalSAT::LocalReach: a patch and a near segment); a
  // spherical cell's samples lie within half a radial cell (`margin`) of its centre.
  const Patch patch = this->PatchFor(data.MinimumSpacing());
  double bounds[6];
  data.GetBounds(bounds);
  reach = volillum::CartesianSAT::LocalReach(cell, patch.HalfWidth, patch.Near);
  margin = 0.0;
  for (const auto& l : sphericalLookups)
  {
    volillum::SphericalSAT planned;
    planned.Plan(bounds, l.Light.Position.data(), cell);
    reach = std::max(reach,
      planned.LocalReach(
        patch.Half, volillum::NearSegmentLength(planned.GetCellSize(), patch.Half)));
    margin = std::max(margin, 0.5 * planned.GetRadialCellLength());
  }
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::ComputeDistributedIllumination(
  vtkMultiProcessController* controller, const volillum::ClassifiedVolume& volume,
  const volillum::VolumePiece& piece, const std::vector<volillum::LightState>& lights,
  const volillum::GridGeometry& target, const std::vector<int>& extents, bool inputModified,
  float* rgb, UpdateReport& report)
{
  report.Mode = 0;
  report.Passes = 0;
  this->Transmittances.clear(); // none from an earlier update
  this->DistributedUpdate = true;
  this->GrownPoints = 0;
  this->SentBytes = 0;
  const int* own = &extents[6 * controller->GetLocalProcessId()];
  const long long points = volillum::ExtentPoints(own);
  const double scale = this->SATResolutionScale;
  if (scale != 1.0 && scale != 0.5 && scale != 0.25)
  {
    vtkErrorMacro("SATResolutionScale must be 1, 0.5 or 0.25; it is " << scale << ".");
    return;
  }
  // A window holds its neighbours' cells: every process rebuilds its tables when any
  // process's input changed.
  inputModified = !volillum::AllOk(controller, !inputModified);
  const bool lit = volume.Geometry.NumberOfPoints() > 0 && points > 0;
  const int channels = this->ChromaticAttenuation ? 3 : 1;
  const volillum::GridGeometry& data = piece.Whole;
  const double cell = data.MinimumSpacing() / scale;
  // The lights that are on (a process without a piece has none: it only takes part).
  std::vector<volillum::SatFrame> frames;
  std::vector<volillum::ShadowLookup> lookups;
  std::vector<volillum::SphericalLookup> sphericalLookups;
  volillum::GroupShadowLights(lights, frames, lookups, sphericalLookups);
  double reach, margin;
  this->TableReach(data, cell, sphericalLookups, reach, margin);
  // The tables' windows over this process's grown block, and the classification they read.
  int tables[6] = { 0, -1, 0, -1, 0, -1 }, wanted[6] = { 0, -1, 0, -1, 0, -1 };
  if (lit)
  {
    volillum::GrownBlock(target, piece, own, reach, margin, tables, wanted);
  }
  volillum::ClassifiedVolume grownVolume;
  this->SentBytes = volillum::GatherClassification(controller, volume, piece, wanted, grownVolume);
  this->GrownPoints = volillum::ExtentPoints(wanted);
  const std::vector<int> tableExtents = volillum::GatherExtents(controller, lit ? tables : nullptr);
  volillum::VolumePiece grown; // the tables' cells, in the grown block's volume
  grown.Whole = data;
  for (int a = 0; a < 3; ++a)
  {
    grown.Offset[a] = wanted[2 * a];
    grown.FirstCell[a] = tables[2 * a];
    grown.LastCell[a] = tables[2 * a + 1] - 1;
  }
  std::unique_ptr<const volillum::EmptyBlocks> empty;
  if (lit)
  {
    empty = std::make_unique<const volillum::EmptyBlocks>(grownVolume);
    // A box starts inside the grid (its near segment stays in it), so the columns it reads
    // beyond a face lie within its patch's reach across the light.
    this->UpdateTables(grownVolume, frames, sphericalLookups, cell, channels, inputModified,
      report.Passes, empty.get(), &grown,
      volillum::CartesianSAT::LocalReach(
        cell, this->PatchFor(data.MinimumSpacing()).HalfWidth, 0.0));
  }
  this->SentBytes += volillum::ShareCellsBeyond(controller, piece, lookups, sphericalLookups,
    channels, tableExtents, this->Tables, this->SphericalTables);
  if (lit)
  {
    this->ShadeGrownBlock(
      data, grownVolume, lookups, sphericalLookups, lights, target, own, empty.get(), rgb);
  }
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::ShadeGrownBlock(const volillum::GridGeometry& data,
  const volillum::ClassifiedVolume& grownVolume, const std::vector<volillum::ShadowLookup>& lookups,
  const std::vector<volillum::SphericalLookup>& sphericalLookups,
  const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
  const int own[6], const volillum::EmptyBlocks* empty, float* rgb)
{
  // Every point of the piece, from the grown block and its tables alone.
  volillum::GridGeometry mine = target;
  for (int a = 0; a < 3; ++a)
  {
    mine.Dimensions[a] = own[2 * a + 1] - own[2 * a] + 1;
    mine.Origin[a] = target.Origin[a] + own[2 * a] * target.Spacing[a];
  }
  double bounds[6];
  data.GetBounds(bounds);
  const int channels = this->ChromaticAttenuation ? 3 : 1;
  const volillum::PointShading shading = this->Shading(grownVolume, bounds, lookups,
    sphericalLookups, this->AllocateTransmittances(lights, channels, mine.NumberOfPoints()), empty);
  volillum::ShadePoints(shading, mine, rgb,
    [this](double fraction)
    {
      this->ReportProgress(0.5 + 0.5 * fraction);
      return true; // computed whole: the output is a piece of the others'
    });
}

//------------------------------------------------------------------------------
bool vtkFilteredVolumetricShadows::UpdateTables(const volillum::ClassifiedVolume& volume,
  const std::vector<volillum::SatFrame>& frames,
  const std::vector<volillum::SphericalLookup>& sphericalLookups, double cellSize, int channels,
  bool inputModified, int& built, const volillum::EmptyBlocks* empty,
  const volillum::VolumePiece* piece, double margin)
{
  const double scale = this->SATResolutionScale;
  // Where the tables lie: the whole grid and the piece's cells for windows, nothing for whole
  // tables (a window fits only the piece and whole grid it was built for).
  std::vector<double> window;
  if (piece)
  {
    const auto& w = piece->Whole;
    window.insert(window.end(), w.Origin.begin(), w.Origin.end());
    window.insert(window.end(), w.Spacing.begin(), w.Spacing.end());
    window.insert(window.end(), w.Dimensions.begin(), w.Dimensions.end());
    window.insert(window.end(), piece->Offset.begin(), piece->Offset.end());
    window.insert(window.end(), piece->FirstCell.begin(), piece->FirstCell.end());
    window.insert(window.end(), piece->LastCell.begin(), piece->LastCell.end());
    window.push_back(margin);
  }
  // Build only the tables whose frame (light position), resolution or classification changed.
  const bool settingsKept =
    !inputModified && this->TablesScale == scale && window == this->TablesWindow;
  std::vector<bool> found;
  auto tables = TakeTables(
    this->Tables, frames.size(),
    [&](size_t f, const volillum::CartesianSAT& t) { return SameFrame(t.GetFrame(), frames[f]); },
    found);
  for (size_t f = 0; f < frames.size(); ++f)
  {
    if (found[f] && settingsKept && tables[f].GetNumberOfChannels() == channels)
    {
      continue;
    }
    tables[f].Build(volume, frames[f], cellSize, channels, empty, piece, margin);
    ++built;
    if (!this->ReportProgress(0.5 * (f + 1) / frames.size()) && !piece)
    {
      this->Tables.clear();
      this->TablesScale = 0.0; // the tables left may predate the classification
      return false;
    }
  }
  // One spherical table per point or spot light, kept while the light does not move.
  auto spherical = TakeTables(
    this->SphericalTables, sphericalLookups.size(),
    [&](size_t i, const volillum::SphericalSAT& t)
    { return t.GetLight() == sphericalLookups[i].Light.Position; },
    found);
  for (size_t i = 0; i < sphericalLookups.size(); ++i)
  {
    if (found[i] && settingsKept && spherical[i].GetTable().GetNumberOfChannels() == channels)
    {
      continue;
    }
    spherical[i].Build(
      volume, sphericalLookups[i].Light.Position.data(), cellSize, channels, 1LL << 25, piece);
    ++built;
    if (!this->ReportProgress(0.5) && !piece)
    {
      this->SphericalTables.clear();
      this->TablesScale = 0.0; // the tables left may predate the classification
      return false;
    }
  }
  this->Tables = std::move(tables);
  this->SphericalTables = std::move(spherical);
  this->TablesScale = scale;
  this->TablesWindow = std::move(window);
  return true;
}

//------------------------------------------------------------------------------
std::vector<float*> vtkFilteredVolumetricShadows::AllocateTransmittances(
  const std::vector<volillum::LightState>& lights, int channels, long long points)
{
  this->Transmittances.assign(lights.size(), nullptr);
  std::vector<float*> out(lights.size(), nullptr);
  for (size_t i = 0; i < lights.size() && this->PerLightTransmittance; ++i)
  {
    if (lights[i].On)
    {
      auto array = vtkSmartPointer<vtkFloatArray>::New();
      array->SetName(("Transmittance" + std::to_string(i)).c_str());
      array->SetNumberOfComponents(channels);
      array->SetNumberOfTuples(points);
      out[i] = array->GetPointer(0);
      this->Transmittances[i] = array;
    }
  }
  return out;
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::AddOutputArrays(vtkPointData* pointData)
{
  for (const auto& array : this->Transmittances)
  {
    if (array)
    {
      pointData->AddArray(array);
    }
  }
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::AddOutputFieldData(vtkFieldData* fieldData)
{
  if (this->DistributedUpdate)
  {
    volillum::AddCountFieldData(fieldData, "GrownPoints", this->GrownPoints);
    volillum::AddCountFieldData(fieldData, "SentBytes", this->SentBytes);
  }
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::SetFilterWidth(double value)
{
  volillum::SetFiniteClamped(this, this->FilterWidth, value, 0.0, 1000.0, "FilterWidth");
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FilterWidth: " << this->FilterWidth << "\n";
  os << indent << "FilterKernel: " << this->FilterKernel << "\n";
  os << indent << "PerLightTransmittance: " << this->PerLightTransmittance << "\n";
  os << indent << "SATResolutionScale: " << this->SATResolutionScale << "\n";
  os << indent << "DistributedTables: " << this->DistributedTables << "\n";
}
