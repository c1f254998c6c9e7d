// Peak memory of a multi-light propagation update, measured by counting every allocation
// of this program. It is an executable of its own: it replaces the global operator new and
// delete (all their forms, the aligned ones that large arrays use included, so that every
// allocation and release goes through the same counting pair), which a sanitizer build must not
// have in its other tests.
#include "IlluminationTestUtilities.h"
#include "vtkMultiLightIlluminationVolume.h"

#include "vtkMath.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>

namespace
{
std::atomic<long long> CurrentBytes(0);
std::atomic<long long> PeakBytes(0);

// Adds an allocation of `size` bytes to the count and raises the peak to it.
void CountAllocation(std::size_t size) noexcept
{
  const long long now = CurrentBytes += static_cast<long long>(size);
  long long peak = PeakBytes.load();
  while (now > peak && !PeakBytes.compare_exchange_weak(peak, now))
  {
  }
}

// Every block carries its size in a header of max_align_t alignment.
void* CountedAllocate(std::size_t size) noexcept
{
  auto* block = static_cast<std::size_t*>(std::malloc(size + sizeof(std::max_align_t)));
  if (!block)
  {
    return nullptr;
  }
  *block = size;
  CountAllocation(size);
  return reinterpret_cast<char*>(block) + sizeof(std::max_align_t);
}

void CountedRelease(void* p) noexcept
{
  if (p)
  {
    auto* block = reinterpret_cast<std::size_t*>(static_cast<char*>(p) - sizeof(std::max_align_t));
    CurrentBytes -= static_cast<long long>(*block);
    std::free(block);
  }
}

void* AllocateOrThrow(std::size_t size)
{
  void* p = CountedAllocate(size);
  if (!p)
  {
    throw std::bad_alloc();
  }
  return p;
}

// The aligned forms: the block is aligned by hand within a larger one, its size and the
// larger block's start kept just before it.
struct AlignedHeader
{
  std::size_t Size;
  void* Base;
};

void* CountedAllocateAligned(std::size_t size, std::align_val_t alignment) noexcept
{
  const std::size_t align = std::max(static_cast<std::size_t>(alignment), alignof(AlignedHeader));
  const std::size_t extra = align + sizeof(AlignedHeader);
  if (size > std::numeric_limits<std::size_t>::max() - extra)
  {
    return nullptr;
  }
  char* base = static_cast<char*>(std::malloc(size + extra));
  if (!base)
  {
    return nullptr;
  }
  const std::uintptr_t first = reinterpret_cast<std::uintptr_t>(base) + sizeof(AlignedHeader);
  char* block =
    base + ((first + align - 1) / align * align - reinterpret_cast<std::uintptr_t>(base));
  reinterpret_cast<AlignedHeader*>(block)[-1] = { size, base };
  CountAllocation(size);
  return block;
}

void CountedReleaseAligned(void* p, std::align_val_t) noexcept
{
  if (p)
  {
    const AlignedHeader header = static_cast<AlignedHeader*>(p)[-1];
    CurrentBytes -= static_cast<long long>(header.Size);
    std::free(header.Base);
  }
}

void* AllocateAlignedOrThrow(std::size_t size, std::align_val_t alignment)
{
  void* p = CountedAllocateAligned(size, alignment);
  if (!p)
  {
    throw std::bad_alloc();
  }
  return p;
}
}

void* operator new(std::size_t size, std::align_val_t alignment)
{
  return AllocateAlignedOrThrow(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment)
{
  return AllocateAlignedOrThrow(size, alignment);
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
  return CountedAllocateAligned(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
  return CountedAllocateAligned(size, alignment);
}
void operator delete(void* p, std::align_val_t alignment) noexcept
{
  CountedReleaseAligned(p, alignment);
}
void operator delete[](void* p, std::align_val_t alignment) noexcept
{
  CountedReleaseAligned(p, alignment);
}
void operator delete(void* p, std::size_t, std::align_val_t alignment) noexcept
{
  CountedReleaseAligned(p, alignment);
}
void operator delete[](void* p, std::size_t, std::align_val_t alignment) noexcept
{
  CountedReleaseAligned(p, alignment);
}
void operator delete(void* p, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
  CountedReleaseAligned(p, alignment);
}
void operator delete[](void* p, std::align_val_t alignment, const std::nothrow_t&) noexcept
{
  CountedReleaseAligned(p, alignment);
}

void* operator new(std::size_t size)
{
  return AllocateOrThrow(size);
}
void* operator new[](std::size_t size)
{
  return AllocateOrThrow(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept
{
  return CountedAllocate(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept
{
  return CountedAllocate(size);
}
void operator delete(void* p) noexcept
{
  CountedRelease(p);
}
void operator delete[](void* p) noexcept
{
  CountedRelease(p);
}
void operator delete(void* p, std::size_t) noexcept
{
  CountedRelease(p);
}
void operator delete[](void* p, std::size_t) noexcept
{
  CountedRelease(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept
{
  CountedRelease(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept
{
  CountedRelease(p);
}

// Peak bytes allocated by a full update at scale 1, per illumination point: the 32-bit
// fixed-point illumination (12) and the extinction-only classification (2, packed); the
// slice and row buffers are counted apart. With the float output (12, allocated by VTK with
// malloc, which this count does not see) that makes 26.
TEST(PeakMemory, MultiLightUpdateNeedsAtMost26BytesPerPoint)
{
  auto image = volillumtest::PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 64);
  auto otf = volillumtest::RampOpacity(image, 0.3);
  auto filter = volillumtest::ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
  filter->AddLight(volillumtest::PointLight(-40, 30, 20));
  filter->AddLight(volillumtest::DirectionalLight(0.3, -0.2, -1));
  const long long base = CurrentBytes.load();
  PeakBytes = base;
  filter->Update();
  const double points = static_cast<double>(image->GetNumberOfPoints());
  const double perPoint = double(PeakBytes.load() - base) / points;
  const double buffers = double(filter->GetLastPeakBufferBytes()) / points;
  std::cout << "peak " << perPoint << " bytes per point (slice buffers " << buffers << ")"
            << std::endl;
  EXPECT_LE(perPoint - buffers, 14.5);
}

TEST(PeakMemory, MultiLightMemoryDoesNotGrowWithLightsBeyondSliceBuffers)
{
  auto image = volillumtest::PhantomScene(vtkIlluminationPhantomSource::ThreeSpheres, 48);
  auto otf = volillumtest::RampOpacity(image, 0.3);
  auto peakFor = [&](int count, size_t& buffers)
  {
    auto filter = volillumtest::ImageFilter<vtkMultiLightIlluminationVolume>(image, otf);
    for (int i = 0; i < count; ++i)
    {
      const double angle = 2.0 * vtkMath::Pi() * i / count;
      filter->AddLight(
        volillumtest::PointLight(24 + 60 * std::cos(angle), 24 + 60 * std::sin(angle), 30));
    }
    const long long base = CurrentBytes.load();
    PeakBytes = base;
    filter->Update();
    buffers = filter->GetLastPeakBufferBytes();
    return PeakBytes.load() - base;
  };
  size_t buffers1 = 0, buffers64 = 0;
  const long long one = peakFor(1, buffers1);
  const long long many = peakFor(64, buffers64);
  std::cout << "peak bytes: 1 light " << one << " (buffers " << buffers1 << "), 64 lights " << many
            << " (buffers " << buffers64 << ")" << std::endl;
  EXPECT_LE(double(many - buffers64), 1.1 * double(one - buffers1));
}
