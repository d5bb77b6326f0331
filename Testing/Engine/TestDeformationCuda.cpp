// The deformation (fusion.deformation on, docs/DEFORMATION.md) with the CUDA pipeline against the CPU's (ctest label
// "cuda"; skipped with a message where no GPU exists). The fit runs on the CPU for both devices, on the frame's
// disparity that the CUDA stereo computes bit for bit as the CPU's: every frame's deformation figures and the graph
// must be the same, while the CUDA pipeline keeps its maps on the device (reconstruct's way); and the fused model,
// which follows the field (every point's motion computed on the host, applied by the fusion's kernels on each
// device), must be the same bit for bit, at rest and where the tissue is now.
#include "SyntheticScan.h"

#include "Core/Device.h"
#include "Fusion/PointModel.h"
#include "Reconstruction/ReconstructionPipeline.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

using namespace tissuemosaic;

TEST(DeformationCuda, FollowsTheTissueLikeTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  synthetic::SyntheticScanOptions options;
  options.width = 480;
  options.height = 270;
  options.frames = 16;
  options.seed = 7;
  options.supersampling = 1;
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;
  options.hardMode.breathingAmplitudeMm = 3;
  options.hardMode.breathingPeriodS = 1;  // the peak at frame 15
  options.hardMode.breathingRadiusMm = 14;
  const synthetic::SyntheticScan scan(options);
  ReconstructionParameters parameters;
  parameters.extractor = FeatureExtractor::TissueMosaicOrb;  // the GPU's extractor, on both devices
  parameters.fusion.deformation = true;
  ReconstructionPipeline cpu(scan.geometry(), parameters, Device::Cpu, scan.T_world_camera(0));
  ReconstructionPipeline gpu(scan.geometry(), parameters, Device::Cuda, scan.T_world_camera(0));
  gpu.setFrameDisparityKept(false);
  int fitted = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    const FrameResult a = cpu.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    const FrameResult b = gpu.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    ASSERT_TRUE(a.T_world_camera == b.T_world_camera) << "frame " << k;
    ASSERT_EQ(a.deformation.fitted, b.deformation.fitted) << "frame " << k;
    EXPECT_EQ(a.deformation.samples, b.deformation.samples) << "frame " << k;
    EXPECT_EQ(a.deformation.nodes, b.deformation.nodes) << "frame " << k;
    EXPECT_EQ(a.deformation.correspondences, b.deformation.correspondences) << "frame " << k;
    EXPECT_EQ(a.deformation.maxNodeMotionMm, b.deformation.maxNodeMotionMm) << "frame " << k;
    EXPECT_EQ(a.deformation.liveShareWithin1mm, b.deformation.liveShareWithin1mm) << "frame " << k;
    fitted += b.deformation.fitted;
  }
  EXPECT_GE(fitted, scan.frameCount() - 1);
  const auto& cpuNodes = cpu.deformationGraph()->nodes();
  const auto& gpuNodes = gpu.deformationGraph()->nodes();
  ASSERT_EQ(cpuNodes.size(), gpuNodes.size());
  for (std::size_t i = 0; i < cpuNodes.size(); ++i) {
    ASSERT_TRUE(cpuNodes[i].translationMm == gpuNodes[i].translationMm) << "node " << i;
  }
  const auto expectSameModel = [](const ModelPoints& a, const ModelPoints& b, const char* which) {
    ASSERT_EQ(a.size(), b.size()) << which;
    EXPECT_EQ(std::memcmp(a.cloud.pointsMm.data(), b.cloud.pointsMm.data(), a.size() * sizeof(cv::Point3f)), 0) << which;
    EXPECT_EQ(std::memcmp(a.cloud.normals.data(), b.cloud.normals.data(), a.size() * sizeof(cv::Point3f)), 0) << which;
    EXPECT_EQ(std::memcmp(a.cloud.colorsRgb.data(), b.cloud.colorsRgb.data(), a.size() * sizeof(cv::Vec3b)), 0) << which;
    EXPECT_EQ(std::memcmp(a.weights.data(), b.weights.data(), a.size() * sizeof(float)), 0) << which;
  };
  const ModelPoints cpuModel = cpu.modelSnapshot();
  expectSameModel(cpuModel, gpu.modelSnapshot(), "the model at rest");
  expectSameModel(cpu.liveModelSnapshot(), gpu.liveModelSnapshot(), "the live model");
  std::printf("CUDA against CPU over %d frames: %d fitted, %zu nodes, the same figures and node motions, the same "
              "fused model of %zu points at rest and live\n",
              scan.frameCount(), fitted, gpuNodes.size(), cpuModel.size());
}
