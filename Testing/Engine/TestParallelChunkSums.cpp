// parallelChunkSums' contract on the CPU backend: every chunk's sums, empty and ragged chunks included, the skip flag,
// and the summation order of a CUDA block (so that both backends give the same bits). The CUDA backend is held to
// the CPU's results bit for bit by ReconstructionPipelineCuda.ReconstructsLikeTheCpu, whose pose LM sums its
// normal-equation terms with it.
#include "Core/ParallelChunkSums.h"

#include <gtest/gtest.h>

#include <vector>

using namespace tissuemosaic;

namespace {

/// Three values per item, whole numbers: any order of addition gives the exact sums.
struct WholeValues {
  TM_HOST_DEVICE void operator()(int64_t i, double out[3]) const {
    out[0] = static_cast<double>(i % 7);
    out[1] = 1.0;
    out[2] = static_cast<double>(1000 * i);
  }
};

struct ListedValues {
  const double* values;
  TM_HOST_DEVICE void operator()(int64_t i, double out[1]) const { out[0] = values[i]; }
};

}  // namespace

TEST(ParallelChunkSums, SumsEveryChunkIncludingEmptyAndLongOnes) {
  // Chunks of 0, 1, 255, 256, 257 and 600 items (longer than a CUDA block: threads take several items).
  const std::vector<int> chunkBegin{0, 0, 1, 256, 512, 769, 1369};
  const int chunks = static_cast<int>(chunkBegin.size()) - 1;
  std::vector<double> sums(3 * chunks, -1.0);
  parallelChunkSums<CpuBackend, 3>(chunks, chunkBegin.data(), WholeValues{}, sums.data());
  for (int c = 0; c < chunks; ++c) {
    double expected[3] = {0, 0, 0};
    for (int64_t i = chunkBegin[c]; i < chunkBegin[c + 1]; ++i) {
      expected[0] += static_cast<double>(i % 7);
      expected[1] += 1.0;
      expected[2] += static_cast<double>(1000 * i);
    }
    for (int k = 0; k < 3; ++k) EXPECT_EQ(sums[3 * c + k], expected[k]) << "chunk " << c << ", value " << k;
  }
  EXPECT_EQ(sums[3 * 0 + 1], 0.0);  // the empty chunk is written, as zero
  EXPECT_EQ(sums[3 * 5 + 1], 600.0);
}

TEST(ParallelChunkSums, AddsInTheOrderOfACudaBlock) {
  // 1e16 + 1 rounds back to 1e16. In item order the sum is (1e16 - 1e16) + 1 = 1; a CUDA block adds lane 2 (the 1)
  // to lane 0 before lane 1 (the -1e16) joins, which loses the 1: the CPU must lose it too.
  const std::vector<double> values{1e16, -1e16, 1.0, 0.0, 0.0};
  const std::vector<int> chunkBegin{0, static_cast<int>(values.size())};
  double sum = -1.0;
  parallelChunkSums<CpuBackend, 1>(1, chunkBegin.data(), ListedValues{values.data()}, &sum);
  EXPECT_EQ(sum, 0.0);
  // Items kChunkSumThreads apart fall to one thread, which adds them before the warp's tree: thread 0 adds 1e16 and
  // -1e16 (item kChunkSumThreads) to 0, thread 1 holds the 1, and the tree keeps it. In item order the 1 is lost.
  std::vector<double> strided(kChunkSumThreads + 1, 0.0);
  strided[0] = 1e16;
  strided[1] = 1.0;
  strided[kChunkSumThreads] = -1e16;
  const std::vector<int> stridedBegin{0, static_cast<int>(strided.size())};
  parallelChunkSums<CpuBackend, 1>(1, stridedBegin.data(), ListedValues{strided.data()}, &sum);
  EXPECT_EQ(sum, 1.0);
}

TEST(ParallelChunkSums, SkipFlagLeavesTheSumsAlone) {
  const std::vector<int> chunkBegin{0, 10, 20};
  std::vector<double> sums(6, -1.0);
  const int skip = 1;
  parallelChunkSums<CpuBackend, 3>(2, chunkBegin.data(), WholeValues{}, sums.data(), &skip);
  for (double s : sums) EXPECT_EQ(s, -1.0);
  const int run = 0;
  parallelChunkSums<CpuBackend, 3>(2, chunkBegin.data(), WholeValues{}, sums.data(), &run);
  EXPECT_EQ(sums[1], 10.0);
  EXPECT_EQ(sums[4], 10.0);
}
