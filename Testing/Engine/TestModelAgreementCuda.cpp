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

/// A 480x270 scan with breathing and an instrument, fused every 10th frame and its other frames' agreement and
/// motion evidence applied, on both devices; the figures of every frame must agree.
struct BothDevices {
  synthetic::SyntheticScan scan;
  PointFusion cpu, gpu;
  int removed = 0;

  static synthetic::SyntheticScanOptions options(int frames) {
    synthetic::SyntheticScanOptions o;
    o.width = 480;
    o.height = 270;
    o.frames = frames;
    o.seed = 5;
    o.hardMode.breathingAmplitudeMm = 2;
    o.hardMode.breathingPeriodS = 1;
    o.hardMode.instruments = 1;
    return o;
  }

  BothDevices(int frames, const FusionParameters& parameters)
      : scan(options(frames)),
        cpu(scan.geometry(), parameters, Device::Cpu),
        gpu(scan.geometry(), parameters, Device::Cuda) {
    const RectifiedGeometry& g = scan.geometry();
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
      const int removedCpu = cpu.updateMotion(frame.disparityPx, frame.T_world_camera, a);
      EXPECT_EQ(removedCpu, gpu.updateMotion(frame.disparityPx, frame.T_world_camera, b)) << "frame " << k;
      EXPECT_EQ(cpu.movedTissueMarkerCount(), gpu.movedTissueMarkerCount()) << "frame " << k;
      EXPECT_EQ(cpu.retiredMarkerCount(), gpu.retiredMarkerCount()) << "frame " << k;
      removed += removedCpu;
    }
  }
};

}  // namespace

TEST(ModelAgreementCuda, MeasuresAndRemovesLikeTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  BothDevices both(30, FusionParameters{});
  const synthetic::SyntheticScan& scan = both.scan;
  PointFusion &cpu = both.cpu, &gpu = both.gpu;
  std::printf("agreement and motion on 480x270 with breathing and an instrument: %d points left on both devices, "
              "%zu remain\n", both.removed, cpu.pointCount());
  EXPECT_GT(both.removed, 0);
  EXPECT_EQ(cpu.pointCount(), gpu.pointCount());
  EXPECT_EQ(differingModelPoints(cpu.download(), gpu.download()), 0);
  // A pose 5 mm off: the same (collapsed) figures.
  const synthetic::SyntheticScanFrame frame = scan.renderFrame(15);
  Eigen::Matrix4d off = frame.T_world_camera;
  off(2, 3) += 5;
  expectSameAgreement(cpu.measureAgreement(frame.disparityPx, off, 1), gpu.measureAgreement(frame.disparityPx, off, 1),
                      "5 mm off, every pixel");
}

// Markers that frames put back at their place come back to life, those they put elsewhere retire
// (FusionParameters::markerRestFrames, here 2 frames so that the breathing scan does both between breaths): the
// same markers on both devices, frame by frame.
TEST(ModelAgreementCuda, RevivesAndRetiresMarkersLikeTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  FusionParameters parameters;
  parameters.markerRestFrames = 2;
  BothDevices both(60, parameters);
  const std::size_t retired = both.cpu.retiredMarkerCount();
  const std::size_t revived = static_cast<std::size_t>(both.removed) - both.cpu.movedTissueMarkerCount() - retired;
  std::printf("markers after 2 frames at rest: %d points left, %zu came back, %zu retired, on both devices\n",
              both.removed, revived, retired);
  EXPECT_GT(revived, 0u);
  EXPECT_GT(retired, 0u);
  EXPECT_EQ(both.cpu.pointCount(), both.gpu.pointCount());
  EXPECT_EQ(differingModelPoints(both.cpu.download(), both.gpu.download()), 0);
}
