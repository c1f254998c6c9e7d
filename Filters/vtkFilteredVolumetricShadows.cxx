#include "vtkFilteredVolumetricShadows.h"

#include "FilteredShadowsKernel.h"
#include "IlluminationFilterSupport.h"
#include "IlluminationParallel.h"
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
// Messages of the cells beyond a window (ShareCellsBeyond).
constexpr int CellsBeyondTag = 8280;

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
  return this->DistributedTables;
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
  double bounds[6];
  data.GetBounds(bounds);
  // The lights that are on (a process without a piece has none: it only takes part).
  std::vector<volillum::SatFrame> frames;
  std::vector<volillum::ShadowLookup> lookups;
  std::vector<volillum::SphericalLookup> sphericalLookups;
  volillum::GroupShadowLights(lights, frames, lookups, sphericalLookups);
  // The table cells that the shadows of this process's points end in lie within `reach` of
  // them (CartesianSAT::LocalReach and SphericalSAT::LocalReach: a patch and a near segment);
  // a spherical cell's samples lie within half a radial cell (`margin`) of its centre.
  const Patch patch = this->PatchFor(data.MinimumSpacing());
  double reach = volillum::CartesianSAT::LocalReach(cell, patch.HalfWidth, patch.Near);
  double margin = 0.0;
  for (const auto& l : sphericalLookups)
  {
    volillum::SphericalSAT planned;
    planned.Plan(bounds, l.Light.Position.data(), cell);
    reach = std::max(reach,
      planned.LocalReach(
        patch.Half, volillum::NearSegmentLength(planned.GetCellSize(), patch.Half)));
    margin = std::max(margin, 0.5 * planned.GetRadialCellLength());
  }
  // The cells of the tables' windows: those whose centres lie in this process's block and
  // the data points around its extent of the illumination grid, grown by the reach and a
  // spacing (tables); and the points they read, grown by the margin and a spacing (wanted).
  int tables[6] = { 0, -1, 0, -1, 0, -1 }, wanted[6] = { 0, -1, 0, -1, 0, -1 };
  if (lit)
  {
    for (int a = 0; a < 3; ++a)
    {
      const double u[2] = {
        (target.Origin[a] + own[2 * a] * target.Spacing[a] - data.Origin[a]) / data.Spacing[a],
        (target.Origin[a] + own[2 * a + 1] * target.Spacing[a] - data.Origin[a]) / data.Spacing[a]
      };
      const double spacing = std::abs(data.Spacing[a]);
      const int halo = static_cast<int>(std::ceil(reach / spacing)) + 1;
      const int more = margin > 0.0 ? static_cast<int>(std::ceil(margin / spacing)) + 1 : 0;
      const int first = std::min(piece.FirstCell[a], static_cast<int>(std::floor(u[0])));
      const int last = std::max(piece.LastCell[a] + 1, static_cast<int>(std::ceil(u[1])));
      tables[2 * a] = std::max(0, first - halo);
      tables[2 * a + 1] = std::min(data.Dimensions[a] - 1, last + halo);
      wanted[2 * a] = std::max(0, tables[2 * a] - more);
      wanted[2 * a + 1] = std::min(data.Dimensions[a] - 1, tables[2 * a + 1] + more);
    }
  }
  volillum::ClassifiedVolume grownVolume;
  this->SentBytes = GatherClassification(controller, volume, piece, wanted, grownVolume);
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
      volillum::CartesianSAT::LocalReach(cell, patch.HalfWidth, 0.0));
  }
  this->ShareCellsBeyond(controller, piece, lookups, sphericalLookups, channels, tableExtents);
  if (!lit)
  {
    return;
  }
  // Every point of the piece, from the grown block and its tables alone.
  volillum::GridGeometry mine = target;
  for (int a = 0; a < 3; ++a)
  {
    mine.Dimensions[a] = own[2 * a + 1] - own[2 * a] + 1;
    mine.Origin[a] = target.Origin[a] + own[2 * a] * target.Spacing[a];
  }
  const volillum::PointShading shading = this->Shading(grownVolume, bounds, lookups,
    sphericalLookups, this->AllocateTransmittances(lights, channels, points), empty.get());
  volillum::ShadePoints(shading, mine, rgb,
    [this](double fraction)
    {
      this->ReportProgress(0.5 + 0.5 * fraction);
      return true; // computed whole: the output is a piece of the others'
    });
}

//------------------------------------------------------------------------------
void vtkFilteredVolumetricShadows::ShareCellsBeyond(vtkMultiProcessController* controller,
  const volillum::VolumePiece& piece, const std::vector<volillum::ShadowLookup>& lookups,
  const std::vector<volillum::SphericalLookup>& sphericalLookups, int channels,
  const std::vector<int>& tableExtents)
{
  // The columns read: a Cartesian table's axis and the end toward the light, a spherical
  // table's (u, v) columns toward the light; the same on every process (those of the first
  // process with a piece: the others have no lights).
  const int processes = controller->GetNumberOfProcesses();
  const int local = controller->GetLocalProcessId();
  int root = 0;
  while (root < processes - 1 && volillum::ExtentPoints(&tableExtents[6 * root]) <= 0)
  {
    ++root;
  }
  std::vector<int> keys; // per key: spherical (1) or not, the table, the axis and the sign
  for (const auto& l : lookups)
  {
    bool known = false;
    for (size_t k = 0; k < keys.size(); k += 4)
    {
      known = known ||
        (keys[k + 1] == static_cast<int>(l.Table) && keys[k + 2] == l.Axis &&
          keys[k + 3] == l.Sign);
    }
    if (!known)
    {
      keys.insert(keys.end(), { 0, static_cast<int>(l.Table), l.Axis, l.Sign });
    }
  }
  for (const auto& l : sphericalLookups)
  {
    keys.insert(keys.end(), { 1, static_cast<int>(l.Table), 2, -1 });
  }
  int count = static_cast<int>(keys.size());
  controller->Broadcast(&count, 1, root);
  keys.resize(count);
  if (count > 0)
  {
    controller->Broadcast(keys.data(), count, root);
  }
  const bool lit = volillum::ExtentPoints(&tableExtents[6 * local]) > 0;
  for (int k = 0; k < count; k += 4)
  {
    const bool spherical = keys[k] == 1;
    const size_t table = static_cast<size_t>(keys[k + 1]);
    const int axis = keys[k + 2], sign = keys[k + 3];
    // Every process's window of the table.
    int window[6] = { 0, 0, 0, 0, 0, 0 };
    if (lit)
    {
      const volillum::TableWindow& w =
        spherical ? this->SphericalTables[table].GetWindow() : this->Tables[table].GetWindow();
      std::copy(w.First.begin(), w.First.end(), window);
      std::copy(w.N.begin(), w.N.end(), window + 3);
    }
    std::vector<int> windows(6 * static_cast<size_t>(processes));
    controller->AllGather(window, windows.data(), 6);
    // The other processes whose windows share columns with this one's: the cells of one
    // that lie beyond the other's grown block go to the other, which adds them up in the
    // order of the processes.
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    auto shared = [&](int p, int q, volillum::TableWindow& w)
    {
      for (int a : { u, v })
      {
        const int first = std::max(windows[6 * p + a], windows[6 * q + a]);
        const int end = std::min(
          windows[6 * p + a] + windows[6 * p + 3 + a], windows[6 * q + a] + windows[6 * q + 3 + a]);
        w.First[a] = first;
        w.N[a] = std::max(0, end - first);
      }
      return w.N[u] > 0 && w.N[v] > 0;
    };
    // Whether the window of q has cells beyond the window of p's first cell toward the
    // light along the axis (sign > 0: a higher index), where p's grown block ends on a
    // column: only then can it send p cells beyond that.
    auto upwind = [&](int q, int p)
    {
      const int* wq = &windows[6 * q];
      const int* wp = &windows[6 * p];
      return sign > 0 ? wq[axis] + wq[3 + axis] - 1 > wp[axis]
                      : wq[axis] < wp[axis] + wp[3 + axis] - 1;
    };
    std::vector<int> peers;
    volillum::TableWindow common;
    for (int q = 0; lit && q < processes; ++q)
    {
      if (q != local && volillum::ExtentPoints(&tableExtents[6 * q]) > 0 &&
        shared(local, q, common) && (upwind(q, local) || upwind(local, q)))
      {
        peers.push_back(q);
      }
    }
    const volillum::TableWindow* own = nullptr;
    if (lit)
    {
      own =
        spherical ? &this->SphericalTables[table].GetWindow() : &this->Tables[table].GetWindow();
    }
    std::vector<double> total(lit ? static_cast<size_t>(channels) * own->N[u] * own->N[v] : 0, 0.0);
    std::vector<double> sums;
    volillum::WithEachPeer(local, peers,
      [&](size_t k, bool send)
      {
        const int q = peers[k];
        const int from = send ? local : q, to = send ? q : local;
        volillum::TableWindow w;
        if (!upwind(from, to) || !shared(local, q, w))
        {
          return;
        }
        sums.assign(static_cast<size_t>(channels) * w.N[u] * w.N[v], 0.0);
        const vtkIdType size = static_cast<vtkIdType>(sums.size());
        if (!send)
        {
          controller->Receive(sums.data(), size, q, CellsBeyondTag);
          for (int j = 0; j < w.N[v]; ++j)
          {
            const double* in = sums.data() + static_cast<size_t>(channels) * j * w.N[u];
            double* out = total.data() +
              static_cast<size_t>(channels) *
                ((w.First[v] - own->First[v] + j) * own->N[u] + w.First[u] - own->First[u]);
            for (int i = 0; i < channels * w.N[u]; ++i)
            {
              out[i] += in[i];
            }
          }
          return;
        }
        // The other's grown block: its cells' points (the window's process's table extent).
        const int* e = &tableExtents[6 * q];
        volillum::VolumePiece other;
        other.Whole = piece.Whole;
        for (int a = 0; a < 3; ++a)
        {
          other.Offset[a] = other.FirstCell[a] = e[2 * a];
          other.LastCell[a] = e[2 * a + 1] - 1;
        }
        if (spherical)
        {
          this->SphericalTables[table].AddCellsBeyond(piece, other, w, sums.data());
        }
        else
        {
          this->Tables[table].AddCellsBeyond(piece, other, w, axis, sign, sums.data());
        }
        controller->Send(sums.data(), size, q, CellsBeyondTag);
        this->SentBytes += size * static_cast<long long>(sizeof(double));
      });
    if (lit && spherical)
    {
      this->SphericalTables[table].SetBeyond(total.data());
    }
    else if (lit)
    {
      this->Tables[table].SetBeyond(axis, sign, total.data());
    }
  }
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
