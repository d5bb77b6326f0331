// The files that `tissuemosaic-app --offscreen --demo --export-model --export-trajectory` wrote in app.offscreen_demo,
// read back and checked against the demo scan's ground truth, made again here from the same options (the generator
// is deterministic). ctest runs this as app.offscreen_outputs after that test (fixture app_offscreen_outputs,
// TM_APP_OUTPUT_DIR set); plain discovery leaves the suite out. Each check also meets a deliberately broken copy.
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "IO/TrajectoryTum.h"

#include <Eigen/LU>

#include <gtest/gtest.h>

#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

std::string outputFile(const std::string& name) {
  const char* folder = std::getenv("TM_APP_OUTPUT_DIR");
  return std::string(folder ? folder : "TM_APP_OUTPUT_DIR-not-set") + "/" + name;
}

/// The demo of app.offscreen_demo: --demo-frames 12 --demo-size 320x180, the demo's seed (1).
tissuemosaic::synthetic::SyntheticScanOptions demoScan() {
  tissuemosaic::synthetic::SyntheticScanOptions options;
  options.frames = 12;
  options.width = 320;
  options.height = 180;
  options.seed = 1;
  return options;
}

/// RMS of the position errors of the poses (world: the first left rectified camera) against the truth.
double trajectoryRmsMm(const tissuemosaic::Trajectory& poses, const tissuemosaic::synthetic::SyntheticScan& scan) {
  const Eigen::Matrix4d worldFromFirst = scan.T_world_camera(0);
  double sum2 = 0;
  for (const tissuemosaic::TimedPose& pose : poses) {
    const int frame = static_cast<int>(std::lround(pose.timeS * scan.options().fps));
    const Eigen::Matrix4d truth = worldFromFirst.inverse() * scan.T_world_camera(frame);
    sum2 += (pose.T_world_camera.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).squaredNorm();
  }
  return poses.empty() ? 1e9 : std::sqrt(sum2 / poses.size());
}

/// RMS distance of the model's points (world: the first left rectified camera) to the true surface.
double modelRmsMm(const std::vector<Eigen::Vector3d>& points, const tissuemosaic::synthetic::SyntheticScan& scan) {
  const Eigen::Matrix4d worldFromFirst = scan.T_world_camera(0);
  double sum2 = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d w = worldFromFirst.topLeftCorner<3, 3>() * p + worldFromFirst.topRightCorner<3, 1>();
    const double d = scan.surface().distanceMm(w.x(), w.y(), w.z());
    sum2 += d * d;
  }
  return points.empty() ? 1e9 : std::sqrt(sum2 / points.size());
}

}  // namespace

// Requirement bars as the reconstruction logic's scan test (positions within 2.5 mm, model on the surface within
// 1 mm RMS); regression bars at twice the values measured when written, 2026-11-25 (trajectory 0.143 mm, model
// 0.473 mm RMS).
TEST(OffscreenDemoOutputs, TrajectoryAndModelMatchTheDemoScan) {
  const tissuemosaic::synthetic::SyntheticScan scan(demoScan());
  const tissuemosaic::Trajectory poses = tissuemosaic::readTumTrajectory(outputFile("trajectory.txt"));
  EXPECT_EQ(static_cast<int>(poses.size()), scan.frameCount()) << "one pose per tracked frame";
  const double trajectoryMm = trajectoryRmsMm(poses, scan);

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(outputFile("model.vtp").c_str());
  reader->Update();
  vtkPoints* modelPoints = reader->GetOutput()->GetPoints();
  ASSERT_NE(modelPoints, nullptr) << "no points in model.vtp";
  std::vector<Eigen::Vector3d> points;
  for (vtkIdType i = 0; i < modelPoints->GetNumberOfPoints(); ++i) {
    double p[3];
    modelPoints->GetPoint(i, p);
    points.emplace_back(p[0], p[1], p[2]);
  }
  const double modelMm = modelRmsMm(points, scan);
  std::printf("read back: %zu poses, position RMS %.3f mm; %zu model points, RMS distance to the surface %.3f mm\n",
              poses.size(), trajectoryMm, points.size(), modelMm);
  EXPECT_GT(points.size(), 1000u);
  EXPECT_LE(trajectoryMm, 2.5);       // requirement
  EXPECT_LE(trajectoryMm, 2 * 0.143);  // regression
  EXPECT_LE(modelMm, 1.0);            // requirement
  EXPECT_LE(modelMm, 2 * 0.473);      // regression

  // Negative controls: the trajectory 12 mm off, and the model 2 mm off along the viewing axis, fail the bars.
  tissuemosaic::Trajectory shifted = poses;
  for (tissuemosaic::TimedPose& pose : shifted) pose.T_world_camera(0, 3) += 12.0;
  EXPECT_GT(trajectoryRmsMm(shifted, scan), 2.5);
  std::vector<Eigen::Vector3d> moved = points;
  for (Eigen::Vector3d& p : moved) p.z() += 2.0;
  EXPECT_GT(modelRmsMm(moved, scan), 1.0);
}
