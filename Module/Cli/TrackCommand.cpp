// tissuemosaic track: camera tracking over a stereo video given as two folders of frames, to a TUM trajectory.
#include "Arguments.h"
#include "Commands.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/StereoRig.h"
#include "IO/ImageFile.h"
#include "IO/TrajectoryError.h"
#include "IO/TrajectoryTum.h"
#include "Stereo/StereoMatcher.h"
#include "Tracking/FrameTracker.h"
#include "Core/Statistics.h"

#include <opencv2/core/persistence.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace tissuemosaic::cli {

namespace {
const char* const help = R"(usage: tissuemosaic track --left-frames DIR --right-frames DIR --calib rig.yml --out trajectory.txt [options]

Tracks the left camera through a stereo video (paper III.A-C: ORB features lifted with the stereo depth, matching
with the previous tracked frame, histogram voting, DynamicR1PPnP, key-frame decision) and writes its trajectory.

input:
  --left-frames DIR        left frames (PNG/JPEG/..., taken in file-name order)
  --right-frames DIR       right frames, as many as left ones, paired in file-name order
  --calib rig.yml          stereo calibration of the unrectified rig (any layout of docs/CALIBRATION.md)
  --rectified              the frames are already rectified (as StereoRectifier makes them from --calib, e.g. the
                           output of `tissuemosaic synth scan`); otherwise they are rectified first
output:
  --out trajectory.txt     TUM lines "t tx ty tz qx qy qz qw": T_world_camera of the LEFT RECTIFIED camera, mm,
                           t = frame index / fps. The world frame is the first frame's left rectified camera (pose
                           identity) unless --start-tum gives another start. Frames where tracking is lost get a
                           "# frame N lost: reason" comment line instead of a pose.
options:
  --start-tum T.txt        take the first frame's pose from the first pose in this TUM file (e.g. a ground truth)
  --groundtruth T.txt      also print the trajectory errors against this TUM file: poses associated by time stamp
                           (within half a frame), no alignment (give --start-tum the same file for a common start);
                           absolute error (ATE) and relative pose error between consecutive frames (RPE), as
                           `tissuemosaic eval` computes them
  --fps F                  frame rate for the time stamps (default 30)
  --device cpu|cuda|auto   where stereo and features run (default auto); the pose solver runs on the CPU
  --features opencv|tissuemosaic
                           ORB implementation: OpenCV's (CPU only) or TissueMosaic's single-source extractor and
                           matcher (CPU or CUDA, identical results); default: tissuemosaic on cuda, opencv on cpu
  --params p.yml           parameters file: nodes "stereo" and "tracking" (missing keys keep the paper's defaults)
  --min-disparity A --max-disparity B   override the stereo disparity range
  --quiet                  no per-frame progress line
)";

std::vector<std::filesystem::path> framesIn(const std::string& folder, const char* option) {
  const std::filesystem::path path(folder);
  require(std::filesystem::is_directory(path), std::string("--") + option + " '" + folder + "' is not a folder");
  std::vector<std::filesystem::path> frames;
  for (const auto& entry : std::filesystem::directory_iterator(path)) {
    if (!entry.is_regular_file()) continue;
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    static const std::vector<std::string> images = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".ppm", ".pgm"};
    if (std::find(images.begin(), images.end(), extension) != images.end()) frames.push_back(entry.path());
  }
  require(!frames.empty(), std::string("--") + option + " '" + folder + "' holds no image files (.png .jpg .bmp .tif ...)");
  std::sort(frames.begin(), frames.end());
  return frames;
}



}  // namespace

int runTrack(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"left-frames", "right-frames", "calib", "out", "rectified", "start-tum", "groundtruth", "fps",
                       "device", "features", "params", "min-disparity", "max-disparity", "quiet"});
  const std::vector<std::filesystem::path> leftFrames = framesIn(arguments.required("left-frames"), "left-frames");
  const std::vector<std::filesystem::path> rightFrames = framesIn(arguments.required("right-frames"), "right-frames");
  require(leftFrames.size() == rightFrames.size(), "--left-frames has " + std::to_string(leftFrames.size()) +
                                                       " images but --right-frames has " +
                                                       std::to_string(rightFrames.size()) + ": they must pair up");
  StereoCalibration calibration = StereoCalibration::read(arguments.required("calib"));
  calibration.adoptFrameSize(loadImage(leftFrames.front().string()).size(), "'" + arguments.required("left-frames") + "'");
  const std::string out = arguments.required("out");
  const bool rectified = arguments.has("rectified");
  const bool quiet = arguments.has("quiet");
  const double fps = arguments.number("fps", 30.0);
  require(fps > 0 && std::isfinite(fps), "--fps must be positive");

  StereoParameters stereoParameters;
  FrameTrackerOptions trackerOptions;
  if (arguments.has("params")) {
    const std::string path = arguments.required("params");
    stereoParameters = StereoParameters::readFile(path);
    const cv::FileStorage storage(path, cv::FileStorage::READ);
    require(storage.isOpened(), "cannot read parameters file '" + path + "'");
    trackerOptions.tracking = TrackingParameters::read(storage["tracking"]);
  }
  stereoParameters.minDisparityPx = arguments.integer("min-disparity", stereoParameters.minDisparityPx);
  stereoParameters.maxDisparityPx = arguments.integer("max-disparity", stereoParameters.maxDisparityPx);
  const Device device = parseDevice(arguments.text("device", "auto"));
  const std::string featureChoice =
      arguments.text("features", device == Device::Cuda ? "tissuemosaic" : "opencv");
  if (featureChoice == "tissuemosaic") {
    trackerOptions.extractor = FeatureExtractor::TissueMosaicOrb;
    trackerOptions.featureDevice = device;
  } else if (featureChoice == "opencv") {
    trackerOptions.extractor = FeatureExtractor::OpenCvOrb;
  } else {
    throw Error("unknown --features '" + featureChoice + "': expected opencv or tissuemosaic");
  }

  Eigen::Matrix4d T_world_start = Eigen::Matrix4d::Identity();
  if (arguments.has("start-tum")) {
    const Trajectory start = readTumTrajectory(arguments.required("start-tum"));
    require(!start.empty(), "--start-tum '" + arguments.required("start-tum") + "' holds no pose");
    T_world_start = start.front().T_world_camera;
  }
  Trajectory groundTruth;
  if (arguments.has("groundtruth")) groundTruth = readTumTrajectory(arguments.required("groundtruth"));

  const StereoRectifier rectifier(calibration);
  const RectifiedGeometry& geometry = rectifier.geometry();
  StereoMatcher matcher(device, stereoParameters);
  FrameTracker tracker(geometry, trackerOptions, T_world_start);
  std::ofstream file(out);
  require(file.good(), "cannot write trajectory '" + out + "'");
  file << "# TissueMosaic track: T_world_camera of the left rectified camera, millimetres, seconds\n"
       << "# t tx ty tz qx qy qz qw\n";

  std::vector<double> loadMs, rectifyMs, stereoMs, orbMs, pnpMs, totalMs;
  int lost = 0, keyFrames = 0;
  Trajectory tracked;
  const int count = static_cast<int>(leftFrames.size());
  for (int index = 0; index < count; ++index) {
    const auto t0 = std::chrono::steady_clock::now();
    const ImagePair pair = loadImagePair(leftFrames[index].string(), rightFrames[index].string());
    require(pair.left.size() == calibration.imageSize,
            "frame '" + leftFrames[index].string() + "' is " + std::to_string(pair.left.cols) + "x" +
                std::to_string(pair.left.rows) + " but the calibration is for " +
                std::to_string(calibration.imageSize.width) + "x" + std::to_string(calibration.imageSize.height));
    const auto t1 = std::chrono::steady_clock::now();
    cv::Mat left = pair.left, right = pair.right;
    if (!rectified) rectifier.rectify(pair.left, pair.right, left, right);
    const auto t2 = std::chrono::steady_clock::now();
    const cv::Mat disparity = matcher.computeDisparity(left, right);
    const auto t3 = std::chrono::steady_clock::now();
    const TrackResult result = tracker.track(left, disparity);
    const auto t4 = std::chrono::steady_clock::now();
    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    loadMs.push_back(ms(t0, t1));
    rectifyMs.push_back(ms(t1, t2));
    stereoMs.push_back(ms(t2, t3));
    orbMs.push_back(result.orbVotingMs);
    if (!result.initial) pnpMs.push_back(result.pnpMs);
    totalMs.push_back(ms(t0, t4));

    TimedPose pose;
    pose.timeS = index / fps;
    pose.T_world_camera = result.T_world_camera;
    if (result.tracked) {
      file << formatTumLine(pose) << "\n";
      keyFrames += result.keyFrame;
      tracked.push_back(pose);
    } else {
      file << "# frame " << index << " lost: " << result.failureReason << "\n";
      ++lost;
    }
    if (!quiet) {
      std::cerr << cv::format("\rframe %d/%d: %s, %d features (%d with depth), %d matches, %d inliers%s, %.0f ms   ",
                              index + 1, count, result.tracked ? "tracked" : "LOST", result.features,
                              result.featuresWithDepth, result.matches, result.inliers,
                              result.keyFrame ? ", key frame" : "", totalMs.back());
      if (!result.tracked) std::cerr << "\n  frame " << index << " lost: " << result.failureReason << "\n";
    }
  }
  if (!quiet) std::cerr << "\n";
  file.flush();
  require(file.good(), "cannot write trajectory '" + out + "' (disk full?)");

  std::cout << "tracked " << count - lost << " of " << count << " frames (" << lost << " lost, " << keyFrames
            << " key frames) on " << deviceDescription(device) << "; wrote " << out << "\n";
  std::cout << cv::format("per-frame milliseconds (median / mean): load %.1f / %.1f, rectify %.1f / %.1f, stereo "
                          "%.1f / %.1f, ORB + voting %.1f / %.1f, DynamicR1PPnP %.1f / %.1f, total %.1f / %.1f\n",
                          median(loadMs), mean(loadMs), median(rectifyMs), mean(rectifyMs), median(stereoMs),
                          mean(stereoMs), median(orbMs), mean(orbMs), median(pnpMs), mean(pnpMs), median(totalMs),
                          mean(totalMs));
  if (!groundTruth.empty()) {
    const AssociatedPoses associated = associateByTime(tracked, groundTruth, 0.5 / fps);
    require(associated.size() > 0, "--groundtruth: no tracked frame has a ground-truth pose within half a frame "
                                   "of its time stamp (check --fps)");
    const TrajectoryErrors errors = trajectoryErrors(associated, TrajectoryAlignment::None);
    std::cout << cv::format("absolute trajectory error (no alignment, %zu frames): RMS %.3f mm, max %.3f mm; "
                            "relative pose error per frame: RMS %.3f mm\n",
                            errors.poses, errors.ateRmseMm, errors.ateMaxMm, errors.rpeRmseMm);
  }
  return count > 1 && lost == count - 1 ? 1 : 0;  // nothing beyond the start tracked: a failed run
}

}  // namespace tissuemosaic::cli
