// The whole pipeline on CUDA against the CPU (ctest label "cuda"; skipped with a message where no GPU exists). On
// CUDA, stereo runs on a second thread and stream beside the tracking, and the surface beside the key-frame
// matching, and the intermediate frames are matched beside the earlier key frames: each frame must still get its own
// disparity, the same tracking decisions, poses and model as on the CPU, bit for bit (every stage computes the same
// floats on both backends: the stereo, ORB, sub-pixel, solver and fusion tests check each one). The CUDA pipeline
// runs as `reconstruct` does, its frames' maps left on the device (the surface measured from the matcher's map there).
#include "SyntheticScan.h"

#include "Core/Device.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "StereoTestUtilities.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

using namespace tissuemosaic;
using test::sameDisparity;

TEST(ReconstructionPipelineCuda, ReconstructsLikeTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  synthetic::SyntheticScanOptions options;  // 960x540
  options.frames = 32;
  options.seed = 11;
  const synthetic::SyntheticScan scan(options);
  ReconstructionParameters parameters;
  parameters.extractor = FeatureExtractor::TissueMosaicOrb;  // the GPU's extractor, on both devices
  ReconstructionPipeline cpu(scan.geometry(), parameters, Device::Cpu, scan.T_world_camera(0));
  ReconstructionPipeline gpu(scan.geometry(), parameters, Device::Cuda, scan.T_world_camera(0));
  gpu.setFrameDisparityKept(false);
  double worstMm = 0, worstDeg = 0;
  int keyFrames = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    const FrameResult a = cpu.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    const FrameResult b = gpu.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    // The automatic disparity range (the default) comes from ORB features, identical on both devices.
    ASSERT_EQ(a.disparityRange, b.disparityRange) << "frame " << k << ": " << a.disparityRange.text() << " against "
                                                  << b.disparityRange.text();
    ASSERT_TRUE(b.disparityPx.empty()) << "frame " << k;
    ASSERT_TRUE(sameDisparity(a.disparityPx, gpu.downloadLastDisparity())) << "frame " << k;
    ASSERT_EQ(a.tracked, b.tracked) << "frame " << k;
    ASSERT_EQ(a.keyFrame, b.keyFrame) << "frame " << k;
    EXPECT_TRUE(b.tracked) << "frame " << k << ": " << b.trackingMessage;
    EXPECT_GT(b.timesMs.stereo, 0.0);
    keyFrames += b.keyFrame;
    const Eigen::Matrix4d& p = a.T_world_camera;
    const Eigen::Matrix4d& q = b.T_world_camera;
    worstMm = std::max(worstMm, (p.block<3, 1>(0, 3) - q.block<3, 1>(0, 3)).norm());
    worstDeg = std::max(worstDeg, Eigen::AngleAxisd(Eigen::Matrix3d(p.block<3, 3>(0, 0).transpose() *
                                                                    q.block<3, 3>(0, 0))).angle() * 180 / M_PI);
  }
  const std::size_t cpuPoints = cpu.modelPointCount(), gpuPoints = gpu.modelPointCount();
  std::printf("CUDA against CPU over %d frames, %d key frames: poses differ by at most %.2e mm and %.2e deg; model "
              "%zu against %zu points\n", scan.frameCount(), keyFrames, worstMm, worstDeg, gpuPoints, cpuPoints);
  EXPECT_GE(keyFrames, 3);
  EXPECT_EQ(worstMm, 0.0);
  EXPECT_EQ(worstDeg, 0.0);
  EXPECT_EQ(gpuPoints, cpuPoints);
}
