/**
 * @file NeighborhoodBins.h
 * @brief For NeighborhoodGrid: where the cells of the pieces lie (bins over the bounds of all
 * pieces, a bit per bin), the cells of a piece near another's, and a point's key.
 */
#ifndef NeighborhoodBins_h
#define NeighborhoodBins_h

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

class vtkDataSet;
class vtkUnstructuredGrid;

namespace volillum
{
namespace neighborhood
{

// Where the cells of the pieces lie: bins over the bounds of all pieces, about `depth`
// wide (at most 64 a side), a bit per bin.
class BinMask
{
public:
  BinMask(const double bounds[6], double depth)
  {
    for (int a = 0; a < 3; ++a)
    {
      const double extent = bounds[2 * a + 1] - bounds[2 * a];
      this->Origin[a] = bounds[2 * a];
      this->Bins[a] = extent > 0.0 && depth > 0.0
        ? static_cast<int>(std::min(64.0, std::max(1.0, std::ceil(extent / depth))))
        : 1;
      this->Size[a] = extent > 0.0 ? extent / this->Bins[a] : 1.0;
    }
    this->Bits.assign((this->Count() + 7) / 8, 0);
  }

  size_t Count() const
  {
    return static_cast<size_t>(this->Bins[0]) * this->Bins[1] * this->Bins[2];
  }

  // Calls visit(bin) for each bin the box overlaps until it returns true; returns whether it
  // did.
  template <typename Visit>
  bool AnyBin(const double box[6], Visit&& visit) const
  {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      const auto at = [&](double x)
      {
        const double f = std::floor((x - this->Origin[a]) / this->Size[a]);
        return static_cast<int>(std::min(std::max(f, 0.0), this->Bins[a] - 1.0));
      };
      lo[a] = at(box[2 * a]);
      hi[a] = at(box[2 * a + 1]);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
    {
      for (int j = lo[1]; j <= hi[1]; ++j)
      {
        for (int i = lo[0]; i <= hi[0]; ++i)
        {
          if (visit(this->Index(i, j, k)))
          {
            return true;
          }
        }
      }
    }
    return false;
  }

  // Marks the bins the box overlaps.
  void Mark(const double box[6])
  {
    this->AnyBin(box,
      [this](size_t bin)
      {
        this->Bits[bin / 8] |= static_cast<unsigned char>(1u << (bin % 8));
        return false;
      });
  }

  // Whether the box grown by depth overlaps a bin marked in `bits` (another mask's).
  bool Meets(const unsigned char* bits, const double box[6], double depth) const
  {
    const double grown[6] = { box[0] - depth, box[1] + depth, box[2] - depth, box[3] + depth,
      box[4] - depth, box[5] + depth };
    return this->AnyBin(grown, [bits](size_t bin) { return Marked(bits, bin); });
  }

  // The whole bins within depth along each axis.
  std::array<int, 3> Reach(double depth) const
  {
    std::array<int, 3> reach;
    for (int d = 0; d < 3; ++d)
    {
      reach[d] = static_cast<int>(std::ceil(depth / this->Size[d]));
    }
    return reach;
  }

  // The bin indices (lowest, highest along each axis) of the marked bins; lowest above
  // highest when none is marked.
  std::array<int, 6> MarkedBox() const
  {
    std::array<int, 6> box = { this->Bins[0], -1, this->Bins[1], -1, this->Bins[2], -1 };
    for (int k = 0; k < this->Bins[2]; ++k)
    {
      for (int j = 0; j < this->Bins[1]; ++j)
      {
        for (int i = 0; i < this->Bins[0]; ++i)
        {
          if (this->Marked(this->Bits.data(), this->Index(i, j, k)))
          {
            const int at[3] = { i, j, k };
            for (int d = 0; d < 3; ++d)
            {
              box[2 * d] = std::min(box[2 * d], at[d]);
              box[2 * d + 1] = std::max(box[2 * d + 1], at[d]);
            }
          }
        }
      }
    }
    return box;
  }

  // The marked bins grown by `reach` bins along each axis (a box around each, one axis at a
  // time): a bin of another mask lies within reach of a marked one exactly where the
  // grown bits and the other's share a bit, the same answer seen from either mask.
  std::vector<unsigned char> Grown(const std::array<int, 3>& reach) const
  {
    std::vector<unsigned char> bins(this->Count());
    for (size_t b = 0; b < bins.size(); ++b)
    {
      bins[b] = this->Marked(this->Bits.data(), b);
    }
    std::vector<unsigned char> line;
    for (int d = 0; d < 3; ++d)
    {
      // Lines along d: `stride` apart from bin to bin, starting at every bin of the other
      // two axes.
      const size_t stride = d == 0 ? 1 : d == 1 ? this->Bins[0] : this->Count() / this->Bins[2];
      const int n = this->Bins[d];
      line.resize(n);
      for (size_t outer = 0; outer < this->Count(); outer += stride * n)
      {
        for (size_t first = outer; first < outer + stride; ++first)
        {
          for (int i = 0; i < n; ++i)
          {
            line[i] = bins[first + i * stride];
          }
          for (int i = 0; i < n; ++i)
          {
            unsigned char any = 0;
            for (int m = std::max(0, i - reach[d]); m <= std::min(n - 1, i + reach[d]); ++m)
            {
              any |= line[m];
            }
            bins[first + i * stride] = any;
          }
        }
      }
    }
    std::vector<unsigned char> bits(this->Bits.size(), 0);
    for (size_t b = 0; b < bins.size(); ++b)
    {
      bits[b / 8] |= static_cast<unsigned char>(bins[b] << (b % 8));
    }
    return bits;
  }

  // Whether two bit masks share a marked bin.
  static bool Share(const std::vector<unsigned char>& a, const unsigned char* b)
  {
    for (size_t i = 0; i < a.size(); ++i)
    {
      if (a[i] & b[i])
      {
        return true;
      }
    }
    return false;
  }

  static bool Marked(const unsigned char* bits, size_t bin)
  {
    return ((bits[bin / 8] >> (bin % 8)) & 1) != 0;
  }

  size_t Index(int i, int j, int k) const
  {
    return i + static_cast<size_t>(this->Bins[0]) * (j + static_cast<size_t>(this->Bins[1]) * k);
  }

  double Origin[3];
  double Size[3];
  int Bins[3];
  std::vector<unsigned char> Bits;
};

// The cells of grid whose bounding boxes grown by depth meet the bins marked in `bits`, with
// their points and arrays.
vtkSmartPointer<vtkUnstructuredGrid> CellsNear(
  vtkUnstructuredGrid* grid, const BinMask& mask, const unsigned char* bits, double depth);

// A point's key: its global id (first value) or its coordinates.
std::array<double, 3> PointKey(vtkDataSet* grid, vtkIdType i, bool byId);

}
}

#endif
