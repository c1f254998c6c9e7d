/**
 * @file SliceInterpolation.h
 * @brief The interpolation of a sweep's slice buffers (private to the light propagation
 * kernel's sources): bilinear, and bicubic (Catmull-Rom) limited to the range of the four
 * surrounding pixels.
 */
#ifndef SliceInterpolation_h
#define SliceInterpolation_h

#include <algorithm>

namespace volillum
{
namespace propagation
{
// Position in a slice (width nb, height nc) as the cell (iu, iv) and the fractions in it.
struct SlicePoint
{
  int U, V;
  float FU, FV;
};

// Where (u, v) falls, or false when outside the slice.
inline bool Locate(double u, double v, int nb, int nc, SlicePoint& at)
{
  if (u < 0.0 || v < 0.0 || u > nb - 1 || v > nc - 1)
  {
    return false;
  }
  at.U = std::min(static_cast<int>(u), std::max(nb - 2, 0));
  at.V = std::min(static_cast<int>(v), std::max(nc - 2, 0));
  at.FU = nb > 1 ? static_cast<float>(u - at.U) : 0.0f;
  at.FV = nc > 1 ? static_cast<float>(v - at.V) : 0.0f;
  return true;
}

// Bilinear interpolation of interleaved channels; strides in values (0 along a flat axis).
inline void Bilinear(const float* base, int channels, long long strideU, long long strideV,
  const SlicePoint& at, float* out)
{
  const float* q = base + at.U * strideU + at.V * strideV;
  for (int ch = 0; ch < channels; ++ch)
  {
    const float a = q[ch] + at.FU * (q[strideU + ch] - q[ch]);
    const float b = q[strideV + ch] + at.FU * (q[strideV + strideU + ch] - q[strideV + ch]);
    out[ch] = a + at.FV * (b - a);
  }
}

// Catmull-Rom weights for the fraction f between the second and third of four samples.
inline void CubicWeights(float f, float w[4])
{
  const float f2 = f * f;
  const float f3 = f2 * f;
  w[0] = 0.5f * (-f3 + 2.0f * f2 - f);
  w[1] = 0.5f * (3.0f * f3 - 5.0f * f2 + 2.0f);
  w[2] = 0.5f * (-3.0f * f3 + 4.0f * f2 + f);
  w[3] = 0.5f * (f3 - f2);
}

// An interpolated value limited to the range of the four values around it (no new extremes).
inline float ClampToSurrounding(float sum, float a, float b, float c, float d)
{
  return std::min(std::max(sum, std::min(std::min(a, b), std::min(c, d))),
    std::max(std::max(a, b), std::max(c, d)));
}

// Bicubic (Catmull-Rom) interpolation of a slice buffer (nb x nc pixels, `channels` values
// each) at `at`, limited to the range of the four surrounding pixels so that it adds no new
// extremes. The buffer may hold only `rows` rows from firstRow on (base: that row; 0: those
// up to the last), those the taps read; a tap beyond them reads the nearest row held.
inline void MonotoneBicubic(const float* base, int channels, int nb, int nc, const SlicePoint& at,
  float* out, int firstRow = 0, int rows = 0)
{
  rows = rows > 0 ? rows : nc - firstRow;
  const long long rowValues = 1LL * channels * nb;
  if (nb < 4 || nc < 4)
  {
    // (clamped to the rows held as the taps below are)
    SlicePoint local = at;
    local.V = std::min(std::max(at.V - firstRow, 0), std::max(rows - 2, 0));
    Bilinear(base, channels, nb > 1 ? channels : 0, nc > 1 && rows > 1 ? rowValues : 0, local, out);
    return;
  }
  float wu[4], wv[4];
  CubicWeights(at.FU, wu);
  CubicWeights(at.FV, wv);
  int iu[4], iv[4];
  for (int m = 0; m < 4; ++m)
  {
    iu[m] = std::min(std::max(at.U - 1 + m, 0), nb - 1);
    iv[m] = std::min(std::max(at.V - 1 + m, 0), nc - 1) - firstRow;
    iv[m] = std::min(std::max(iv[m], 0), rows - 1);
  }
  for (int ch = 0; ch < channels; ++ch)
  {
    float sum = 0.0f;
    for (int mv = 0; mv < 4; ++mv)
    {
      const float* row = base + rowValues * iv[mv] + ch;
      sum += wv[mv] *
        (wu[0] * row[channels * iu[0]] + wu[1] * row[channels * iu[1]] +
          wu[2] * row[channels * iu[2]] + wu[3] * row[channels * iu[3]]);
    }
    const float a = base[rowValues * iv[1] + channels * iu[1] + ch];
    const float b = base[rowValues * iv[1] + channels * iu[2] + ch];
    const float c = base[rowValues * iv[2] + channels * iu[1] + ch];
    const float d = base[rowValues * iv[2] + channels * iu[2] + ch];
    out[ch] = ClampToSurrounding(sum, a, b, c, d);
  }
}
}
}

#endif
