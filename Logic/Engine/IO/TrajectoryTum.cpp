#include "IO/TrajectoryTum.h"

#include "IO/AtomicFile.h"

#include "Core/Error.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace tissuemosaic {

std::string formatTumLine(const TimedPose& pose) {
  const Eigen::Matrix3d R = pose.T_world_camera.block<3, 3>(0, 0);
  const Eigen::Quaterniond q(R);
  char line[256];
  std::snprintf(line, sizeof(line), "%.6f %.17g %.17g %.17g %.17g %.17g %.17g %.17g", pose.timeS,
                pose.T_world_camera(0, 3), pose.T_world_camera(1, 3), pose.T_world_camera(2, 3), q.x(), q.y(), q.z(),
                q.w());
  return line;
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& header) {
  writeStreamAtomically(path, "trajectory", [&](std::ostream& file) {
    std::istringstream lines(header);
    for (std::string line; std::getline(lines, line);) file << "# " << line << "\n";
    for (const TimedPose& pose : trajectory) file << formatTumLine(pose) << "\n";
  });
}

Trajectory readTumTrajectory(const std::string& path) {
  std::ifstream file(path);
  require(file.good(), "cannot read trajectory '" + path + "': file does not exist or is not readable");
  Trajectory trajectory;
  std::map<double, int> lineOfTime;
  int number = 0;
  for (std::string line; std::getline(file, line);) {
    ++number;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream words(line);
    double v[8];
    for (double& value : v) words >> value;
    std::string rest;
    require(!words.fail() && !(words >> rest),
            "trajectory '" + path + "' line " + std::to_string(number) + ": expected 't tx ty tz qx qy qz qw'");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    require(std::abs(q.norm() - 1.0) < 1e-3, "trajectory '" + path + "' line " + std::to_string(number) +
                                                 ": the quaternion is not of unit length");
    require(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && std::isfinite(v[3]),
            "trajectory '" + path + "' line " + std::to_string(number) + ": a value is not a finite number");
    // Poses are associated by time stamp: a repeated one would make the association ambiguous.
    const auto [earlier, fresh] = lineOfTime.emplace(v[0], number);
    if (!fresh) {
      char time[64];
      std::snprintf(time, sizeof(time), "%.6f", v[0]);
      throw Error("trajectory '" + path + "' line " + std::to_string(number) + " repeats the time stamp " + time +
                  " of line " + std::to_string(earlier->second));
    }
    TimedPose pose;
    pose.timeS = v[0];
    pose.T_world_camera.block<3, 3>(0, 0) = q.normalized().toRotationMatrix();
    pose.T_world_camera.block<3, 1>(0, 3) = Eigen::Vector3d(v[1], v[2], v[3]);
    trajectory.push_back(pose);
  }
  return trajectory;
}

}  // namespace tissuemosaic
