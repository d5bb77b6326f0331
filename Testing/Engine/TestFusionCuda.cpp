// The CUDA surface measurement and point fusion against the CPU ones (ctest label "cuda"; skipped with a message
// where no GPU exists). Both run the same functors with the same float operations, the z-buffer keeps a
// thread-order-independent minimum and new points are placed by a prefix sum, so counts, points, normals, colours and
// weights must be identical, and so must sampleVisible's samples. Inputs are rendered in-process.
#include "FusionTestScene.h"
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Fusion/PointFusion.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace tissuemosaic;

namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Pixels whose float channels differ in any bit (NaN = NaN).
long differingPixels(const cv::Mat& a, const cv::Mat& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_EQ(a.type(), b.type());
  long differ = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const cv::Vec3f p = a.at<cv::Vec3f>(y, x), q = b.at<cv::Vec3f>(y, x);
      bool same = true;
      for (int c = 0; c < 3; ++c) same = same && (sameBits(p[c], q[c]) || (std::isnan(p[c]) && std::isnan(q[c])));
      differ += !same;
    }
  return differ;
}

/// Model points whose position, normal, colour or weight differ in any bit; also the largest position difference.
long differingModelPoints(const ModelPoints& a, const ModelPoints& b, double& maxPositionMm) {
  EXPECT_EQ(a.size(), b.size());
  long differ = 0;
  maxPositionMm = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    const cv::Point3f &p = a.cloud.pointsMm[i], &q = b.cloud.pointsMm[i];
    const cv::Point3f &n = a.cloud.normals[i], &m = b.cloud.normals[i];
    maxPositionMm = std::max(maxPositionMm, cv::norm(cv::Point3d(p) - cv::Point3d(q)));
    differ += !sameBits(p.x, q.x) || !sameBits(p.y, q.y) || !sameBits(p.z, q.z) || !sameBits(n.x, m.x) ||
              !sameBits(n.y, m.y) || !sameBits(n.z, m.z) || a.cloud.colorsRgb[i] != b.cloud.colorsRgb[i] ||
              !sameBits(a.weights[i], b.weights[i]);
  }
  return differ;
}

synthetic::SyntheticScanOptions scanOptions() {
  synthetic::SyntheticScanOptions options;
  options.width = 480;
  options.height = 270;
  options.frames = 60;
  options.seed = 21;
  return options;
}

}  // namespace

TEST(FusionCuda, MeasuresTheSameSurfaceAsTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const synthetic::SyntheticScan scan(scanOptions());
  const synthetic::SyntheticScanFrame frame = scan.renderFrame(10);
  cv::Mat disparity = frame.disparityPx.clone(), noise(disparity.size(), CV_32F);
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.1);
  disparity += noise;
  const SurfaceMeasurement cpu = measureSurface(disparity, frame.leftRectified, scan.geometry(), Device::Cpu);
  const SurfaceMeasurement gpu = measureSurface(disparity, frame.leftRectified, scan.geometry(), Device::Cuda);
  const long points = differingPixels(cpu.pointsCameraMm, gpu.pointsCameraMm);
  const long normals = differingPixels(cpu.normalsCamera, gpu.normalsCamera);
  std::printf("measureSurface 480x270: %d valid pixels (CPU) / %d (CUDA); %ld points and %ld normals differ\n",
              cpu.validPixels, gpu.validPixels, points, normals);
  EXPECT_GT(cpu.validPixels, 100000);
  EXPECT_EQ(cpu.validPixels, gpu.validPixels);
  EXPECT_EQ(points, 0);
  EXPECT_EQ(normals, 0);
  EXPECT_EQ(cv::norm(cpu.colourBgr, gpu.colourBgr, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(cpu.validMask, gpu.validMask, cv::NORM_INF), 0);
  ASSERT_TRUE(gpu.onDevice) << "a CUDA measurement keeps its maps on the device";

  // Kept on the device only: no host maps, the same mask, and the device maps are the same maps.
  const SurfaceMeasurement kept = measureSurface(disparity, frame.leftRectified, scan.geometry(), Device::Cuda, 2, 2.0,
                                                 SurfaceMapResidence::DeviceOnly);
  EXPECT_FALSE(kept.hasHostMaps());
  EXPECT_EQ(kept.size(), disparity.size());
  EXPECT_EQ(kept.validPixels, cpu.validPixels);
  EXPECT_EQ(cv::norm(cpu.validMask, kept.validMask, cv::NORM_INF), 0);
  cv::Mat keptPoints, keptNormals;
  kept.hostMaps(keptPoints, keptNormals);
  EXPECT_EQ(differingPixels(cpu.pointsCameraMm, keptPoints), 0);
  EXPECT_EQ(differingPixels(cpu.normalsCamera, keptNormals), 0);

  // From a map already in device memory (the pipeline's: the stereo matcher's own), nothing uploaded.
  Image<float> onDevice(Device::Cuda, disparity.cols, disparity.rows);
  onDevice.buffer().upload(disparity.ptr<float>());
  const SurfaceMeasurement fromDevice = measureSurface(onDevice.view(), frame.leftRectified, scan.geometry(), Device::Cuda);
  EXPECT_EQ(fromDevice.validPixels, cpu.validPixels);
  EXPECT_EQ(differingPixels(cpu.pointsCameraMm, fromDevice.pointsCameraMm), 0);
  EXPECT_EQ(differingPixels(cpu.normalsCamera, fromDevice.normalsCamera), 0);
  ASSERT_TRUE(fromDevice.onDevice);
  std::vector<uint8_t> colour(fromDevice.onDevice->colourBgr.size());
  fromDevice.onDevice->colourBgr.download(colour.data());
  EXPECT_EQ(cv::norm(cv::Mat(frame.leftRectified.size(), CV_8UC3, colour.data()), frame.leftRectified, cv::NORM_INF), 0);
}

// Fusion from maps that never left the device (the reconstruct pipeline's path on CUDA) gives the CPU's model; a
// CPU fusion given such a measurement downloads the maps.
TEST(FusionCuda, FusesTheSameModelFromMapsKeptOnTheDevice) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const synthetic::SyntheticScan scan(scanOptions());
  const RectifiedGeometry& g = scan.geometry();
  FusionParameters parameters;
  PointFusion cpu(g, parameters, Device::Cpu), gpu(g, parameters, Device::Cuda), cpuFromDevice(g, parameters, Device::Cpu);
  for (int index = 0; index < scan.frameCount(); index += 15) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(index);
    const SurfaceMeasurement host = measureSurface(frame.disparityPx, frame.leftRectified, g, Device::Cpu);
    const SurfaceMeasurement kept = measureSurface(frame.disparityPx, frame.leftRectified, g, Device::Cuda, 2, 2.0,
                                                   SurfaceMapResidence::DeviceOnly);
    const FusionStats a = cpu.integrate(host, frame.T_world_camera);
    const FusionStats b = gpu.integrate(kept, frame.T_world_camera);
    const FusionStats c = cpuFromDevice.integrate(kept, frame.T_world_camera);
    EXPECT_EQ(a.merged, b.merged);
    EXPECT_EQ(a.added, b.added);
    EXPECT_EQ(a.merged, c.merged);
    EXPECT_EQ(a.added, c.added);
  }
  ASSERT_GT(cpu.pointCount(), 0u);
  double maxPositionMm = 0;
  EXPECT_EQ(differingModelPoints(cpu.download(), gpu.download(), maxPositionMm), 0);
  EXPECT_EQ(differingModelPoints(cpu.download(), cpuFromDevice.download(), maxPositionMm), 0);
}

TEST(FusionCuda, FusesTheSameModelAsTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const synthetic::SyntheticScan scan(scanOptions());
  const RectifiedGeometry& g = scan.geometry();
  FusionParameters parameters;
  PointFusion cpu(g, parameters, Device::Cpu), gpu(g, parameters, Device::Cuda);
  cv::RNG rng(9);
  long statMismatches = 0;
  for (int index = 0; index < scan.frameCount(); index += 5) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(index);
    cv::Mat disparity = frame.disparityPx.clone(), noise(disparity.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.1);
    disparity += noise;
    const SurfaceMeasurement m = measureSurface(disparity, frame.leftRectified, g, Device::Cpu);
    const FusionStats a = cpu.integrate(m, frame.T_world_camera);
    const FusionStats b = gpu.integrate(m, frame.T_world_camera);
    std::printf("frame %2d: CPU %6d merged %6d added %.1f ms | CUDA %6d merged %6d added %.2f ms | %zu points\n", index,
                a.merged, a.added, a.milliseconds, b.merged, b.added, b.milliseconds, gpu.pointCount());
    statMismatches += a.merged != b.merged || a.added != b.added || a.refusedForBudget != b.refusedForBudget;
  }
  EXPECT_EQ(statMismatches, 0);
  ASSERT_EQ(cpu.pointCount(), gpu.pointCount());
  EXPECT_GT(gpu.pointCount(), static_cast<std::size_t>(g.imageSize.area()));  // the device buffers grew
  double maxPositionMm = 0;
  const long differ = differingModelPoints(cpu.download(), gpu.download(), maxPositionMm);
  std::printf("%zu model points: %ld differ in some bit, largest position difference %.3g mm; %.1f MB on the GPU\n",
              gpu.pointCount(), differ, maxPositionMm, gpu.deviceBytes() / 1e6);
  EXPECT_LE(maxPositionMm, 1e-4);
  EXPECT_EQ(differ, 0);
  EXPECT_GT(gpu.deviceBytes(), gpu.pointCount() * 48);

  // The same samples of the visible model.
  std::vector<Eigen::Vector3f> cpuPoints, cpuNormals, gpuPoints, gpuNormals;
  const Eigen::Matrix4d T = scan.T_world_camera(scan.frameCount() / 2);
  cpu.sampleVisible(T, 3000, cpuPoints, cpuNormals);
  gpu.sampleVisible(T, 3000, gpuPoints, gpuNormals);
  ASSERT_EQ(cpuPoints.size(), gpuPoints.size());
  EXPECT_GT(gpuPoints.size(), 1500u);
  long sampleDiffer = 0;
  for (std::size_t i = 0; i < cpuPoints.size(); ++i) sampleDiffer += cpuPoints[i] != gpuPoints[i] || cpuNormals[i] != gpuNormals[i];
  EXPECT_EQ(sampleDiffer, 0);
}

TEST(FusionCuda, StopsAtTheSameBudgetAsTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const RectifiedGeometry g = test::fusionGeometry();
  FusionParameters parameters;
  parameters.maxPoints = 30000;
  PointFusion cpu(g, parameters, Device::Cpu), gpu(g, parameters, Device::Cuda);
  const test::PlanePatch plane;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Matrix4d T = test::cameraPose(Eigen::Vector3d(25.0 * k, 0, 0));
    const SurfaceMeasurement m = test::patchMeasurement(g, plane, T);
    const FusionStats a = cpu.integrate(m, T), b = gpu.integrate(m, T);
    EXPECT_EQ(a.added, b.added);
    EXPECT_EQ(a.merged, b.merged);
    EXPECT_EQ(a.refusedForBudget, b.refusedForBudget);
  }
  EXPECT_TRUE(gpu.budgetReached());
  EXPECT_EQ(gpu.pointCount(), 30000u);
  double maxPositionMm = 0;
  EXPECT_EQ(differingModelPoints(cpu.download(), gpu.download(), maxPositionMm), 0);
}
