// parallelChain's contract on the CPU backend: each loop covers its whole range before the next starts, in the
// order given, and an empty loop is skipped. The CUDA backend (one block, a barrier between loops) is held to the
// same results by RefinementCuda.*, whose pose LM runs its per-frame steps as chains and must equal the CPU bit for
// bit.
#include "Core/ParallelChain.h"

#include <gtest/gtest.h>

#include <numeric>
#include <vector>

using namespace tissuemosaic;

namespace {

struct Fill {
  int* values;
  TM_HOST_DEVICE void operator()(int64_t i) const { values[i] = static_cast<int>(3 * i + 1); }
};

/// Reads what the previous loop wrote at the mirrored index: only right when that loop has finished.
struct Mirror {
  const int* from;
  int* to;
  int64_t count;
  TM_HOST_DEVICE void operator()(int64_t i) const { to[i] = from[count - 1 - i] + from[i]; }
};

struct Total {
  const int* values;
  int64_t count;
  long long* total;
  TM_HOST_DEVICE void operator()(int64_t) const {
    for (int64_t i = 0; i < count; ++i) *total += values[i];
  }
};

struct MustNotRun {
  int* calls;
  TM_HOST_DEVICE void operator()(int64_t) const { ++*calls; }
};

}  // namespace

TEST(ParallelChain, EachLoopFinishesBeforeTheNextInTheOrderGiven) {
  const int64_t n = 1000;  // more items than a CUDA chain's block has threads
  std::vector<int> a(n, -1), b(n, -1);
  long long total = 0;
  int emptyCalls = 0;
  parallelChain<CpuBackend>(chainLoop(n, Fill{a.data()}), chainLoop(0, MustNotRun{&emptyCalls}),
                            chainLoop(n, Mirror{a.data(), b.data(), n}), chainLoop(1, Total{b.data(), n, &total}));
  for (int64_t i = 0; i < n; ++i) {
    ASSERT_EQ(a[i], 3 * i + 1);
    ASSERT_EQ(b[i], (3 * (n - 1 - i) + 1) + (3 * i + 1)) << "item " << i;
  }
  // Every b[i] = 3 (n - 1) + 2.
  EXPECT_EQ(total, n * (3 * (n - 1) + 2));
  EXPECT_EQ(emptyCalls, 0);
}
