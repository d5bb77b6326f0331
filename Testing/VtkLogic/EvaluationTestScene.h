#pragma once
// Camera paths for the evaluation tests: a scan-like path 65-95 mm above the height field of TestRegistrationScene.h
// (t = k / 30 s, looking down +z, gently tilting), and trajectories moved into another world.
#include "IO/TrajectoryTum.h"
#include "TestRegistrationScene.h"

#include <cmath>

namespace tissuemosaic::test {

inline Trajectory cameraPath(int poses) {
  Trajectory path;
  for (int k = 0; k < poses; ++k) {
    const double s = k / 30.0;
    TimedPose p;
    p.timeS = s;
    p.T_world_camera = rigidTransform({std::cos(s), std::sin(s), 0}, 8 * std::sin(0.5 * s), Eigen::Vector3d::Zero(),
                                      {18 * std::sin(0.3 * s), 15 * std::sin(1.7 * s), -80 + 15 * std::sin(0.9 * s)});
    path.push_back(p);
  }
  return path;
}

/// Every pose moved into another world: T_new_camera = T_new_old * T_old_camera.
inline Trajectory moved(const Trajectory& trajectory, const Eigen::Matrix4d& T_new_old) {
  Trajectory result = trajectory;
  for (TimedPose& p : result) p.T_world_camera = T_new_old * p.T_world_camera;
  return result;
}

}  // namespace tissuemosaic::test
