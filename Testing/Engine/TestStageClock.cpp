// StageClock on the CPU: one duration per mark, each the time between two marks. The checks compare each stage with
// steady-clock readings taken just outside its marks, never with a fixed number of milliseconds: a loaded machine
// may pause the test anywhere, and the checks still hold (a stage lies within the readings around it, and is at least
// the sleep inside it).
#include "Core/StageClock.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

using namespace tissuemosaic;

namespace {

using Clock = std::chrono::steady_clock;

double milliseconds(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

/// One stage's duration against what happened around it: at least `sleptMs` (the work inside), at most the readings
/// taken just before its start mark and just after its end mark. Returns what is wrong, or "" when nothing is.
std::string checkStage(double stageMs, double sleptMs, double outerMs) {
  if (stageMs < sleptMs) return std::to_string(stageMs) + " ms is shorter than the " + std::to_string(sleptMs) + " ms inside";
  if (stageMs > outerMs) return std::to_string(stageMs) + " ms is longer than the " + std::to_string(outerMs) + " ms around";
  return "";
}

}  // namespace

TEST(StageClock, CpuStagesAreTheTimesBetweenMarks) {
  const Clock::time_point beforeStart = Clock::now();
  StageClock clock(Device::Cpu);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  const Clock::time_point beforeFirst = Clock::now();
  clock.mark();
  const Clock::time_point afterFirst = Clock::now();
  clock.mark();  // an empty stage
  const Clock::time_point afterSecond = Clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  clock.mark();
  const Clock::time_point afterThird = Clock::now();
  const std::vector<double> stages = clock.stageMilliseconds();
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_EQ(checkStage(stages[0], 30.0, milliseconds(beforeStart, afterFirst)), "");
  EXPECT_EQ(checkStage(stages[1], 0.0, milliseconds(beforeFirst, afterSecond)), "");  // the empty stage
  EXPECT_EQ(checkStage(stages[2], 10.0, milliseconds(afterFirst, afterThird)), "");
  // Negative controls, on fixed numbers (wall-clock ones could pass by a pause at the wrong moment): a stage shorter
  // than the sleep inside it, or longer than the readings around it, fails.
  EXPECT_NE(checkStage(29.0, 30.0, 45.0), "");
  EXPECT_NE(checkStage(46.0, 30.0, 45.0), "");
}
