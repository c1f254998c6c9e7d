/**
 * @file LargeArrays.h
 * @brief Memory for arrays of hundreds of megabytes that are written right after they are
 * allocated (the classification, the fixed-point illumination and its record, summed-area
 * tables, the filters' output arrays).
 *
 * The first write to each 4 KiB page of new memory costs a page fault: ~0.5 s for the 200 MB
 * of an illumination volume of 256^3 points on a VM (measured). On Linux such memory is
 * aligned to 2 MiB and offered to transparent huge pages, which fault 512 times less often;
 * elsewhere, and below one huge page, memory is allocated as usual.
 */
#ifndef LargeArrays_h
#define LargeArrays_h

#include "VolIllumKernelsModule.h"

#include <cstddef>
#include <new>
#include <vector>

namespace volillum
{

/// Whether an allocation of `bytes` is offered to huge pages: then it is aligned to
/// HugePageAlignment, and AdviseHugePages offers the whole huge pages it spans before its
/// first write (its last part, short of a huge page, keeps small pages).
VOLILLUMKERNELS_EXPORT bool OffersHugePages(std::size_t bytes);
constexpr std::size_t HugePageAlignment = std::size_t(1) << 21;
VOLILLUMKERNELS_EXPORT void AdviseHugePages(void* memory, std::size_t bytes);

/// `bytes` of memory offered to huge pages, released with std::free (for arrays that free
/// their memory so, as vtkDataArray's VTK_DATA_ARRAY_FREE), or null when huge pages are not
/// offered or the allocation fails: the caller then allocates as usual.
VOLILLUMKERNELS_EXPORT void* AllocateHugePages(std::size_t bytes);

/// A std::vector allocator that offers large allocations to huge pages (through the aligned
/// operator new, so that replacements of it see them).
template <typename T>
struct LargeArrayAllocator
{
  using value_type = T;

  LargeArrayAllocator() = default;
  template <typename U>
  LargeArrayAllocator(const LargeArrayAllocator<U>&)
  {
  }

  T* allocate(std::size_t n)
  {
    const std::size_t bytes = n * sizeof(T);
    if (!OffersHugePages(bytes))
    {
      return static_cast<T*>(::operator new(bytes));
    }
    void* memory = ::operator new(bytes, std::align_val_t(HugePageAlignment));
    AdviseHugePages(memory, bytes);
    return static_cast<T*>(memory);
  }
  void deallocate(T* memory, std::size_t n)
  {
    if (OffersHugePages(n * sizeof(T)))
    {
      ::operator delete(memory, std::align_val_t(HugePageAlignment));
    }
    else
    {
      ::operator delete(memory);
    }
  }

  template <typename U>
  bool operator==(const LargeArrayAllocator<U>&) const
  {
    return true;
  }
  template <typename U>
  bool operator!=(const LargeArrayAllocator<U>&) const
  {
    return false;
  }
};

/// A vector for large arrays (LargeArrayAllocator).
template <typename T>
using LargeVector = std::vector<T, LargeArrayAllocator<T>>;

}

#endif
