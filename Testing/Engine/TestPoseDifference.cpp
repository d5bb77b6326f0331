// poseDifference grades every PnP test and bench pnp: here it is graded itself, on poses whose rotation angle and
// camera-centre distance are known by hand.
#include "Tracking/PnpSolver.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

using namespace tissuemosaic;

namespace {

Eigen::Matrix4d cameraFromWorld(double angleZDeg, const Eigen::Vector3d& t) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(angleZDeg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.block<3, 1>(0, 3) = t;
  return T;
}

}  // namespace

TEST(PoseDifference, SamePoseIsZero) {
  const Eigen::Matrix4d a = cameraFromWorld(37, {1, -2, 80});
  double rotationDeg = -1, centreMm = -1;
  poseDifference(a, a, rotationDeg, centreMm);
  EXPECT_NEAR(rotationDeg, 0, 1e-12);
  EXPECT_NEAR(centreMm, 0, 1e-12);
}

TEST(PoseDifference, RotationAloneAndTranslationAlone) {
  double rotationDeg = 0, centreMm = 0;
  poseDifference(cameraFromWorld(0, {0, 0, 0}), cameraFromWorld(30, {0, 0, 0}), rotationDeg, centreMm);
  EXPECT_NEAR(rotationDeg, 30, 1e-9);
  EXPECT_NEAR(centreMm, 0, 1e-12);
  poseDifference(cameraFromWorld(0, {0, 0, 0}), cameraFromWorld(0, {3, 4, 0}), rotationDeg, centreMm);
  EXPECT_NEAR(rotationDeg, 0, 1e-12);
  EXPECT_NEAR(centreMm, 5, 1e-12);  // the 3-4-5 triangle
  poseDifference(cameraFromWorld(0, {0, 0, 0}), cameraFromWorld(180, {0, 0, 0}), rotationDeg, centreMm);
  EXPECT_NEAR(rotationDeg, 180, 1e-9);
}

// The distance is between camera CENTRES (-R^T t), not between translation vectors: T_camera_world a = [Rz(90) |
// (1,0,0)] has its centre at (0,1,0), b = [I | (1,0,0)] at (-1,0,0); equal translations, centres sqrt(2) mm apart.
TEST(PoseDifference, ComparesCameraCentresNotTranslations) {
  double rotationDeg = 0, centreMm = 0;
  poseDifference(cameraFromWorld(90, {1, 0, 0}), cameraFromWorld(0, {1, 0, 0}), rotationDeg, centreMm);
  EXPECT_NEAR(rotationDeg, 90, 1e-9);
  EXPECT_NEAR(centreMm, std::sqrt(2.0), 1e-12);
}

// Tiny rotations stay exact (an acos of the trace would lose them): 1e-6 rad is 5.729578e-5 degrees.
TEST(PoseDifference, TinyRotationIsExact) {
  double rotationDeg = 0, centreMm = 0;
  poseDifference(cameraFromWorld(0, {0, 0, 0}), cameraFromWorld(1e-6 * 180 / M_PI, {0, 0, 0}), rotationDeg, centreMm);
  EXPECT_NEAR(rotationDeg, 1e-6 * 180 / M_PI, 1e-12);
}
