#pragma once
/// @file HostMemory.h
/// @brief Host memory on transparent huge pages, for the few large CPU buffers that are read scattered.
#include <cstddef>

namespace tissuemosaic {

/// Where a CPU Buffer's memory comes from.
enum class HostPages {
  Normal,  ///< new[]: the heap, 4 KiB pages
  Huge,    ///< its own mapping, advised onto 2 MiB huge pages (Linux's madvise mode); for large buffers read a few
           ///< hundred bytes at a time all over (the stereo cost volume: with 4 KiB pages nearly every read there
           ///< misses the TLB). A mapping of its own, so that freed huge pages never back other allocations.
};

/// Maps `bytes` (rounded up to 2 MiB) with the huge-page advice; where huge pages are off, the mapping simply stays
/// on normal pages. Throws std::bad_alloc when the memory is not there. Release with releaseHugePageMemory.
void* allocateHugePageMemory(std::size_t bytes);
void releaseHugePageMemory(void* memory, std::size_t bytes);

}  // namespace tissuemosaic
