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
#include "vtkSMPTools.h"

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
  // Light by light, keeping what each light adds (its share) for the next update, unless the
  // per-light transmittances are asked for (every light is then shaded again) or the shares
  // would take more than MaximumShareBytes.
  const double shareBytes = static_cast<double>(target.NumberOfPoints()) * channels *
    static_cast<double>(lookups.size() + sphericalLookups.size()) * sizeof(float);
  if (!this->PerLightTransmittance && shareBytes <= MaximumShareBytes)
  {
    const std::vector<double> key = { static_cast<double>(target.Dimensions[0]),
      static_cast<double>(target.Dimensions[1]), static_cast<double>(target.Dimensions[2]),
      target.Origin[0], target.Origin[1], target.Origin[2], target.Spacing[0], target.Spacing[1],
      target.Spacing[2], this->FilterWidth, static_cast<double>(this->FilterKernel),
      static_cast<double>(channels), static_cast<double>(lights.size()) };
    const bool kept = !inputModified && key == this->SharesKey;
    this->SharesKey = key;
    if (!this->ShadeSelectively(
          volume, bounds, lights, lookups, sphericalLookups, target, kept, rgb))
    {
      this->Shares.clear();
      return false;
    }
    report.Mode =
      this->ShadedLights < static_cast<int>(lookups.size() + sphericalLookups.size()) ? 1 : 0;
    return true;
  }
  this->Shares.clear();
  this->ShadedLights = static_cast<int>(lookups.size() + sphericalLookups.size());
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
bool vtkFilteredVolumetricShadows::ShadeSelectively(const volillum::ClassifiedVolume& volume,
  const double bounds[6], const std::vector<volillum::LightState>& lights,
  const std::vector<volillum::ShadowLookup>& lookups,
  const std::vector<volillum::SphericalLookup>& sphericalLookups,
  const volillum::GridGeometry& target, bool kept, float* rgb)
{
  const int channels = this->ChromaticAttenuation ? 3 : 1;
  const long long points = target.NumberOfPoints();
  this->Transmittances.clear();
  if (!kept)
  {
    this->Shares.clear();
  }
  this->Shares.resize(lights.size());
  // A light's geometry: its state at radiance 1 (a colour or intensity edit shades nothing).
  auto geometry = [&](size_t index)
  {
    volillum::LightState g = lights[index];
    g.Color = { { 1.0, 1.0, 1.0 } };
    g.Intensity = 1.0;
    return g;
  };
  // The lights to shade again, each alone at radiance 1 (rgb holds its share meanwhile).
  std::vector<volillum::ShadowLookup> directional;
  std::vector<volillum::SphericalLookup> spherical;
  // A light is shaded again when it has no share, its geometry changed or its table was
  // built anew.
  for (auto l : lookups)
  {
    if (this->Shares[l.Index].Values.empty() ||
      this->Shares[l.Index].Geometry != geometry(l.Index) || this->RebuiltTables[l.Table])
    {
      l.Radiance = { { 1.0, 1.0, 1.0 } };
      directional.push_back(l);
    }
  }
  for (auto l : sphericalLookups)
  {
    if (this->Shares[l.Index].Values.empty() ||
      this->Shares[l.Index].Geometry != geometry(l.Index) || this->RebuiltSphericalTables[l.Table])
    {
      l.Light = geometry(l.Index);
      spherical.push_back(l);
    }
  }
  this->ShadedLights = static_cast<int>(directional.size() + spherical.size());
  int shaded = 0;
  auto shade = [&](const std::vector<volillum::ShadowLookup>& one,
                 const std::vector<volillum::SphericalLookup>& sphericalOne, size_t index)
  {
    const volillum::PointShading shading = this->Shading(volume, bounds, one, sphericalOne,
      std::vector<float*>(lights.size(), nullptr), this->GetEmptyBlocks());
    const double done = static_cast<double>(shaded++) / this->ShadedLights;
    if (!volillum::ShadePoints(shading, target, rgb,
          [this, done](double fraction)
          { return this->ReportProgress(0.5 + 0.5 * (done + fraction / this->ShadedLights)); }))
    {
      return false;
    }
    LightShare& share = this->Shares[index];
    share.Geometry = geometry(index);
    share.Values.resize(static_cast<size_t>(points) * channels);
    vtkSMPTools::For(0, points,
      [&](long long begin, long long end)
      {
        for (long long p = begin; p < end; ++p)
        {
          for (int c = 0; c < channels; ++c)
          {
            share.Values[channels * p + c] = rgb[3 * p + c];
          }
        }
      });
    return true;
  };
  for (const auto& l : directional)
  {
    if (!shade({ l }, {}, l.Index))
    {
      return false;
    }
  }
  for (const auto& l : spherical)
  {
    if (!shade({}, { l }, l.Index))
    {
      return false;
    }
  }
  // The illumination: every light that is on, its radiance times its share, in the lights'
  // order (the same sum whichever lights were shaded again).
  std::vector<std::array<double, 3>> radiance;
  std::vector<const float*> values;
  for (size_t i = 0; i < lights.size(); ++i)
  {
    if (lights[i].On && !this->Shares[i].Values.empty())
    {
      radiance.push_back(lights[i].Radiance());
      values.push_back(this->Shares[i].Values.data());
    }
    else
    {
      this->Shares[i] = LightShare();
    }
  }
  vtkSMPTools::For(0, points,
    [&](long long begin, long long end)
    {
      for (long long p = begin; p < end; ++p)
      {
        for (int c = 0; c < 3; ++c)
        {
          double sum = 0.0;
          for (size_t l = 0; l < values.size(); ++l)
          {
            sum += radiance[l][c] * values[l][channels * p + (channels == 3 ? c : 0)];
          }
          rgb[3 * p + c] = static_cast<float>(sum);
        }
      }
    });
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
  this->Shares.clear();
  this->SharesKey.clear();
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
  this->ShadedLights = static_cast<int>(lookups.size() + sphericalLookups.size());
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
  this->RebuiltTables.assign(frames.size(), true);
  this->RebuiltSphericalTables.assign(sphericalLookups.size(), true);
  for (size_t f = 0; f < frames.size(); ++f)
  {
    if (found[f] && settingsKept && tables[f].GetNumberOfChannels() == channels)
    {
      this->RebuiltTables[f] = false;
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
      this->RebuiltSphericalTables[i] = false;
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
  volillum::AddCountFieldData(fieldData, "ShadedLights", this->ShadedLights);
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
