#include "IlluminationClassify.h"

#include "vtkArrayDispatch.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

namespace volillum
{

namespace
{
// Transfer functions sampled densely over the scalar range, looked up with linear
// interpolation (as the GPU mapper does with its lookup textures).
struct TransferTable
{
  static constexpr int Size = 4096;
  double Min = 0.0;
  double Max = 1.0;
  std::vector<float> Sigma;  // Size entries
  std::vector<float> Absorb; // 3 * Size entries

  void Build(const ClassificationSettings& s, double lo, double hi)
  {
    this->Min = lo;
    this->Max = hi > lo ? hi : lo + 1.0;
    std::vector<double> opacity(Size), rgb(3 * Size);
    if (s.Opacity)
    {
      s.Opacity->GetTable(this->Min, this->Max, Size, opacity.data());
    }
    else
    {
      for (int i = 0; i < Size; ++i)
      {
        opacity[i] = static_cast<double>(i) / (Size - 1);
      }
    }
    if (s.Color)
    {
      s.Color->GetTable(this->Min, this->Max, Size, rgb.data());
    }
    else
    {
      for (int i = 0; i < Size; ++i)
      {
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = static_cast<double>(i) / (Size - 1);
      }
    }
    this->Sigma.resize(Size);
    this->Absorb.resize(3 * Size);
    for (int i = 0; i < Size; ++i)
    {
      const double a = std::min(std::max(opacity[i], 0.0), MaximumOpacity);
      // A tiny unit distance makes the extinction huge: keep it finite (it is opaque either
      // way), so that products with zero step lengths stay zero instead of NaN.
      this->Sigma[i] = static_cast<float>(
        std::min(-std::log1p(-a) / s.UnitDistance, ClassifiedVolume::MaximumSigma));
      for (int c = 0; c < 3; ++c)
      {
        const double col = std::min(std::max(rgb[3 * i + c], 0.0), 1.0);
        this->Absorb[3 * i + c] = s.Chromatic ? static_cast<float>(1.0 - col) : 1.0f;
      }
    }
  }

  /// The largest values a point may get: sigma and k_c from Lookup; k_c 1 at NaN points.
  void Largest(double largest[4]) const
  {
    largest[0] = *std::max_element(this->Sigma.begin(), this->Sigma.end());
    for (int c = 0; c < 3; ++c)
    {
      largest[1 + c] = 1.0;
      for (int i = 0; i < Size; ++i)
      {
        largest[1 + c] = std::max(largest[1 + c], static_cast<double>(this->Absorb[3 * i + c]));
      }
    }
  }

  /// sigma into out[0], with channels 4 also k_c into out[1 + c].
  void Lookup(double v, int channels, float* out) const
  {
    double u = (v - this->Min) / (this->Max - this->Min) * (Size - 1);
    u = std::min(std::max(u, 0.0), static_cast<double>(Size - 1));
    int i = std::min(static_cast<int>(u), Size - 2);
    const float f = static_cast<float>(u - i);
    out[0] = this->Sigma[i] + f * (this->Sigma[i + 1] - this->Sigma[i]);
    for (int c = 0; c < channels - 1; ++c)
    {
      const float a0 = this->Absorb[3 * i + c];
      const float a1 = this->Absorb[3 * (i + 1) + c];
      out[1 + c] = a0 + f * (a1 - a0);
    }
  }
};

struct ClassifyWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, int component, const TransferTable& table, ClassifiedVolume& out,
    std::atomic<long long>& nans)
  {
    const auto values = vtk::DataArrayTupleRange(array);
    const int channels = out.Channels;
    vtkSMPTools::For(0, values.size(),
      [&](vtkIdType begin, vtkIdType end)
      {
        long long localNans = 0;
        for (vtkIdType t = begin; t < end; ++t)
        {
          const double v = static_cast<double>(values[t][component]);
          float properties[4] = { 0.0f, 1.0f, 1.0f, 1.0f };
          if (std::isnan(v))
          {
            ++localNans;
          }
          else
          {
            table.Lookup(v, channels, properties);
          }
          PackedValue* o = out.Properties.data() + channels * t;
          for (int c = 0; c < channels; ++c)
          {
            o[c] = out.Pack(c, properties[c]);
          }
        }
        nans += localNans;
      });
  }
};

// Smallest and largest finite value of one component, NaN and infinities left out (an
// infinite value then takes the transfer functions' end it lies beyond, as a scalar beyond
// the range does), on all threads: a new array's GetRange (such as the whole image a
// parallel run assembles) took 0.33 s for 256^3 bytes on one thread.
struct RangeWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, int component, double range[2])
  {
    const auto values = vtk::DataArrayTupleRange(array);
    const double infinity = std::numeric_limits<double>::infinity();
    vtkSMPThreadLocal<std::array<double, 2>> local(std::array<double, 2>{ infinity, -infinity });
    vtkSMPTools::For(0, values.size(),
      [&](vtkIdType begin, vtkIdType end)
      {
        std::array<double, 2>& r = local.Local();
        for (vtkIdType t = begin; t < end; ++t)
        {
          const double v = static_cast<double>(values[t][component]);
          if (std::isfinite(v))
          {
            r[0] = v < r[0] ? v : r[0];
            r[1] = v > r[1] ? v : r[1];
          }
        }
      });
    range[0] = infinity;
    range[1] = -infinity;
    for (const auto& r : local)
    {
      range[0] = std::min(range[0], r[0]);
      range[1] = std::max(range[1], r[1]);
    }
  }
};

}

//------------------------------------------------------------------------------
bool FiniteRange(vtkDataArray* scalars, int component, double range[2])
{
  RangeWorker worker;
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker, component, range))
  {
    worker(scalars, component, range);
  }
  return std::isfinite(range[0]) && std::isfinite(range[1]) && range[0] <= range[1];
}

//------------------------------------------------------------------------------
bool Classify(vtkDataArray* scalars, const GridGeometry& geometry,
  const ClassificationSettings& settings, ClassifiedVolume& out, std::string& error,
  long long* nanCount)
{
  if (!scalars)
  {
    error = "the input has no point scalars to illuminate";
    return false;
  }
  if (scalars->GetNumberOfTuples() != geometry.NumberOfPoints())
  {
    error = "the scalars must be point data with one value per grid point";
    return false;
  }
  if (settings.Component < 0 || settings.Component >= scalars->GetNumberOfComponents())
  {
    error = "the selected scalar component does not exist";
    return false;
  }
  if (!(settings.UnitDistance > 0.0) || !std::isfinite(settings.UnitDistance))
  {
    error = "the scalar opacity unit distance must be a positive number";
    return false;
  }
  double range[2];
  if (settings.Range)
  {
    std::copy_n(settings.Range, 2, range);
  }
  else if (!FiniteRange(scalars, settings.Component, range))
  {
    error = "the scalars have no finite values";
    return false;
  }
  TransferTable table;
  table.Build(settings, range[0], range[1]);

  out.Geometry = geometry;
  out.Channels = settings.Chromatic ? 4 : 1;
  // Every value is written below: resizing keeps the memory of the last classification
  // without filling it first.
  out.Properties.resize(out.Channels * static_cast<size_t>(geometry.NumberOfPoints()));
  double largest[4];
  table.Largest(largest);
  out.SetScales(largest);
  std::atomic<long long> nans(0);
  ClassifyWorker worker;
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker, settings.Component, table, out, nans))
  {
    worker(scalars, settings.Component, table, out, nans);
  }
  if (nanCount)
  {
    *nanCount = nans.load();
  }
  return true;
}

}
