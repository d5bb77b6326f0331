// The model agreement and the motion evidence on CUDA against the CPU (ctest label "cuda"; skipped with a message
// where no GPU exists): the same functors with the same float operations and integer counters, so the agreement's
// counts and figures and the model after the motion evidence must be identical, bit for bit.
#include "FusionTestScene.h"
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Fusion/PointFusion.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace tissuemosaic;

namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

long differingModelPoints(const ModelPoints& a, const ModelPoints& b) {
  EXPECT_EQ(a.size(), b.size());
  long differ = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    const cv::Point3f &p = a.cloud.pointsMm[i], &q = b.cloud.pointsMm[i];
    differ += !sameBits(p.x, q.x) || !sameBits(p.y, q.y) || !sameBits(p.z, q.z) || !sameBits(a.weights[i], b.weights[i]) ||
              a.cloud.colorsRgb[i] != b.cloud.colorsRgb[i];
  }
  return differ;
}

void expectSameAgreement(const ModelAgreement& cpu, const ModelAgreement& gpu, const char* what) {
  EXPECT_EQ(cpu.measured, gpu.measured) << what;
  EXPECT_EQ(cpu.measuredSamples, gpu.measuredSamples) << what;
  EXPECT_EQ(cpu.overlapSamples, gpu.overlapSamples) << what;
  EXPECT_TRUE(cpu.medianDepthDifferenceMm == gpu.medianDepthDifferenceMm ||
              (std::isnan(cpu.medianDepthDifferenceMm) && std::isnan(gpu.medianDepthDifferenceMm))) << what;
  EXPECT_TRUE(cpu.shareWithin1mm == gpu.shareWithin1mm || (std::isnan(cpu.shareWithin1mm) && std::isnan(gpu.shareWithin1mm)))
      << what;
}

}  // namespace

TEST(ModelAgreementCuda, MeasuresAndRemovesLikeTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  synthetic::SyntheticScanOptions options;
  options.width = 480;
  options.height = 270;
  options.frames = 30;
  options.seed = 5;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.breathingPeriodS = 1;
  options.hardMode.instruments = 1;
  const synthetic::SyntheticScan scan(options);
  const RectifiedGeometry& g = scan.geometry();
  PointFusion cpu(g, FusionParameters{}, Device::Cpu), gpu(g, FusionParameters{}, Device::Cuda);
  int removedCpu = 0, removedGpu = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    if (k % 10 == 0) {  // "key frames": fused on both devices
      cpu.integrate(measureSurface(frame.disparityPx, frame.leftRectified, g, Device::Cpu), frame.T_world_camera);
      gpu.integrate(measureSurface(frame.disparityPx, frame.leftRectified, g, Device::Cuda), frame.T_world_camera);
      continue;
    }
    const ModelAgreement a = cpu.measureAgreement(frame.disparityPx, frame.T_world_camera, 2);
    const ModelAgreement b = gpu.measureAgreement(frame.disparityPx, frame.T_world_camera, 2);
    expectSameAgreement(a, b, cv::format("frame %d", k).c_str());
    removedCpu += cpu.updateMotion(frame.disparityPx, frame.T_world_camera, a);
    removedGpu += gpu.updateMotion(frame.disparityPx, frame.T_world_camera, b);
    ASSERT_EQ(removedCpu, removedGpu) << "frame " << k;
  }
  std::printf("agreement and motion on 480x270 with breathing and an instrument: %d points left on both devices, "
              "%zu remain\n", removedCpu, cpu.pointCount());
  EXPECT_GT(removedCpu, 0);
  EXPECT_EQ(cpu.pointCount(), gpu.pointCount());
  EXPECT_EQ(differingModelPoints(cpu.download(), gpu.download()), 0);
  // A pose 5 mm off: the same (collapsed) figures.
  const synthetic::SyntheticScanFrame frame = scan.renderFrame(15);
  Eigen::Matrix4d off = frame.T_world_camera;
  off(2, 3) += 5;
  expectSameAgreement(cpu.measureAgreement(frame.disparityPx, off, 1), gpu.measureAgreement(frame.disparityPx, off, 1),
                      "5 mm off, every pixel");
}
