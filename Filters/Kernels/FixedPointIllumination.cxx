#include "LightPropagationKernel.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

double FixedPointIllumination::ScaleFor(double bound)
{
  if (!(bound > 0.0) || !std::isfinite(bound))
  {
    return 1.0; // no light: any scale holds the zeros
  }
  int exponent;
  std::frexp(bound, &exponent); // bound < 2^exponent
  return std::ldexp(1.0, 28 - exponent);
}

bool FixedPointIllumination::Holds(double largest, double final) const
{
  const double units = largest * this->Scale;
  return std::isfinite(units) && units <= std::ldexp(1.0, 30) &&
    final * this->Scale >= std::ldexp(1.0, 20);
}

void FixedPointIllumination::ToFloat(const std::uint32_t* units, size_t count, double scale,
  float* out, size_t unitStride, size_t outStride)
{
  const double unit = 1.0 / scale;
  vtkSMPTools::For(0, static_cast<long long>(count),
    [&](long long b, long long e)
    {
      for (long long i = b; i < e; ++i)
      {
        out[i * outStride] =
          static_cast<float>(static_cast<std::int32_t>(units[i * unitStride]) * unit);
      }
    });
}

void FixedPointIllumination::SubtractRecord()
{
  std::uint32_t* v = this->Values.data();
  const std::uint32_t* r = this->Recorded.data();
  vtkSMPTools::For(0, static_cast<long long>(std::min(this->Values.size(), this->Recorded.size())),
    [&](long long b, long long e)
    {
      for (long long i = b; i < e; ++i)
      {
        v[i] -= r[i]; // modulo 2^32, as the record was added
      }
    });
}
}
