// tissuemosaic reconstruct: a stereo video to a fused, textured point model, its key-frame trajectory and the
// paper's runtime table (sections II-III end to end).
#include "Arguments.h"
#include "Commands.h"
#include "ModelOutput.h"
#include "ProgressBar.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/StereoRig.h"
#include "Core/Stopwatch.h"
#include "IO/PointCloudPly.h"
#include "IO/StereoFrameSource.h"
#include "IO/TrajectoryTum.h"
#include "Reconstruction/QualityLog.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "Reconstruction/TimingTable.h"

#include <opencv2/core.hpp>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace tissuemosaic::cli {

namespace {

const char* const help = R"(usage: tissuemosaic reconstruct INPUT [--calib rig.yml] --out model.ply [options]

Reconstructs a stereo video (paper sections II-III): stereo matching, ORB tracking with DynamicR1PPnP, key-frame
refinement (bundle adjustment + point-to-plane ICP) and point-based TSDF fusion. Prints the paper's per-stage
timing table (median and mean milliseconds per key frame and per other frame) and the peak memory.

INPUT, one of:
  --left-frames DIR --right-frames DIR   two folders of frames (PNG/JPEG/..., paired in file-name order)
  --left-video L --right-video R         two video files
  --video SBS                            one side-by-side video (left eye in the left half)
Geometry, one of:
  --calib rig.yml          OpenCV YAML/XML stereo calibration (K1 D1 K2 D2 R T, image size): frames are rectified
  --calib rig.yml --rectified   frames already rectified as StereoRectifier makes them from rig.yml
  --focal-px F --baseline-mm B [--cx-px X] [--cy-px Y] [--doffs-px D]
                           frames already rectified, with this geometry (cx, cy default to the image centre)
Outputs:
  --out model.ply          the fused model: binary PLY with colour and normals, or .vtp (VTK XML, LPS mark)
                           when the name ends so (.vtp needs a build with VTK). World frame: the first left
                           rectified camera (or --start-tum's pose), millimetres.
  --trajectory traj.txt    the key frames' refined poses, TUM (t tx ty tz qx qy qz qw, T_world_camera, mm)
  --frames-trajectory T    every tracked frame's pose, TUM (lost frames as comments)
  --timing-json t.json     the timing table and memory figures as JSON, with "lost_spans" ([[first, last], ...]:
                           frames reported lost) and "relocalisations" ([frame, ...]: the first frame tracked
                           again after each span)
  --quality-json q.json    the model agreement of every frame (docs/RECONSTRUCTION.md), a JSON array of records
                           {"frame", "status" (tracked | lost | relocalised), "median_depth_difference_mm",
                           "share_within_1mm" (null where not measured: lost, or no model in view), "inliers"}
  --snapshot view.png      an offscreen rendering of the model and the key-frame frusta (needs VTK; uses a
                           private Xvfb when there is no display)
Options:
  --params p.yml           parameters file (nodes stereo, features, tracking, refinement, fusion, pipeline)
  --device cpu|cuda|auto   where the engine runs (default auto)
  --fps F                  frame rate of frame folders (default 30)
  --max-frames N           stop after N frames
  --start-tum T.txt        the first frame's pose: the first pose of this TUM file (e.g. a ground truth)
  --min-disparity A --max-disparity B   override the stereo disparity range
  --quiet                  no progress bar
)";

std::unique_ptr<StereoFrameSource> openSource(const Arguments& arguments, double fps) {
  const bool folders = arguments.has("left-frames") || arguments.has("right-frames");
  const bool videos = arguments.has("left-video") || arguments.has("right-video");
  const bool sideBySide = arguments.has("video");
  require(folders + videos + sideBySide == 1,
          "give exactly one input: --left-frames/--right-frames, --left-video/--right-video or --video");
  if (folders) {
    return StereoFrameSource::openFrameFolders(arguments.required("left-frames"), arguments.required("right-frames"),
                                               fps);
  }
  if (videos) return StereoFrameSource::openVideoPair(arguments.required("left-video"), arguments.required("right-video"));
  return StereoFrameSource::openSideBySideVideo(arguments.required("video"));
}

/// The geometry of already rectified frames given on the command line.
RectifiedGeometry geometryFromOptions(const Arguments& arguments, const cv::Size& size) {
  RectifiedGeometry geometry;
  geometry.imageSize = size;
  geometry.focalPx = arguments.number("focal-px", 0);
  geometry.baselineMm = arguments.number("baseline-mm", 0);
  geometry.cxLeftPx = arguments.number("cx-px", (size.width - 1) / 2.0);
  geometry.cyPx = arguments.number("cy-px", (size.height - 1) / 2.0);
  geometry.doffsPx = arguments.number("doffs-px", 0);
  require(geometry.focalPx > 0 && std::isfinite(geometry.focalPx), "--focal-px must be a positive number of pixels");
  require(geometry.baselineMm > 0 && std::isfinite(geometry.baselineMm), "--baseline-mm must be a positive number of mm");
  geometry.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -geometry.cxLeftPx, 0, 1, 0, -geometry.cyPx, 0, 0, 0,
                geometry.focalPx, 0, 0, 1.0 / geometry.baselineMm, geometry.doffsPx / geometry.baselineMm);
  return geometry;
}

double peakHostMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

}  // namespace

int runReconstruct(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"left-frames", "right-frames", "left-video", "right-video", "video", "calib", "rectified",
                       "focal-px", "baseline-mm", "cx-px", "cy-px", "doffs-px", "out", "trajectory",
                       "frames-trajectory", "timing-json", "quality-json", "snapshot", "params", "device", "fps",
                       "max-frames",
                       "start-tum", "min-disparity", "max-disparity", "quiet"});
  const std::string out = arguments.required("out");
  checkModelOutputPath(out);
  // The reports are written after the run: a folder that does not exist is refused before it starts.
  for (const char* report : {"quality-json", "timing-json", "frames-trajectory", "trajectory"}) {
    if (!arguments.has(report)) continue;
    const std::filesystem::path parent = std::filesystem::path(arguments.required(report)).parent_path();
    require(parent.empty() || std::filesystem::is_directory(parent),
            std::string("cannot write --") + report + " '" + arguments.required(report) + "': the folder '" +
                parent.string() + "' does not exist");
  }
  if (arguments.has("snapshot")) checkSnapshotAvailable();
  const double fps = arguments.number("fps", 30.0);
  require(fps > 0 && std::isfinite(fps), "--fps must be positive");
  const int maxFrames = arguments.integer("max-frames", -1);
  require(maxFrames == -1 || maxFrames > 0, "--max-frames must be positive");

  ReconstructionParameters parameters;
  if (arguments.has("params")) parameters = ReconstructionParameters::readFile(arguments.required("params"));
  parameters.stereo.minDisparityPx = arguments.integer("min-disparity", parameters.stereo.minDisparityPx);
  parameters.stereo.maxDisparityPx = arguments.integer("max-disparity", parameters.stereo.maxDisparityPx);
  parameters.validate();
  const Device device = parseDevice(arguments.text("device", "auto"));

  Eigen::Matrix4d T_world_start = Eigen::Matrix4d::Identity();
  if (arguments.has("start-tum")) {
    const Trajectory start = readTumTrajectory(arguments.required("start-tum"));
    require(!start.empty(), "--start-tum '" + arguments.required("start-tum") + "' holds no pose");
    T_world_start = start.front().T_world_camera;
  }

  std::unique_ptr<StereoFrameSource> source = openSource(arguments, fps);
  const cv::Size frameSize = source->frameSize();
  std::unique_ptr<ReconstructionPipeline> pipeline;
  const bool hasFocal = arguments.has("focal-px") || arguments.has("baseline-mm");
  if (arguments.has("calib")) {
    require(!hasFocal, "give either --calib or --focal-px/--baseline-mm, not both");
    const StereoCalibration calibration = StereoCalibration::read(arguments.required("calib"));
    require(calibration.imageSize == frameSize,
            "the calibration is for " + std::to_string(calibration.imageSize.width) + "x" +
                std::to_string(calibration.imageSize.height) + " but the frames of " + source->description() +
                " are " + std::to_string(frameSize.width) + "x" + std::to_string(frameSize.height));
    if (arguments.has("rectified")) {
      pipeline = std::make_unique<ReconstructionPipeline>(StereoRectifier(calibration).geometry(), parameters, device,
                                                          T_world_start);
    } else {
      pipeline = std::make_unique<ReconstructionPipeline>(calibration, parameters, device, T_world_start);
    }
  } else {
    require(hasFocal, "give the geometry: --calib rig.yml, or --focal-px and --baseline-mm for rectified frames");
    pipeline = std::make_unique<ReconstructionPipeline>(geometryFromOptions(arguments, frameSize), parameters, device,
                                                        T_world_start);
  }

  const bool quiet = arguments.has("quiet");
  const int total = maxFrames > 0 && (source->frameCount() < 0 || maxFrames < source->frameCount())
                        ? maxFrames : source->frameCount();
  ProgressBar progress(total, !quiet);
  TimingTable timing;
  Trajectory framePoses;
  std::string framesLog;
  int lost = 0;
  QualityLog quality;
  bool budgetWarned = false;
  StereoFrame frame;
  for (int index = 0; maxFrames < 0 || index < maxFrames; ++index) {
    const auto readStart = std::chrono::steady_clock::now();
    if (!source->next(frame)) break;
    const double readMs = millisecondsSince(readStart);
    FrameResult result = pipeline->process(frame.left, frame.right, frame.timeS);
    result.timesMs.videoReading += readMs;
    result.timesMs.total += readMs;
    timing.add(result);
    quality.add(result);
    if (result.tracked) {
      TimedPose pose;
      pose.timeS = frame.timeS;
      pose.T_world_camera = result.T_world_camera;
      framePoses.push_back(pose);
    } else {
      ++lost;
      framesLog += "frame " + std::to_string(frame.index) + " lost: " + result.trackingMessage + "\n";
      progress.message("frame " + std::to_string(frame.index) + " lost: " + result.trackingMessage);
    }
    if (result.pointBudgetReached && !budgetWarned) {
      budgetWarned = true;
      progress.message("the model reached its point budget (" + std::to_string(parameters.fusion.maxPoints) +
                       " points, fusion parameter maxPoints): new surface is no longer added");
    }
    progress.update(index + 1, cv::format("%d key frames, %zu points, %s", static_cast<int>(pipeline->keyFrames().size()),
                                          result.modelPoints, QualityLog::progressText(result).c_str()));
  }
  progress.finish();
  const int frames = pipeline->frameCount();
  require(frames > 0, "no frame could be read from " + source->description());
  require(frames == 1 || lost < frames - 1, "tracking was lost on every frame after the first: no reconstruction");

  const ModelPoints model = pipeline->modelSnapshot();
  require(model.size() > 0, "the reconstruction produced no model points (tracking never started?)");
  writeModelFile(out, model.cloud, "TissueMosaic reconstruct: world frame = first left rectified camera, mm");
  if (arguments.has("trajectory")) {
    Trajectory keyFrames;
    for (const KeyFramePose& k : pipeline->keyFrames()) {
      TimedPose pose;
      pose.timeS = k.timeS;
      pose.T_world_camera = k.T_world_camera;
      keyFrames.push_back(pose);
    }
    writeTumTrajectory(arguments.required("trajectory"), keyFrames,
                       "TissueMosaic reconstruct: key frames, T_world_camera of the left rectified camera, mm\n"
                       "t tx ty tz qx qy qz qw");
  }
  if (arguments.has("frames-trajectory")) {
    writeTumTrajectory(arguments.required("frames-trajectory"), framePoses,
                       "TissueMosaic reconstruct: every tracked frame, T_world_camera, mm\nt tx ty tz qx qy qz qw\n" +
                           framesLog);
  }
  std::string snapshotLine;
  if (arguments.has("snapshot")) snapshotLine = renderSnapshot(arguments.required("snapshot"), *pipeline);

  const double hostMb = peakHostMegabytes();
  const double deviceMb = pipeline->peakDeviceBytes() / (1024.0 * 1024.0);
  std::cout << "reconstructed " << frames << " frames (" << frames - lost << " tracked, " << lost << " lost, "
            << pipeline->keyFrames().size() << " key frames) on " << deviceDescription(device) << "\n"
            << "model: " << model.size() << " points -> " << out << "\n\n"
            << timing.format() << "\n"
            << cv::format("peak memory: host %.0f MiB (resident), device %.0f MiB (in use, with the CUDA context)\n",
                          hostMb, deviceMb);
  if (!snapshotLine.empty()) std::cout << snapshotLine << "\n";
  if (arguments.has("quality-json")) quality.writeJson(arguments.required("quality-json"));
  if (arguments.has("timing-json")) {
    std::ofstream json(arguments.required("timing-json"));
    require(json.good(), "cannot write '" + arguments.required("timing-json") + "'");
    json << "{\"device\": \"" << deviceDescription(device) << "\", \"width\": " << frameSize.width
         << ", \"height\": " << frameSize.height << ", \"frames\": " << frames << ", \"lost\": " << lost
         << ", \"key_frames\": " << pipeline->keyFrames().size() << ", \"model_points\": " << model.size()
         << ", \"peak_host_mib\": " << cv::format("%.1f", hostMb) << ", \"peak_device_mib\": "
         << cv::format("%.1f", deviceMb) << ", \"lost_spans\": " << quality.lostSpansJson()
         << ", \"relocalisations\": " << quality.relocalisationsJson() << ", \"timing\": " << timing.toJson() << "}\n";
    require(json.good(), "cannot write '" + arguments.required("timing-json") + "' (disk full?)");
  }
  return 0;
}

}  // namespace tissuemosaic::cli
