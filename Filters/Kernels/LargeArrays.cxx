#include "LargeArrays.h"

#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace volillum
{

bool OffersHugePages(std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  return bytes >= HugePageAlignment;
#else
  (void)bytes;
  return false;
#endif
}

void AdviseHugePages(void* memory, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  madvise(memory, bytes / HugePageAlignment * HugePageAlignment, MADV_HUGEPAGE);
#else
  (void)memory;
  (void)bytes;
#endif
}

void* AllocateHugePages(std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (!OffersHugePages(bytes))
  {
    return nullptr;
  }
  // aligned_alloc wants a whole number of alignments.
  const std::size_t rounded =
    (bytes + HugePageAlignment - 1) / HugePageAlignment * HugePageAlignment;
  void* memory = std::aligned_alloc(HugePageAlignment, rounded);
  if (memory)
  {
    AdviseHugePages(memory, rounded);
  }
  return memory;
#else
  (void)bytes;
  return nullptr;
#endif
}

}
