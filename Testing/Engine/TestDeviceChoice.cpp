// Where no GPU is usable, asking for CUDA is an error that says why, never a silent fallback to the CPU; "auto"
// takes the CPU. (Not among the CUDA tests: there every test must run, and this one can only run without a GPU.)
#include "Core/Device.h"
#include "Core/Error.h"
#include "Stereo/StereoMatcher.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;

TEST(StereoDeviceChoice, GpuRequestRefusedWithoutGpu) {
  if (cudaAvailable()) GTEST_SKIP() << "a GPU is present: the refusal path cannot be exercised here";
  EXPECT_THROW(StereoMatcher(Device::Cuda, StereoParameters{}), Error);
  EXPECT_THROW(parseDevice("cuda"), Error);
  EXPECT_EQ(parseDevice("auto"), Device::Cpu);
}
