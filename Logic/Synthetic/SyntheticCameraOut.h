#pragma once
/// @file SyntheticCameraOut.h
/// @brief The scope withdrawn and put back (camera-out): frames [start, end) show no tissue (a third smoke, a third
/// dark, a third a smeared lens being wiped), and at `end` the camera is back about 10 mm and 10 degrees from
/// where it left at start - 1, then follows its path from there (the path's own motion, offset in the camera
/// frame). A camera-out frame has no ground-truth pose.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <cstdint>

namespace tissuemosaic::synthetic {

class SyntheticCameraOut {
public:
  static constexpr double kReturnOffsetMm = 10.0, kReturnRotationDeg = 10.0;

  SyntheticCameraOut() = default;
  /// Frames [start, end) out of the body; start < 0: none.
  SyntheticCameraOut(int start, int end, uint32_t seed);

  bool active() const { return start_ >= 0; }
  int start() const { return start_; }
  int end() const { return end_; }
  bool contains(int index) const { return active() && index >= start_ && index < end_; }
  /// The camera at `end` relative to the camera at start - 1 (T_left_back: back-camera to left-camera frame):
  /// kReturnOffsetMm mostly sideways and kReturnRotationDeg about an axis that is mostly the optical axis (so that
  /// the returned view still looks at the tissue), both in directions drawn from the seed.
  Eigen::Matrix4d returnMotion() const;
  /// The images of camera-out frame `index` (CV_8UC3) of a video at `fps`: smoke, then dark, then a smeared lens,
  /// with sensor noise.
  void render(int index, cv::Size size, double fps, double noiseStdGrey, cv::Mat& left, cv::Mat& right) const;

private:
  int start_ = -1, end_ = -1;
  uint32_t seed_ = 0;
};

}  // namespace tissuemosaic::synthetic
