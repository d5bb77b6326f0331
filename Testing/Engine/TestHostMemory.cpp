// CPU buffers on huge pages: the same contents and ownership rules as normal buffers.
#include "Core/Buffer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>

using namespace tissuemosaic;

namespace {

/// Kibibytes of the calling process's anonymous memory on huge pages (-1 where /proc says nothing).
long anonHugePagesKib() {
  std::ifstream smaps("/proc/self/smaps_rollup");
  std::string key;
  long value = -1;
  while (smaps >> key) {
    if (key == "AnonHugePages:") {
      smaps >> value;
      return value;
    }
  }
  return -1;
}

}  // namespace

TEST(HostMemory, HugePageBufferHoldsItsContentsThroughMoves) {
  const std::size_t count = (std::size_t{5} << 20) + 123;  // 10 MB of int16 and a partial 2 MiB page
  Buffer<int16_t> buffer(Device::Cpu, count, HostPages::Huge);
  ASSERT_EQ(buffer.size(), count);
  for (std::size_t i = 0; i < count; ++i) buffer.data()[i] = static_cast<int16_t>(i * 7);
  Buffer<int16_t> moved(std::move(buffer));
  EXPECT_EQ(buffer.size(), 0u);
  EXPECT_EQ(buffer.data(), nullptr);
  Buffer<int16_t> assigned(Device::Cpu, 10);  // a normal buffer, released on assignment
  assigned = std::move(moved);
  ASSERT_EQ(assigned.size(), count);
  for (std::size_t i = 0; i < count; i += 4099) ASSERT_EQ(assigned.data()[i], static_cast<int16_t>(i * 7)) << i;
  EXPECT_EQ(assigned.data()[count - 1], static_cast<int16_t>((count - 1) * 7));
  // Copies between kinds of memory work as between normal buffers.
  Buffer<int16_t> normal(Device::Cpu, count);
  normal.copyFrom(assigned);
  EXPECT_EQ(normal.data()[count - 1], assigned.data()[count - 1]);
  // Informational: whether the kernel gave huge pages depends on its settings (madvise or always).
  std::printf("anonymous huge pages of this process: %ld KiB\n", anonHugePagesKib());
}

TEST(HostMemory, EmptyHugePageBufferHasNoMemory) {
  Buffer<float> empty(Device::Cpu, 0, HostPages::Huge);
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(empty.data(), nullptr);
}
