// Trajectory errors against constructed ground truth: association by time stamp, the rigid alignment recovering a
// known transform, the ATE of known noise, the RPE of a known per-step drift, and the refusals.
#include "Core/Error.h"
#include "IO/TrajectoryError.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace tissuemosaic;

namespace {

Eigen::Matrix4d pose(const Eigen::Vector3d& axis, double angleDeg, const Eigen::Vector3d& translation) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angleDeg * M_PI / 180, axis.normalized()).toRotationMatrix();
  T.topRightCorner<3, 1>() = translation;
  return T;
}

/// A scan-like reference path: a raster 40 x 25 mm at about 80 mm above the tissue, gently tilting, t = k / 30 s.
Trajectory scanPath(int poses) {
  Trajectory path;
  for (int k = 0; k < poses; ++k) {
    const double s = k / 30.0;
    TimedPose p;
    p.timeS = s;
    p.T_world_camera = pose(Eigen::Vector3d(std::cos(s), std::sin(s), 0.3), 6 * std::sin(0.7 * s),
                            Eigen::Vector3d(20 * std::sin(0.4 * s), 12 * std::sin(2.1 * s), -80 + 5 * std::sin(s)));
    path.push_back(p);
  }
  return path;
}

/// Every pose moved into another world: T_world'_camera = T_world'_world * T_world_camera.
Trajectory moved(const Trajectory& trajectory, const Eigen::Matrix4d& T_new_old) {
  Trajectory result = trajectory;
  for (TimedPose& p : result) p.T_world_camera = T_new_old * p.T_world_camera;
  return result;
}

double rotationErrorDeg(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  const Eigen::Matrix3d r = a.topLeftCorner<3, 3>() * b.topLeftCorner<3, 3>().transpose();
  return Eigen::AngleAxisd(r).angle() * 180 / M_PI;
}

}  // namespace

TEST(TrajectoryError, AssociatesByNearestTimeStampOneToOne) {
  const Trajectory reference = scanPath(30);  // t = k / 30 s, k = 0 .. 29
  Trajectory estimate;
  for (int k = 20; k >= 0; --k) {  // unsorted, stamps off by -8, -4, 0, 4, 8 ms
    TimedPose p = reference[static_cast<std::size_t>(k)];
    p.timeS += 0.004 * (k % 5 - 2);
    estimate.push_back(p);
  }
  TimedPose late = reference.back();
  late.timeS = 5.0;  // beyond the reference: no partner
  estimate.push_back(late);
  TimedPose twin = reference[20];  // 9 ms from reference 20, whose own estimate is 8 ms away and wins
  twin.timeS += 0.009;
  twin.T_world_camera(0, 3) += 1000;
  estimate.push_back(twin);

  const AssociatedPoses poses = associateByTime(estimate, reference, 0.01);
  ASSERT_EQ(poses.size(), 21u);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_LE(std::abs(poses.estimate[i].timeS - poses.reference[i].timeS), 0.01);
    EXPECT_EQ(poses.estimate[i].T_world_camera, poses.reference[i].T_world_camera) << "paired with the wrong pose";
    if (i > 0) EXPECT_LT(poses.estimate[i - 1].timeS, poses.estimate[i].timeS);
  }
  EXPECT_EQ(associateByTime(estimate, reference, 0.001).size(), 4u);  // k = 2, 7, 12, 17: exact stamps
  EXPECT_EQ(associateByTime(estimate, Trajectory{}, 1.0).size(), 0u);
  EXPECT_THROW(associateByTime(estimate, reference, -1), Error);
}

TEST(TrajectoryError, RigidAlignmentRecoversAKnownTransformExactly) {
  const Trajectory reference = scanPath(120);
  const Eigen::Matrix4d T_reference_estimate = pose({1, -2, 0.5}, 35, {12, -40, 95});
  const Trajectory estimate = moved(reference, T_reference_estimate.inverse());
  AssociatedPoses poses{estimate, reference};
  const TrajectoryErrors errors = trajectoryErrors(poses, TrajectoryAlignment::Rigid);
  EXPECT_EQ(errors.poses, 120u);
  EXPECT_LT(errors.ateRmseMm, 1e-9);
  EXPECT_LT(errors.rpeRmseMm, 1e-9);
  EXPECT_LT((errors.T_reference_estimate - T_reference_estimate).norm(), 1e-9);
  // Without the alignment the whole offset is error.
  EXPECT_GT(trajectoryErrors(poses, TrajectoryAlignment::None).ateRmseMm, 50.0);
}

TEST(TrajectoryError, AteOfKnownNoiseAfterAlignment) {
  const Trajectory reference = scanPath(600);
  const Eigen::Matrix4d T_reference_estimate = pose({0.2, 1, -1}, -50, {-30, 8, 60});
  Trajectory estimate = moved(reference, T_reference_estimate.inverse());
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0, 0.3);
  double sumSquares = 0;
  for (TimedPose& p : estimate) {
    const Eigen::Vector3d n(noise(random), noise(random), noise(random));
    p.T_world_camera.topRightCorner<3, 1>() += n;  // in the estimate's world: the same length in the reference's
    sumSquares += n.squaredNorm();
  }
  const double noiseRmsMm = std::sqrt(sumSquares / static_cast<double>(estimate.size()));
  const TrajectoryErrors errors = trajectoryErrors({estimate, reference}, TrajectoryAlignment::Rigid);
  std::printf("noise RMS %.4f mm, ATE %.4f mm, alignment rotation error %.3f deg\n", noiseRmsMm, errors.ateRmseMm,
              rotationErrorDeg(errors.T_reference_estimate, T_reference_estimate));
  // The true transform is one candidate of the least-squares fit, so the ATE cannot exceed the noise; the fit
  // absorbs only 6 of 1800 degrees of freedom, so it cannot be much below it.
  EXPECT_LE(errors.ateRmseMm, noiseRmsMm + 1e-12);
  EXPECT_GE(errors.ateRmseMm, 0.99 * noiseRmsMm);
  // The alignment itself is close to the truth: 0.3 mm noise on 600 poses spread over 40 x 25 x 10 mm.
  EXPECT_LT(rotationErrorDeg(errors.T_reference_estimate, T_reference_estimate), 0.3);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const TimedPose& p : reference) centroid += p.T_world_camera.topRightCorner<3, 1>() / 600.0;
  const Eigen::Matrix4d error = errors.T_reference_estimate * T_reference_estimate.inverse();
  EXPECT_LT((error.topLeftCorner<3, 3>() * centroid + error.topRightCorner<3, 1>() - centroid).norm(), 0.05);
  EXPECT_GT(errors.ateMaxMm, errors.ateRmseMm);
  EXPECT_LT(errors.ateMeanMm, errors.ateRmseMm);
}

TEST(TrajectoryError, AlignmentUncertaintyPredictsTheRotationError) {
  // Over 40 noise draws, the RMS rotation error of the alignment lies between the predicted standard deviation about
  // the weakest axis and sqrt(3) times it (all three axes that weak); a short, nearly straight path is far worse.
  const Trajectory reference = scanPath(300);
  const Eigen::Matrix4d T_reference_estimate = pose({0.2, 1, -1}, -50, {-30, 8, 60});
  std::mt19937 random(17);
  std::normal_distribution<double> noise(0, 0.3);
  double squares = 0, predictedDeg = 0;
  for (int draw = 0; draw < 40; ++draw) {
    Trajectory estimate = moved(reference, T_reference_estimate.inverse());
    for (TimedPose& p : estimate) {
      p.T_world_camera.topRightCorner<3, 1>() += Eigen::Vector3d(noise(random), noise(random), noise(random));
    }
    const TrajectoryErrors errors = trajectoryErrors({estimate, reference}, TrajectoryAlignment::Rigid);
    squares += std::pow(rotationErrorDeg(errors.T_reference_estimate, T_reference_estimate), 2);
    predictedDeg += errors.alignmentRotationSdDeg / 40;
  }
  const double observedDeg = std::sqrt(squares / 40);
  std::printf("alignment rotation error: RMS %.4f deg over 40 draws, predicted sd about the weakest axis %.4f deg\n",
              observedDeg, predictedDeg);
  EXPECT_GT(observedDeg, 0.8 * predictedDeg);
  EXPECT_LT(observedDeg, 1.2 * std::sqrt(3.0) * predictedDeg);

  // Ten frames (a third of a second) along a nearly straight stretch: the rotation about the path is undetermined.
  Trajectory shortPath;
  for (int k = 0; k < 10; ++k) {
    TimedPose p;
    p.timeS = k / 30.0;
    p.T_world_camera.topRightCorner<3, 1>() = Eigen::Vector3d(0.4 * k, 0.01 * k * k, -80);
    shortPath.push_back(p);
  }
  Trajectory noisyShort = shortPath;
  for (TimedPose& p : noisyShort) {
    p.T_world_camera.topRightCorner<3, 1>() += 0.02 * Eigen::Vector3d(noise(random), noise(random), noise(random));
  }
  const TrajectoryErrors shortErrors = trajectoryErrors({noisyShort, shortPath}, TrajectoryAlignment::Rigid);
  std::printf("short path: ATE %.4f mm, alignment rotation sd %.2f deg\n", shortErrors.ateRmseMm,
              shortErrors.alignmentRotationSdDeg);
  EXPECT_GT(shortErrors.alignmentRotationSdDeg, 1.0);
}

TEST(TrajectoryError, RpeIsTheDriftPerStep) {
  // Each estimated step is the true step followed by a fixed extra motion E (0.3 mm, 0.4 mm, 0 in the camera frame):
  // the relative error of every consecutive pair is exactly E, whatever the path and the estimate's world.
  const Trajectory reference = scanPath(90);
  const Eigen::Matrix4d E = pose({0, 0, 1}, 0, {0.3, 0.4, 0});
  Trajectory estimate = reference;
  for (std::size_t i = 1; i < estimate.size(); ++i) {
    const Eigen::Matrix4d step = reference[i - 1].T_world_camera.inverse() * reference[i].T_world_camera;
    estimate[i].T_world_camera = estimate[i - 1].T_world_camera * step * E;
  }
  estimate = moved(estimate, pose({1, 1, 1}, 20, {5, 5, 5}));
  const TrajectoryErrors errors = trajectoryErrors({estimate, reference}, TrajectoryAlignment::Rigid);
  EXPECT_EQ(errors.rpePairs, 89u);
  EXPECT_NEAR(errors.rpeRmseMm, 0.5, 1e-9);
  EXPECT_GT(errors.ateRmseMm, 1.0) << "a drift of 0.5 mm per step accumulates";
  EXPECT_NEAR(trajectoryErrors({estimate, reference}, TrajectoryAlignment::None).rpeRmseMm, 0.5, 1e-9);
}

TEST(TrajectoryError, RefusesWhatCannotBeAligned) {
  const Trajectory reference = scanPath(10);
  EXPECT_THROW(trajectoryErrors({}, TrajectoryAlignment::None), Error);
  AssociatedPoses two{Trajectory(reference.begin(), reference.begin() + 2),
                      Trajectory(reference.begin(), reference.begin() + 2)};
  EXPECT_THROW(trajectoryErrors(two, TrajectoryAlignment::Rigid), Error);
  EXPECT_NO_THROW(trajectoryErrors(two, TrajectoryAlignment::None));
  Trajectory line = reference;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const double s = static_cast<double>(i);
    line[i].T_world_camera.topRightCorner<3, 1>() = Eigen::Vector3d(s, 2 * s, 0);
  }
  try {
    trajectoryErrors({line, line}, TrajectoryAlignment::Rigid);
    ADD_FAILURE() << "collinear positions were accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("collinear"), std::string::npos) << error.what();
  }
}
