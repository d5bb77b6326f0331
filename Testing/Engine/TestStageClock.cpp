// StageClock on the CPU: one duration per mark, each the time between two marks.
#include "Core/StageClock.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

using namespace tissuemosaic;

TEST(StageClock, CpuStagesAreTheTimesBetweenMarks) {
  StageClock clock(Device::Cpu);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  clock.mark();
  clock.mark();  // an empty stage
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  clock.mark();
  const std::vector<double> stages = clock.stageMilliseconds();
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_GE(stages[0], 30.0);
  EXPECT_LT(stages[0], 1000.0);
  EXPECT_GE(stages[1], 0.0);
  EXPECT_LT(stages[1], 5.0);
  EXPECT_GE(stages[2], 10.0);
  EXPECT_LT(stages[2], 1000.0);
}
