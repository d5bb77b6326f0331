// The CUDA key-frame refinement against the CPU one (ctest label "cuda"; skipped with a message where no GPU
// exists). Both run the same functors (RefinementKernels.h) without FMA and reduce the per-residual terms in the same
// chunks and order, so the poses must agree to rounding: asserted within 1e-6 degrees and 1e-6 mm.
#include "RefinementTestScene.h"

#include "Refinement/KeyFrameRefiner.h"
#include "Refinement/RefinementSolver.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;
using namespace tissuemosaic::refinement_test;

namespace {

bool cudaMissing() {
  if (cudaAvailable()) return false;
  std::printf("no usable CUDA device: %s\n", cudaUnavailableReason().c_str());
  return true;
}

void expectSamePose(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, const char* what) {
  double degrees = 0, mm = 0;
  poseError(a, b, degrees, mm);
  std::printf("%s: CPU vs CUDA %.3g deg, %.3g mm\n", what, degrees, mm);
  EXPECT_LT(degrees, 1e-6) << what;
  EXPECT_LT(mm, 1e-6) << what;
}

}  // namespace

TEST(RefinementCuda, BundleAdjustmentMatchesCpu) {
  if (cudaMissing()) GTEST_SKIP() << "no CUDA device: " << cudaUnavailableReason();
  const BundleRun cpu = runBundleScenario(Device::Cpu), gpu = runBundleScenario(Device::Cuda);
  ASSERT_TRUE(cpu.result.refined) << cpu.result.message;
  ASSERT_TRUE(gpu.result.refined) << gpu.result.message;
  EXPECT_EQ(cpu.result.baObservations, gpu.result.baObservations);
  EXPECT_EQ(cpu.result.iterations, gpu.result.iterations);
  EXPECT_NEAR(cpu.result.finalCost, gpu.result.finalCost, 1e-9 * cpu.result.finalCost);
  expectSamePose(cpu.result.T_world_camera, gpu.result.T_world_camera, "key frame");
  ASSERT_EQ(cpu.result.intermediatePoses.size(), gpu.result.intermediatePoses.size());
  for (std::size_t f = 0; f < cpu.result.intermediatePoses.size(); ++f) {
    expectSamePose(cpu.result.intermediatePoses[f].T_world_camera, gpu.result.intermediatePoses[f].T_world_camera,
                   "intermediate frame");
  }
  std::printf("CPU %.1f ms, CUDA %.1f ms (whole refineKeyFrame, matching included)\n", cpu.result.milliseconds,
              gpu.result.milliseconds);
}

TEST(RefinementCuda, IcpTermMatchesCpu) {
  if (cudaMissing()) GTEST_SKIP() << "no CUDA device: " << cudaUnavailableReason();
  const RectifiedGeometry g = testGeometry();
  const CurvedSurface surface;
  const SurfaceMeasurement measurement = surface.measure(g);
  std::vector<Eigen::Vector3f> model = surface.sample(30, 22, 90);
  for (Eigen::Vector3f& p : model) p.z() -= p.x() > 8 && p.y() > 4 ? 8.f : 0.f;  // an outlier block
  const Eigen::Matrix4d tracked = pose(Eigen::Vector3d(1, 2, 0), 0.8, Eigen::Vector3d(0.4, -0.3, 1.5));
  const FeatureScene none(0, 1);
  const auto refine = [&](Device device) {
    KeyFrameRefiner refiner(g, RefinementParameters{}, TrackingParameters{}, FeatureParameters{}, device);
    return refiner.refineKeyFrame(0, none.observe(Eigen::Matrix4d::Identity(), g, 0, 0, 0, 0, 1), tracked,
                                  measurement, model, {});
  };
  const RefinementResult cpu = refine(Device::Cpu), gpu = refine(Device::Cuda);
  ASSERT_TRUE(cpu.refined) << cpu.message;
  ASSERT_TRUE(gpu.refined) << gpu.message;
  EXPECT_EQ(cpu.iterations, gpu.iterations);
  expectSamePose(cpu.T_world_camera, gpu.T_world_camera, "ICP key frame");
}

// The ICP term read from maps that never left the device (the reconstruct pipeline's path on CUDA).
TEST(RefinementCuda, IcpTermFromMapsKeptOnTheDeviceMatchesCpu) {
  if (cudaMissing()) GTEST_SKIP() << "no CUDA device: " << cudaUnavailableReason();
  const RectifiedGeometry g = testGeometry();
  const CurvedSurface surface;
  const SurfaceMeasurement host = surface.measure(g);
  SurfaceMeasurement kept;  // the same measurement, its maps on the device only
  auto maps = std::make_shared<SurfaceMapsOnDevice>();
  const int width = host.pointsCameraMm.cols, height = host.pointsCameraMm.rows;
  maps->pointsCameraMm = Image<Float3>(Device::Cuda, width, height);
  maps->normalsCamera = Image<Float3>(Device::Cuda, width, height);
  maps->pointsCameraMm.buffer().upload(host.pointsCameraMm.ptr<Float3>());
  maps->normalsCamera.buffer().upload(host.normalsCamera.ptr<Float3>());
  kept.onDevice = maps;
  kept.validMask = host.validPixelMask();
  kept.colourBgr = host.colourBgr;
  ASSERT_FALSE(kept.hasHostMaps());
  const std::vector<Eigen::Vector3f> model = surface.sample(30, 22, 90);
  const Eigen::Matrix4d tracked = pose(Eigen::Vector3d(1, 2, 0), 0.8, Eigen::Vector3d(0.4, -0.3, 1.5));
  const FeatureScene none(0, 1);
  const auto refine = [&](Device device, const SurfaceMeasurement& measurement) {
    KeyFrameRefiner refiner(g, RefinementParameters{}, TrackingParameters{}, FeatureParameters{}, device);
    return refiner.refineKeyFrame(0, none.observe(Eigen::Matrix4d::Identity(), g, 0, 0, 0, 0, 1), tracked,
                                  measurement, model, {});
  };
  const RefinementResult cpu = refine(Device::Cpu, host), gpu = refine(Device::Cuda, kept);
  const RefinementResult cpuFromDevice = refine(Device::Cpu, kept);  // downloads the maps
  ASSERT_TRUE(cpu.refined) << cpu.message;
  ASSERT_TRUE(gpu.refined) << gpu.message;
  EXPECT_EQ(cpu.icpPoints, gpu.icpPoints);
  EXPECT_EQ(cpu.iterations, gpu.iterations);
  expectSamePose(cpu.T_world_camera, gpu.T_world_camera, "ICP key frame, maps on the device");
  expectSamePose(cpu.T_world_camera, cpuFromDevice.T_world_camera, "ICP key frame, CPU from device maps");
}

// The solver directly, with free points, several frames and the ICP term together.
TEST(RefinementCuda, SolverMatchesCpu) {
  if (cudaMissing()) GTEST_SKIP() << "no CUDA device: " << cudaUnavailableReason();
  const RectifiedGeometry g = testGeometry();
  const FeatureScene scene(800, 12);
  const CurvedSurface surface;
  refinement::RefinementProblem problem;
  problem.camera = {g.leftIntrinsics(), g.imageSize.width, g.imageSize.height};
  problem.robust = {2.0, 2.0, 0.5, 0.1};
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0, 0.5);
  for (int f = 0; f < 4; ++f) {
    const Eigen::Matrix4d T = perturb(truePose(3 * f), 1.0, 1.5, random).inverse();
    refinement::Pose p;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) p.r[3 * r + c] = T(r, c);
      p.t[r] = T(r, 3);
    }
    problem.poses.push_back(p);
    const Eigen::Matrix4d truth = truePose(3 * f).inverse();
    for (std::size_t i = 0; i < scene.pointsWorldMm.size(); ++i) {
      const Eigen::Vector3d c = truth.block<3, 3>(0, 0) * scene.pointsWorldMm[i] + truth.block<3, 1>(0, 3);
      problem.observations.push_back({f, static_cast<int>(i), g.focalPx * c.x() / c.z() + g.cxLeftPx + noise(random),
                                      g.focalPx * c.y() / c.z() + g.cyPx + noise(random)});
    }
  }
  for (std::size_t i = 0; i < scene.pointsWorldMm.size(); ++i) {
    const Eigen::Vector3d& X = scene.pointsWorldMm[i];
    problem.pointsWorldMm.insert(problem.pointsWorldMm.end(), {X.x() + noise(random), X.y() + noise(random), X.z()});
    problem.pointFixed.push_back(i % 3 == 0);
  }
  for (const Eigen::Vector3f& p : surface.sample(30, 22, 60)) problem.modelPointsWorldMm.push_back({p.x(), p.y(), p.z()});
  const SurfaceMeasurement measurement = surface.measure(g);
  problem.measuredPointsCameraMm = measurement.pointsCameraMm;
  problem.measuredNormalsCamera = measurement.normalsCamera;
  const RefinementParameters parameters;
  const refinement::RefinementSolution cpu = refinement::solveRefinement(problem, parameters, Device::Cpu);
  const refinement::RefinementSolution gpu = refinement::solveRefinement(problem, parameters, Device::Cuda);
  EXPECT_EQ(cpu.iterations, gpu.iterations);
  EXPECT_NEAR(cpu.finalCost, gpu.finalCost, 1e-9 * cpu.finalCost);
  EXPECT_LT(cpu.finalCost, cpu.initialCost);
  double worstPoint = 0;
  for (std::size_t k = 0; k < cpu.pointsWorldMm.size(); ++k) {
    worstPoint = std::max(worstPoint, std::abs(cpu.pointsWorldMm[k] - gpu.pointsWorldMm[k]));
  }
  std::printf("solver: cost %.6g (CPU) vs %.6g (CUDA); worst point difference %.3g mm\n", cpu.finalCost, gpu.finalCost,
              worstPoint);
  EXPECT_LT(worstPoint, 1e-6);
  for (std::size_t f = 0; f < cpu.poses.size(); ++f) {
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(cpu.poses[f].r[k], gpu.poses[f].r[k], 1e-9);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(cpu.poses[f].t[k], gpu.poses[f].t[k], 1e-6);
  }
}
