#include "vtkFilteredVolumetricShadows.h"

#include "FilteredShadowsKernel.h"
#include "IlluminationFilterSupport.h"
#include "IlluminationParallel.h"
#include "vtkCommunicator.h"
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
  if (!this->UpdateTables(volume, frames, sphericalLookups, minSpacing / scale, channels,
        inputModified, report.Passes))
  {
    return false;
  }

  double bounds[6];
  volume.Geometry.GetBounds(bounds);
  const volillum::PointShading shading = this->Shading(volume, bounds, lookups, sphericalLookups,
    this->AllocateTransmittances(lights, channels, target.NumberOfPoints()));
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
  std::vector<float*> transmittances)
{
  const double minSpacing = volume.Geometry.MinimumSpacing();
  const double cell = minSpacing / this->SATResolutionScale;
  // Half the patch side. A hard shadow (FilterWidth 0) reads a patch one data spacing wide
  // (a table cell's piecewise-constant content blurs it by at most a cell more); a
  // spherical table widens it to its own cell.
  const double patch = 0.5 * this->FilterWidth * minSpacing;
  // The near segment stands in for the table where the table's own cell is the filter (hard
  // shadows); soft shadows are read from the table along the whole ray. It is measured in the
  // table's own cells (a capped spherical table's are coarser).
  volillum::PointShading shading{ volume, nullptr, {}, this->ChromaticAttenuation ? 3 : 1, lookups,
    this->Tables, sphericalLookups, this->SphericalTables, patch, std::max(patch, 0.5 * minSpacing),
    volillum::NearSegmentLength(cell, patch), {},
    this->FilterKernel == Gaussian ? volillum::GaussianWeights(5) : std::vector<double>(),
    std::move(transmittances) };
  std::copy_n(bounds, 6, shading.Bounds);
  for (const auto& table : this->SphericalTables)
  {
    shading.SphericalNear.push_back(volillum::NearSegmentLength(table.GetCellSize(), patch));
  }
  // Empty blocks speed up the near segments; soft shadows have none.
  if (shading.NearLength > 0.0 ||
    std::any_of(
      shading.SphericalNear.begin(), shading.SphericalNear.end(), [](double l) { return l > 0.0; }))
  {
    shading.Empty = this->GetEmptyBlocks();
  }
  return shading;
}

//------------------------------------------------------------------------------
bool vtkFilteredVolumetricShadows::LightsDistributedPieces() const
{
  return this->DistributedTables && this->OnlyDirectionalLights();
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
  const long long points =
    volillum::ExtentPoints(extents.data() + 6 * controller->GetLocalProcessId());
  const double scale = this->SATResolutionScale;
  if (scale != 1.0 && scale != 0.5 && scale != 0.25)
  {
    vtkErrorMacro("SATResolutionScale must be 1, 0.5 or 0.25; it is " << scale << ".");
    return;
  }
  // The directional lights that are on (the same on every process; a process without a
  // piece has no lights in the data's frame and adds nothing).
  const auto states = this->GetLightStates();
  const int count = static_cast<int>(std::count_if(
    states.begin(), states.end(), [](const volillum::LightState& l) { return l.On; }));
  if (count == 0)
  {
    return;
  }
  const bool marches = volume.Geometry.NumberOfPoints() > 0;
  const int channels = this->ChromaticAttenuation ? 3 : 1;
  std::vector<volillum::SatFrame> frames;
  std::vector<volillum::ShadowLookup> lookups;
  std::vector<volillum::SphericalLookup> none;
  double bounds[6];
  piece.Whole.GetBounds(bounds);
  if (marches)
  {
    volillum::GroupShadowLights(lights, frames, lookups, none);
    this->UpdateTables(volume, frames, none, piece.Whole.MinimumSpacing() / scale, channels,
      inputModified, report.Passes, &piece);
  }
  std::unique_ptr<const volillum::PointShading> shading;
  if (marches)
  {
    shading = std::make_unique<const volillum::PointShading>(
      this->Shading(volume, bounds, lookups, none, std::vector<float*>(lights.size(), nullptr)));
  }
  std::vector<float*> transmittances =
    this->AllocateTransmittances(lights, channels, marches ? points : 0);
  // Each process adds the parts of the optical depths its piece holds, for the points of
  // every extent; the sums arrive at the extent's process.
  const int components = channels * count;
  volillum::ReduceOverPieces(
    controller, extents, components, vtkCommunicator::SUM_OP,
    [&](const int* e, size_t first, size_t rows, double* depths)
    {
      const long long width = e[1] - e[0] + 1, rowsY = e[3] - e[2] + 1;
      std::fill(depths, depths + rows * width * components, 0.0);
      if (!marches)
      {
        return;
      }
      vtkSMPTools::For(0, static_cast<long long>(rows),
        [&](long long begin, long long end)
        {
          std::vector<double> x(width);
          for (long long r = begin; r < end; ++r)
          {
            const long long row = static_cast<long long>(first) + r;
            double p[3];
            target.PointPosition(e[0], e[2] + row % rowsY, e[4] + row / rowsY, p);
            for (long long i = 0; i < width; ++i)
            {
              x[i] = target.Origin[0] + (e[0] + i) * target.Spacing[0]; // PointPosition's x
            }
            volillum::DirectionalDepthParts(*shading, piece, x.data(), static_cast<int>(width),
              p[1], p[2], depths + components * r * width);
          }
        });
    },
    [&](const int* e, size_t first, size_t rows, const double* depths)
    {
      const long long width = e[1] - e[0] + 1;
      for (long long n = 0; n < static_cast<long long>(rows) * width; ++n)
      {
        const long long id = static_cast<long long>(first) * width + n;
        double sum[3] = { 0.0, 0.0, 0.0 };
        for (size_t m = 0; m < lookups.size(); ++m)
        {
          const volillum::ShadowLookup& l = lookups[m];
          double transmittance[3] = { 1.0, 1.0, 1.0 };
          for (int c = 0; c < channels; ++c)
          {
            transmittance[c] = std::exp(-std::max(depths[components * n + channels * m + c], 0.0));
          }
          for (int c = 0; c < 3; ++c)
          {
            sum[c] += l.Radiance[c] * transmittance[channels == 3 ? c : 0];
          }
          if (float* out = transmittances[l.Index])
          {
            std::copy_n(transmittance, channels, out + channels * id);
          }
        }
        for (int c = 0; c < 3; ++c)
        {
          rgb[3 * id + c] = static_cast<float>(sum[c]);
        }
      }
    },
    [this](double fraction) { this->ReportProgress(0.5 + 0.5 * fraction); });
}

//------------------------------------------------------------------------------
bool vtkFilteredVolumetricShadows::UpdateTables(const volillum::ClassifiedVolume& volume,
  const std::vector<volillum::SatFrame>& frames,
  const std::vector<volillum::SphericalLookup>& sphericalLookups, double cellSize, int channels,
  bool inputModified, int& built, const volillum::VolumePiece* piece)
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
    tables[f].Build(volume, frames[f], cellSize, channels, this->GetEmptyBlocks(), piece);
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
    spherical[i].Build(volume, sphericalLookups[i].Light.Position.data(), cellSize, channels);
    ++built;
    if (!this->ReportProgress(0.5))
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
