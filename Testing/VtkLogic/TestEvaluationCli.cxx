// Inputs for the `tissuemosaic eval` end-to-end tests (Testing/Cli/CMakeLists.txt, cli.eval.*): a reference surface
// and models whose scores are known, written to $TM_EVAL_CLI_DIR (default: the test output folder). Values that
// depend on the random noise are written beside them as checks for Testing/Cli/CheckEvalJson.cmake.
#include "EvaluationTestScene.h"
#include "IO/MeshPly.h"
#include "IO/PointCloudPly.h"
#include "IO/TrajectoryTum.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <opencv2/core.hpp>
#include <vtkPolyData.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

using namespace tissuemosaic;
using namespace tissuemosaic::test;

namespace {

std::filesystem::path evalFolder() {
  const char* folder = std::getenv("TM_EVAL_CLI_DIR");
  const std::filesystem::path path = folder ? folder : std::filesystem::path(TM_TEST_OUTPUT_DIR) / "eval-cli";
  std::filesystem::create_directories(path);
  return path;
}

/// A point cloud PLY as `tissuemosaic reconstruct` writes it (IO/PointCloudPly.h), in the model's own frame.
void writeCloud(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points) {
  ColoredPointCloud cloud;
  for (const Eigen::Vector3d& p : points) {
    cloud.pointsMm.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    cloud.colorsRgb.emplace_back(200, 120, 110);
  }
  writePly(path.string(), cloud, "TissueMosaic eval test model, mm");
}

}  // namespace

TEST(EvalCliInputs, WriteReferenceModelsAndTrajectories) {
  const std::filesystem::path folder = evalFolder();
  writeSurfaceModel((folder / "reference.ply").string(), heightFieldMesh(30, 0.5));

  // offset.ply: a 0.25 mm grid over [-25, 25]^2 lifted 0.25 mm along the true normal: every distance 0.25 mm (the
  // mesh's sag changes it by < 0.003 mm).
  std::vector<Eigen::Vector3d> surface, offset;
  for (double y = -25; y <= 25 + 1e-9; y += 0.25) {
    for (double x = -25; x <= 25 + 1e-9; x += 0.25) {
      surface.emplace_back(x, y, height(x, y));
      offset.push_back(surface.back() + 0.25 * surfaceNormal(x, y));
    }
  }
  writeCloud(folder / "offset.ply", offset);

  // moved.ply + model_trajectory.txt: the surface points and the true path in the reconstruction's own world, the
  // path's positions with 0.2 mm noise per axis. ATE: at most the noise's RMS (the truth is one candidate of the
  // fit), at least 98% of it; RPE: exactly the RMS of n_i+1 - n_i; the model comes back to within 0.05 mm.
  const Eigen::Matrix4d T_reference_model = rigidTransform({1, -1, 2}, 40, {0, 0, 0}, {30, -50, 80});
  const Trajectory reference = cameraPath(300);
  Trajectory model = moved(reference, T_reference_model.inverse());
  std::mt19937 random(8);
  std::normal_distribution<double> noise(0, 0.2);
  double sumSquares = 0, stepSquares = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Eigen::Vector3d n(noise(random), noise(random), noise(random));
    model[i].T_world_camera.topRightCorner<3, 1>() += n;
    sumSquares += n.squaredNorm();
    if (i > 0) stepSquares += (n - previous).squaredNorm();
    previous = n;
  }
  const double noiseRmsMm = std::sqrt(sumSquares / static_cast<double>(model.size()));
  const double rpeMm = std::sqrt(stepSquares / static_cast<double>(model.size() - 1));
  writeCloud(folder / "moved.ply", transformedPoints(surface, T_reference_model.inverse()));
  writeTumTrajectory((folder / "model_trajectory.txt").string(), model, "eval test: the model's camera path");
  writeTumTrajectory((folder / "reference_trajectory.txt").string(), reference, "eval test: the true camera path");
  std::ofstream(folder / "trajectory.expect")
      << cv::format("ate_mm:%.6f:%.6f,rpe_mm:%.6f:%.6f", 0.98 * noiseRmsMm, noiseRmsMm + 1e-6, rpeMm - 1e-6,
                    rpeMm + 1e-6);
  // The first third of a second of both paths: too short to place the model.
  writeTumTrajectory((folder / "short_model_trajectory.txt").string(), Trajectory(model.begin(), model.begin() + 10));
  writeTumTrajectory((folder / "short_reference_trajectory.txt").string(),
                     Trajectory(reference.begin(), reference.begin() + 10));
  Trajectory late = model;  // another recording's clock: no common time stamp
  for (TimedPose& p : late) p.timeS += 1000;
  writeTumTrajectory((folder / "late_trajectory.txt").string(), late);

  // perturbed.ply: the surface points moved by 3 degrees and 1.4 mm: ICP brings them back.
  writeCloud(folder / "perturbed.ply",
             transformedPoints(surface, rigidTransform({0.3, 1, 0.2}, 3, {0, 0, 0}, {1.0, -0.8, 0.6})));

  // Bad input.
  // Truncated files (a copy cut short): in the vertices of a point cloud, in the faces of a mesh.
  const auto truncated = [&](const char* from, const char* to, std::uintmax_t bytes) {
    std::ifstream in(folder / from, std::ios::binary);
    std::string data(bytes, '\0');
    in.read(data.data(), static_cast<std::streamsize>(bytes));
    std::ofstream(folder / to, std::ios::binary) << data;
  };
  truncated("offset.ply", "corrupt.ply", std::filesystem::file_size(folder / "offset.ply") / 2);
  truncated("reference.ply", "truncated_reference.ply", std::filesystem::file_size(folder / "reference.ply") - 100);
  std::ofstream(folder / "garbage.ply") << "this is not a PLY file\n";
  writePly((folder / "empty.ply").string(), ColoredPointCloud{});
  EXPECT_TRUE(std::filesystem::exists(folder / "perturbed.ply"));
  EXPECT_EQ(readSurfaceModel((folder / "offset.ply").string()).polyDataLps->GetNumberOfPoints(),
            static_cast<vtkIdType>(offset.size()));
}

// Issue 32's bad models and references: NaN points are left out and counted (never scored at a finite distance); a
// model of NaN points only, and a reference whose faces all have zero area, are refused with a message (the latter
// hung in vtkPolyDataNormals).
TEST(EvalCliInputs, WriteNonFiniteModelsAndDegenerateReference) {
  const std::filesystem::path folder = evalFolder();
  std::vector<Eigen::Vector3d> halfNan, allNan;
  const double nan = std::nan("");
  for (double y = -20; y <= 20 + 1e-9; y += 0.5) {
    for (double x = -20; x <= 20 + 1e-9; x += 0.5) {
      halfNan.push_back(Eigen::Vector3d(x, y, height(x, y)) + 0.25 * surfaceNormal(x, y));
      halfNan.emplace_back(nan, nan, nan);
      allNan.emplace_back(nan, nan, nan);
    }
  }
  writeCloud(folder / "half_nan.ply", halfNan);
  writeCloud(folder / "all_nan.ply", allNan);
  std::ofstream(folder / "half_nan.expect") << "non_finite_points_left_out:" << allNan.size() << ":" << allNan.size()
                                            << ",points:" << allNan.size() << ":" << allNan.size() << "\n";
  TriangleMesh degenerate;
  degenerate.verticesMm = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  degenerate.triangles = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  writeMeshPly((folder / "degenerate_reference.ply").string(), degenerate, "all faces degenerate");
}
