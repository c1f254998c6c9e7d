#include "vtkFilteredVolumetricShadows.h"

#include "IlluminationFilterSupport.h"
#include "RayMarchKernel.h"
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
// A directional light as a table lookup: which table, which of its axes, toward which end.
struct ShadowLookup
{
  size_t Index; // of the light
  size_t Table;
  int Axis;
  int Sign;
  std::array<double, 3> Radiance;
  std::array<double, 3> Toward; // unit direction toward the light
};

// A point or spot light and its spherical table.
struct SphericalLookup
{
  size_t Index; // of the light
  size_t Table;
  volillum::LightState Light;
};

// Store a point's transmittance in a per-light array, when there is one.
void Record(float* out, long long id, const double* transmittance, int channels)
{
  if (out)
  {
    for (int c = 0; c < channels; ++c)
    {
      out[channels * id + c] = static_cast<float>(transmittance[c]);
    }
  }
}

// Shadow rays are integrated through the full-resolution data over their first
// NearSegmentCells table cells toward the light and read from the table beyond: the optical
// depth next to a sample changes fastest across rays (a sample inside a thin structure or at
// its edge), and a table cell is one to four data cells wide. Measured (material RMS at
// FilterWidth 0, engine, directional light, default tables, patch one cell wide): 16.6 %
// without, 9.9 % with 1 cell, 7.6 % with 2, 5.9 % with 4, 4.9 % with 8; with the patch one
// data spacing wide, chest CT: 10.77 % with 4 cells, 10.11 % with 6, 9.19 % with 8 (the
// whole update 0-25 % slower than with 4).
constexpr double NearSegmentCells = 8.0;

// The near part of the shadow ray from p toward the light (unit direction toward, clipped
// to the box and to `reach`): its optical depth per channel, and in far the point where the
// table takes over. Without empty blocks (no near segment) the table starts at p.
void NearSegment(const volillum::ClassifiedVolume& volume, const volillum::EmptyBlocks* empty,
  const double bounds[6], const double p[3], const double toward[3], double reach, int channels,
  double depth[3], double far[3])
{
  if (!empty)
  {
    depth[0] = depth[1] = depth[2] = 0.0; // soft shadows: the table gives the whole ray
    std::copy(p, p + 3, far);
    return;
  }
  const double length = std::min(reach, volillum::DistanceToBoxExit(p, toward, bounds));
  volillum::SegmentOpticalDepth(volume, p, toward, length, channels, depth, empty);
  for (int a = 0; a < 3; ++a)
  {
    far[a] = p[a] + std::max(length, 0.0) * toward[a];
  }
}

bool SameFrame(const volillum::SatFrame& a, const volillum::SatFrame& b)
{
  return a.Axes == b.Axes;
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
  const double cellSize = minSpacing / scale;
  const int channels = this->ChromaticAttenuation ? 3 : 1;

  // Frames: a light joins the first frame that has its direction as an axis (eq. 14).
  std::vector<volillum::SatFrame> frames;
  std::vector<ShadowLookup> lookups;
  std::vector<SphericalLookup> sphericalLookups;
  for (size_t index = 0; index < lights.size(); ++index)
  {
    const auto& light = lights[index];
    if (!light.On)
    {
      continue;
    }
    if (light.Kind != volillum::LightKind::Directional)
    {
      sphericalLookups.push_back({ index, sphericalLookups.size(), light });
      continue;
    }
    // The table is read toward the light, against the direction light travels.
    const auto travel = light.Direction();
    const double toward[3] = { -travel[0], -travel[1], -travel[2] };
    ShadowLookup lookup{ index, frames.size(), -1, 0, light.Radiance(),
      { toward[0], toward[1], toward[2] } };
    for (size_t f = 0; f < frames.size() && lookup.Axis < 0; ++f)
    {
      lookup.Axis = volillum::AxisOfDirection(frames[f], toward, lookup.Sign);
      lookup.Table = f;
    }
    if (lookup.Axis < 0)
    {
      frames.push_back(volillum::FrameForDirection(toward));
      lookup.Table = frames.size() - 1;
      lookup.Axis = volillum::AxisOfDirection(frames.back(), toward, lookup.Sign);
    }
    lookups.push_back(lookup);
  }

  // Build only the tables whose frame, resolution or classification changed.
  std::vector<volillum::CartesianSAT> tables(frames.size());
  report.Passes = 0;
  for (size_t f = 0; f < frames.size(); ++f)
  {
    auto reuse = std::find_if(this->Tables.begin(), this->Tables.end(),
      [&](const volillum::CartesianSAT& t) { return SameFrame(t.GetFrame(), frames[f]); });
    if (!inputModified && this->TablesScale == scale && reuse != this->Tables.end() &&
      reuse->GetNumberOfChannels() == channels)
    {
      tables[f] = std::move(*reuse);
      continue;
    }
    tables[f].Build(volume, frames[f], cellSize, channels);
    ++report.Passes;
    if (!this->ReportProgress(0.5 * (f + 1) / frames.size()))
    {
      this->Tables.clear();
      return false;
    }
  }
  // One spherical table per point or spot light, kept while the light does not move.
  std::vector<volillum::SphericalSAT> spherical(sphericalLookups.size());
  for (size_t i = 0; i < sphericalLookups.size(); ++i)
  {
    const auto& position = sphericalLookups[i].Light.Position;
    auto reuse = std::find_if(this->SphericalTables.begin(), this->SphericalTables.end(),
      [&](const volillum::SphericalSAT& t) { return t.GetLight() == position; });
    if (!inputModified && this->TablesScale == scale && reuse != this->SphericalTables.end() &&
      reuse->GetTable().GetNumberOfChannels() == channels)
    {
      spherical[i] = std::move(*reuse);
      continue;
    }
    spherical[i].Build(volume, position.data(), cellSize, channels);
    ++report.Passes;
    if (!this->ReportProgress(0.5))
    {
      this->SphericalTables.clear();
      return false;
    }
  }
  this->Tables = std::move(tables);
  this->SphericalTables = std::move(spherical);
  this->TablesScale = scale;

  // Half the patch side. A hard shadow (FilterWidth 0) reads a patch one data spacing wide
  // (a table cell's piecewise-constant content blurs it by at most a cell more); a
  // spherical table widens it to its own cell.
  const double patch = 0.5 * this->FilterWidth * minSpacing;
  const double halfWidth = std::max(patch, 0.5 * minSpacing);
  // The near segment stands in for the table where the table's own cell is the filter (hard
  // shadows); a patch two cells wide or wider is read from the table along the whole ray, so
  // soft shadows are filtered everywhere (linear in between, so the width changes smoothly).
  // It is measured in the table's own cells (a capped spherical table's are coarser).
  auto nearSegment = [patch](double cell)
  { return NearSegmentCells * cell * std::min(std::max(2.0 - 2.0 * patch / cell, 0.0), 1.0); };
  const double nearLength = nearSegment(cellSize);
  std::vector<double> sphericalNear;
  for (const auto& table : this->SphericalTables)
  {
    sphericalNear.push_back(nearSegment(table.GetCellSize()));
  }
  double bounds[6];
  volume.Geometry.GetBounds(bounds);
  // Empty blocks speed up the near segments; soft shadows have none.
  const bool anyNear = nearLength > 0.0 ||
    std::any_of(sphericalNear.begin(), sphericalNear.end(), [](double l) { return l > 0.0; });
  const volillum::EmptyBlocks* empty = anyNear ? this->GetEmptyBlocks() : nullptr;
  const std::vector<double> gaussian =
    this->FilterKernel == Gaussian ? volillum::GaussianWeights(5) : std::vector<double>();
  // Optional per-light transmittance arrays, indexed by light.
  this->Transmittances.assign(lights.size(), nullptr);
  std::vector<float*> transmittanceOut(lights.size(), nullptr);
  if (this->PerLightTransmittance)
  {
    for (size_t i = 0; i < lights.size(); ++i)
    {
      if (lights[i].On)
      {
        auto array = vtkSmartPointer<vtkFloatArray>::New();
        array->SetName(("Transmittance" + std::to_string(i)).c_str());
        array->SetNumberOfComponents(channels);
        array->SetNumberOfTuples(target.NumberOfPoints());
        transmittanceOut[i] = array->GetPointer(0);
        this->Transmittances[i] = array;
      }
    }
  }
  const long long nx = target.Dimensions[0];
  const long long ny = target.Dimensions[1];
  const long long points = target.NumberOfPoints();
  const long long chunk = std::max(1LL, points / 20);
  for (long long first = 0; first < points; first += chunk)
  {
    const long long last = std::min(points, first + chunk);
    vtkSMPTools::For(first, last,
      [&](long long begin, long long end)
      {
        for (long long id = begin; id < end; ++id)
        {
          double p[3];
          target.PointPosition(id % nx, (id / nx) % ny, id / (nx * ny), p);
          double sum[3] = { 0.0, 0.0, 0.0 };
          for (const auto& l : lookups)
          {
            const auto& table = this->Tables[l.Table];
            double near[3], far[3];
            NearSegment(volume, empty, bounds, p, l.Toward.data(), nearLength, channels, near, far);
            double transmittance[3] = { 1.0, 1.0, 1.0 };
            for (int c = 0; c < channels; ++c)
            {
              const double tau = near[c] +
                (gaussian.empty() ? table.FilteredOpticalDepth(c, far, l.Axis, l.Sign, halfWidth)
                                  : table.KernelFilteredOpticalDepth(
                                      c, far, l.Axis, l.Sign, halfWidth, gaussian));
              transmittance[c] = std::exp(-std::max(tau, 0.0));
            }
            for (int c = 0; c < 3; ++c)
            {
              sum[c] += l.Radiance[c] * transmittance[channels == 3 ? c : 0];
            }
            Record(transmittanceOut[l.Index], id, transmittance, channels);
          }
          for (const auto& l : sphericalLookups)
          {
            const auto incidence = volillum::ComputeIncidence(l.Light, p);
            const double cone = incidence.ConeFactor;
            if (cone == 0.0 && !transmittanceOut[l.Index])
            {
              continue;
            }
            const auto& table = this->SphericalTables[l.Table];
            const auto radiance = l.Light.Radiance();
            double near[3], far[3];
            NearSegment(volume, empty, bounds, p, incidence.ToLight.data(),
              std::min(sphericalNear[l.Table], incidence.Distance), channels, near, far);
            double transmittance[3] = { 1.0, 1.0, 1.0 };
            for (int c = 0; c < channels; ++c)
            {
              transmittance[c] =
                std::exp(-std::max(near[c] + table.FilteredOpticalDepth(c, far, patch), 0.0));
            }
            for (int c = 0; c < 3; ++c)
            {
              sum[c] += cone * radiance[c] * transmittance[channels == 3 ? c : 0];
            }
            Record(transmittanceOut[l.Index], id, transmittance, channels);
          }
          for (int c = 0; c < 3; ++c)
          {
            rgb[3 * id + c] = static_cast<float>(sum[c]);
          }
        }
      });
    if (!this->ReportProgress(0.5 + 0.5 * static_cast<double>(last) / points))
    {
      return false;
    }
  }
  report.Mode = 0;
  return true;
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
}
