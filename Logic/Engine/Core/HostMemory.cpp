#include "HostMemory.h"

#include <cstdlib>
#include <new>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tissuemosaic {

namespace {
constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;
std::size_t roundToHugePages(std::size_t bytes) { return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes; }
}  // namespace

#if defined(__linux__)
void* allocateHugePageMemory(std::size_t bytes) {
  const std::size_t mapped = roundToHugePages(bytes == 0 ? 1 : bytes);
  void* memory = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (memory == MAP_FAILED) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
  madvise(memory, mapped, MADV_HUGEPAGE);  // advice only: without huge pages the mapping keeps normal pages
#endif
  return memory;
}

void releaseHugePageMemory(void* memory, std::size_t bytes) {
  if (memory) munmap(memory, roundToHugePages(bytes == 0 ? 1 : bytes));
}
#else
void* allocateHugePageMemory(std::size_t bytes) {
  void* memory = std::malloc(bytes == 0 ? 1 : bytes);
  if (!memory) throw std::bad_alloc();
  return memory;
}
void releaseHugePageMemory(void* memory, std::size_t) { std::free(memory); }
#endif

}  // namespace tissuemosaic
