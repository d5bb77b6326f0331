// tissuemosaic track: camera tracking over a stereo video (frame folders, two videos or a side-by-side video), to a
// TUM trajectory.
#include "CommonOptions.h"
#include "Commands.h"
#include "StopSignal.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/Statistics.h"
#include "Core/StereoRig.h"
#include "IO/AtomicFile.h"
#include "IO/StereoFrameSource.h"
#include "IO/TrajectoryError.h"
#include "IO/TrajectoryTum.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/DisparityRangeFollower.h"
#include "Stereo/StereoMatcher.h"
#include "Tracking/FrameTracker.h"

#include <opencv2/core/persistence.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace tissuemosaic::cli {

namespace {
const char* const details = R"(Tracks the left camera through a stereo video (paper III.A-C: ORB features lifted with the stereo depth, matching
with the previous tracked frame, histogram voting, DynamicR1PPnP, key-frame decision) and writes its trajectory:
TUM lines "t tx ty tz qx qy qz qw", T_world_camera of the LEFT RECTIFIED camera in mm, t from the video's time
stamps or frame index / --fps. The world frame is the first frame's left rectified camera (pose identity) unless
--start-tum gives another start. Frames where tracking is lost get a "# frame N lost: reason" comment line instead
of a pose. The stereo depth runs on --device, and so do the features with --features tissuemosaic; the pose
solver runs on the CPU. --groundtruth prints the errors against a TUM file: poses associated by time stamp (within
half a frame at --fps), no alignment (give --start-tum the same file for a common start); absolute error (ATE)
and relative pose error between consecutive frames (RPE), as `tissuemosaic eval` computes them. Without a
disparity range it is chosen from the first frame's sparse feature matches and follows the tissue from frame to
frame (docs/STEREO.md); the ranges used are printed at the end.
Exit status 1 when tracking was lost on every frame after the first.)";

struct TrackOptions {
  InputOptions input;
  GeometryOptions geometry;
  std::string out;
  std::optional<std::string> startTum, groundTruth, features, params;
  DisparityRangeOptions range;
  DeviceOption device;
  bool quiet = false;
};

void runTrack(TrackOptions options) {
  const DatasetInput dataset = applyDatasetLayout(options.input, options.geometry);
  requireWritableOutput(options.out, "trajectory");
  StereoParameters stereoParameters;
  FrameTrackerOptions trackerOptions;
  if (options.params) {
    // The whole file is read (and checked strictly), as reconstruct reads it; track uses its stereo and tracking.
    const ReconstructionParameters fileParameters = ReconstructionParameters::readFile(*options.params);
    stereoParameters = fileParameters.stereo;
    trackerOptions.tracking = fileParameters.tracking;
  }
  options.range.applyTo(stereoParameters);
  const Device device = options.device.resolve();
  const std::string featureChoice = options.features.value_or(device == Device::Cuda ? "tissuemosaic" : "opencv");
  if (featureChoice == "tissuemosaic") {
    trackerOptions.extractor = FeatureExtractor::TissueMosaicOrb;
    trackerOptions.featureDevice = device;
  } else if (featureChoice == "opencv") {
    trackerOptions.extractor = FeatureExtractor::OpenCvOrb;
  } else {
    throw Error("unknown --features '" + featureChoice + "': expected opencv or tissuemosaic");
  }

  Eigen::Matrix4d T_world_start = Eigen::Matrix4d::Identity();
  if (options.startTum) {
    const Trajectory start = readTumTrajectory(*options.startTum);
    require(!start.empty(), "--start-tum '" + *options.startTum + "' holds no pose");
    T_world_start = start.front().T_world_camera;
  } else if (!dataset.poses.empty()) {
    T_world_start = dataset.poses.front().T_world_camera;
  }
  // A data set's own poses (SCARED) are the ground truth unless a file is given.
  Trajectory groundTruth = dataset.poses;
  if (options.groundTruth) groundTruth = readTumTrajectory(*options.groundTruth);

  const std::unique_ptr<StereoFrameSource> source = openInput(options.input);
  const StereoGeometry geometry = resolveGeometry(options.geometry, source->frameSize(), source->description());
  requireDisparityRangeMeetsImage(stereoParameters, source->frameSize().width);
  StereoMatcher matcher(device, stereoParameters);
  DisparityRangeFollower range(stereoParameters, geometry.rectified, device);
  FrameTracker tracker(geometry.rectified, trackerOptions, T_world_start);
  // The trajectory is kept in memory and written atomically at the end: a run that fails midway leaves an existing
  // file as it was; one stopped by Ctrl-C or SIGTERM writes the frames it tracked and says so in the file.
  std::ostringstream file;
  file << "# TissueMosaic track: T_world_camera of the left rectified camera, millimetres, seconds\n"
       << "# t tx ty tz qx qy qz qw\n";

  std::vector<double> loadMs, rectifyMs, stereoMs, orbMs, pnpMs, totalMs;
  int count = 0, lost = 0, keyFrames = 0, mostFeatures = 0;
  Trajectory tracked;
  const int expected = source->frameCount();
  StereoFrame frame;
  const StopOnSignal stop(nullptr);
  for (;;) {
    if (stop.requested()) break;
    const auto t0 = std::chrono::steady_clock::now();
    if (!source->next(frame)) break;
    ++count;
    const auto t1 = std::chrono::steady_clock::now();
    cv::Mat left = frame.left, right = frame.right;
    if (geometry.rectifier) geometry.rectifier->rectify(frame.left, frame.right, left, right);
    const auto t2 = std::chrono::steady_clock::now();
    try {
      matcher.setDisparityRange(range.beforeFrame(left, right));  // fixed for the frame
    } catch (const DisparityRangeError& error) {
      rethrowWithRangeOptions(error);
    }
    if (count == 1) {
      const std::string warning = rowOffsetWarning(range.history());
      if (!warning.empty()) std::cerr << "warning: the stereo pair is " << warning << "\n";
    }
    right = range.alignedRight(right);
    // As the reconstruction pipeline does: features near a highlight get no depth (StereoMatcher.h).
    matcher.computeDisparity(left, right);
    const cv::Mat disparity = matcher.lastDisparityAwayFromHighlights();
    const auto t3 = std::chrono::steady_clock::now();
    const TrackResult result = tracker.track(left, disparity);
    range.afterFrame(left, right);  // the next frame's range, from this frame's sparse matches
    const auto t4 = std::chrono::steady_clock::now();
    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    loadMs.push_back(ms(t0, t1));
    rectifyMs.push_back(ms(t1, t2));
    stereoMs.push_back(ms(t2, t3));
    orbMs.push_back(result.timesMs.orbVoting);
    if (!result.initial) pnpMs.push_back(result.timesMs.pnp);
    totalMs.push_back(ms(t0, t4));

    TimedPose pose;
    pose.timeS = frame.timeS;
    pose.T_world_camera = result.T_world_camera;
    mostFeatures = std::max(mostFeatures, result.features);
    if (result.tracked) {
      file << formatTumLine(pose) << "\n";
      keyFrames += result.keyFrame;
      tracked.push_back(pose);
    } else {
      file << "# frame " << frame.index << " lost: " << result.failureReason << "\n";
      ++lost;
    }
    if (!options.quiet) {
      std::cerr << cv::format("\rframe %d/%s: %s, %d features (%d with depth), %d matches, %d inliers%s, %.0f ms   ",
                              count, expected > 0 ? std::to_string(expected).c_str() : "?",
                              result.tracked ? "tracked" : "LOST", result.features, result.featuresWithDepth,
                              result.matches, result.inliers, result.keyFrame ? ", key frame" : "", totalMs.back());
      if (!result.tracked) std::cerr << "\n  frame " << frame.index << " lost: " << result.failureReason << "\n";
    }
  }
  if (!options.quiet) std::cerr << "\n";
  require(count > 0, "no frame could be read from " + source->description());
  if (stop.requested()) file << "# stopped by a signal after " << count << " frames: the trajectory is incomplete\n";
  writeStreamAtomically(options.out, "trajectory", [&](std::ostream& out) { out << file.str(); });

  std::cout << "tracked " << count - lost << " of " << count << " frames (" << lost << " lost, " << keyFrames
            << " key frames) on " << deviceDescription(device) << "; wrote " << options.out << "\n"
            << "disparity range " << range.description() << "\n";
  if (stop.requested()) std::cout << "stopped by a signal after " << count << " frames\n";
  std::cout << cv::format("per-frame milliseconds (median / mean): load %.1f / %.1f, rectify %.1f / %.1f, stereo "
                          "%.1f / %.1f, ORB + voting %.1f / %.1f, DynamicR1PPnP %.1f / %.1f, total %.1f / %.1f\n",
                          median(loadMs), mean(loadMs), median(rectifyMs), mean(rectifyMs), median(stereoMs),
                          mean(stereoMs), median(orbMs), mean(orbMs), median(pnpMs), mean(pnpMs), median(totalMs),
                          mean(totalMs));
  if (!groundTruth.empty()) {
    const AssociatedPoses associated = associateByTime(tracked, groundTruth, 0.5 / options.input.fps);
    require(associated.size() > 0, "--groundtruth: no tracked frame has a ground-truth pose within half a frame "
                                   "of its time stamp (check --fps)");
    const TrajectoryErrors errors = trajectoryErrors(associated, TrajectoryAlignment::None);
    std::cout << cv::format("absolute trajectory error (no alignment, %zu frames): RMS %.3f mm, max %.3f mm; "
                            "relative pose error per frame: RMS %.3f mm\n",
                            errors.poses, errors.ateRmseMm, errors.ateMaxMm, errors.rpeRmseMm);
  }
  require(count == 1 || lost < count - 1,
          "tracking was lost on every frame after the first" +
              std::string(mostFeatures == 0 ? " (no frame has a single ORB feature: are the frames black, saturated or "
                                              "uniform?)"
                                            : ""));
  stop.throwIfRequested("after " + std::to_string(count) + " frames");  // exit status 128 + the signal
}

}  // namespace

void setupTrack(CLI::App& tool) {
  auto options = std::make_shared<TrackOptions>();
  CLI::App* command = addCommand(tool, "track", "camera tracking (ORB, histogram voting, DynamicR1PPnP) to a TUM "
                                               "trajectory", details);
  addInputOptions(*command, options->input);
  addGeometryOptions(*command, options->geometry);
  command->add_option("--out", options->out, "the trajectory (TUM, T_world_camera, mm)")
      ->required()
      ->type_name("trajectory.txt")
      ->group(heading::output);
  command->add_option("--start-tum", options->startTum,
                      "the first frame's pose: the first pose of this TUM file (e.g. a ground truth)")
      ->type_name("T.txt")
      ->group(heading::options);
  command->add_option("--groundtruth", options->groundTruth,
                      "also print the trajectory errors (ATE, RPE) against this TUM file")
      ->type_name("T.txt")
      ->group(heading::options);
  command->add_option("--features", options->features,
                      "ORB implementation: OpenCV's (CPU only) or TissueMosaic's single-source extractor and matcher "
                      "(CPU or CUDA, identical results); default: tissuemosaic on cuda, opencv on cpu")
      ->type_name("opencv|tissuemosaic")
      ->group(heading::options);
  addDisparityRangeOptions(*command, options->range);
  addDeviceOption(*command, options->device, "where stereo and features run");
  addParamsOption(*command, options->params, "stereo, tracking");
  addQuietFlag(*command, options->quiet, "no per-frame progress line");
  command->callback([options] { runTrack(*options); });
}

}  // namespace tissuemosaic::cli
