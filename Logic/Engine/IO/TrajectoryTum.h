#pragma once
/// @file TrajectoryTum.h
/// @brief Camera trajectories in the TUM RGB-D format: one line per pose, "t tx ty tz qx qy qz qw" (seconds,
/// millimetres here, unit quaternion, Hamilton, scalar last), the pose T_world_camera (camera to world).
/// Lines starting with '#' are comments (e.g. frames where tracking was lost).
#include <Eigen/Core>
#include <Eigen/StdVector>

#include <string>
#include <vector>

namespace tissuemosaic {

struct TimedPose {
  double timeS = 0;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

using Trajectory = std::vector<TimedPose, Eigen::aligned_allocator<TimedPose>>;

/// One TUM line (no newline) with full double precision.
std::string formatTumLine(const TimedPose& pose);
/// Writes header comment lines (each line of header prefixed with "# ") and one line per pose. Throws Error when
/// the path cannot be written.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& header = {});
/// Reads every non-comment line; throws Error naming the line that is malformed, and for a missing file.
Trajectory readTumTrajectory(const std::string& path);

}  // namespace tissuemosaic
