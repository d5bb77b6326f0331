#include "HostMemory.h"

#include <cstdlib>
#include <new>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tissuemosaic {

namespace {
constexpr std::size_t kCacheLineBytes = 64;
constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

std::size_t roundUp(std::size_t bytes, std::size_t alignment) { return (bytes + alignment - 1) / alignment * alignment; }
}  // namespace

void* allocateHostMemory(std::size_t bytes) {
  const std::size_t alignment = bytes >= kHugePageThresholdBytes ? kHugePageBytes : kCacheLineBytes;
  const std::size_t rounded = roundUp(bytes == 0 ? 1 : bytes, alignment);  // aligned_alloc wants a multiple
  void* memory = std::aligned_alloc(alignment, rounded);
  if (!memory) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Only advice: where huge pages are off or unavailable the memory simply stays on normal pages.
  if (alignment == kHugePageBytes) madvise(memory, rounded, MADV_HUGEPAGE);
#endif
  return memory;
}

void releaseHostMemory(void* memory) { std::free(memory); }

}  // namespace tissuemosaic
