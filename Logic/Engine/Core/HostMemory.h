#pragma once
/// @file HostMemory.h
/// @brief Host allocations for the CPU backend's buffers: large ones on transparent huge pages.
#include <cstddef>

namespace tissuemosaic {

/// Allocates `bytes` aligned to a cache line; allocations of kHugePageThresholdBytes and more are aligned to 2 MiB
/// and advised onto huge pages (Linux's madvise mode). The stereo cost volume is about 100 MB that the re-selection
/// reads a few hundred bytes at a time across whole rows: with 4 KiB pages nearly every read misses the TLB.
/// Throws std::bad_alloc when the memory is not there. Release with releaseHostMemory.
void* allocateHostMemory(std::size_t bytes);
void releaseHostMemory(void* memory);

constexpr std::size_t kHugePageThresholdBytes = std::size_t{4} << 20;

}  // namespace tissuemosaic
