// tissuemosaic reconstruct: a stereo video to a fused, textured point model, its key-frame trajectory and the
// paper's runtime table (sections II-III end to end).
#include "CommonOptions.h"
#include "Commands.h"
#include "IgtLinkOptions.h"
#include "ModelFile.h"
#include "Snapshot.h"
#include "ProgressBar.h"
#include "StopSignal.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/StereoRig.h"
#include "Core/Stopwatch.h"
#include "Deformation/DeformationRecord.h"
#include "IO/AtomicFile.h"
#include "IO/PointCloudPly.h"
#include "IO/StereoFrameSource.h"
#include "IO/TrajectoryTum.h"
#include "Reconstruction/QualityLog.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "Reconstruction/TimingTable.h"
#include "Stereo/DisparityRangeEstimator.h"

#include <opencv2/core.hpp>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <utility>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Reconstructs a stereo video (paper sections II-III): stereo matching, ORB tracking with DynamicR1PPnP, key-frame
refinement (bundle adjustment + point-to-plane ICP) and point-based TSDF fusion. Prints the paper's per-stage
timing table (median and mean milliseconds per key frame and per other frame) and the peak memory. The model's
world frame is the first left rectified camera (or --start-tum's pose), in millimetres; .vtp output needs a build
with VTK, and so does --snapshot (a private Xvfb when there is no display). Live inputs (devices, pipelines,
OpenIGTLink) are read in real time, the newest frame first; the summary counts the frames dropped. Ctrl-C or SIGTERM
stops the scan cleanly and writes the outputs; a second one ends the program at once. Without a disparity range it is
chosen from the first frame's sparse feature matches and follows the tissue as the scope moves (printed at the end,
and in --timing-json as "disparity_range").)";

struct ReconstructOptions {
  InputOptions input;
  GeometryOptions geometry;
  std::string out;
  std::optional<std::string> trajectory, framesTrajectory, timingJson, qualityJson, snapshot, startTum, params;
  std::optional<std::string> deformation, deformationOut, canonicalOut, liveOut, liveFrames;
  int liveEvery = 10;
  std::optional<int> maxFrames;
  DisparityRangeOptions range;
  StereoSearchOption search;
  DeviceOption device;
  IgtLinkServerOptions igtl;
  bool quiet = false;
};

double peakHostMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

void runReconstruct(ReconstructOptions options) {
  const DatasetInput dataset = applyDatasetLayout(options.input, options.geometry);
  checkModelOutputPath(options.out);
  // Every output is checked before any work: a bad secondary path found after the scan would waste it.
  if (options.trajectory) requireWritableOutput(*options.trajectory, "trajectory (--trajectory)");
  if (options.framesTrajectory) requireWritableOutput(*options.framesTrajectory, "trajectory (--frames-trajectory)");
  if (options.qualityJson) requireWritableOutput(*options.qualityJson, "quality JSON (--quality-json)");
  if (options.timingJson) requireWritableOutput(*options.timingJson, "timing JSON (--timing-json)");
  if (options.deformationOut) requireWritableOutput(*options.deformationOut, "deformation record (--deformation-out)");
  if (options.canonicalOut) requireWritableOutput(*options.canonicalOut, "canonical surface (--canonical-out)");
  if (options.liveOut) requireWritableOutput(*options.liveOut, "live model (--live-out)");
  if (options.liveFrames) {
    std::error_code made;
    std::filesystem::create_directories(*options.liveFrames, made);
    require(std::filesystem::is_directory(*options.liveFrames),
            "cannot make the folder '" + *options.liveFrames + "' for --live-frames");
  }
  if (options.snapshot) {
    checkSnapshotAvailable();
    requireWritableOutput(*options.snapshot, "snapshot (--snapshot)");
  }
  const int maxFrames = options.maxFrames.value_or(-1);
  require(!options.maxFrames || maxFrames > 0, "--max-frames must be positive");

  ReconstructionParameters parameters;
  if (options.params) parameters = ReconstructionParameters::readFile(*options.params);
  options.range.applyTo(parameters.stereo);
  options.search.applyTo(parameters.stereo);
  if (options.deformation) parameters.fusion.deformation = *options.deformation == "on";
  require((!options.deformationOut && !options.canonicalOut && !options.liveOut && !options.liveFrames) ||
              parameters.fusion.deformation,
          std::string(options.deformationOut   ? "--deformation-out"
                      : options.canonicalOut ? "--canonical-out"
                      : options.liveOut      ? "--live-out"
                                             : "--live-frames") +
              " needs the deformation on (--deformation on, or fusion.deformation: on in --params)");
  parameters.validate();
  const Device device = options.device.resolve();

  Eigen::Matrix4d T_world_start = Eigen::Matrix4d::Identity();
  if (options.startTum) {
    const Trajectory start = readTumTrajectory(*options.startTum);
    require(!start.empty(), "--start-tum '" + *options.startTum + "' holds no pose");
    T_world_start = start.front().T_world_camera;
  } else if (!dataset.poses.empty()) {
    T_world_start = dataset.poses.front().T_world_camera;
  }

  std::unique_ptr<StereoFrameSource> source = openInput(options.input);
  const cv::Size frameSize = source->frameSize();
  const StereoGeometry geometry = resolveGeometry(options.geometry, frameSize, source->description());
  requireDisparityRangeMeetsImage(parameters.stereo, frameSize.width);
  const std::unique_ptr<IgtLinkSender> igtl = startIgtLinkSender(options.igtl, std::cerr);
  StereoFrameSource* const sourceToStop = source.get();
  const StopOnSignal stop([sourceToStop] { sourceToStop->interrupt(); });
  // Raw frames: the pipeline rectifies them itself, from the calibration.
  const std::unique_ptr<ReconstructionPipeline> pipeline =
      geometry.rectifier
          ? std::make_unique<ReconstructionPipeline>(*geometry.calibration, parameters, device, T_world_start)
          : std::make_unique<ReconstructionPipeline>(geometry.rectified, parameters, device, T_world_start);
  pipeline->setFrameDisparityKept(false);  // nothing here shows or writes the per-frame disparity

  const int total = maxFrames > 0 && (source->frameCount() < 0 || maxFrames < source->frameCount())
                        ? maxFrames : source->frameCount();
  ProgressBar progress(total, !options.quiet);
  TimingTable timing;
  Trajectory framePoses;
  std::string framesLog;
  int lost = 0;
  QualityLog quality;
  std::optional<DeformationRecordWriter> deformationRecord;
  if (options.deformationOut) deformationRecord.emplace(*options.deformationOut);
  bool budgetWarned = false;
  int framesBeyondRange = 0;  // frames whose scene outgrew the disparity range (rangeTooNarrowWarning)
  StereoFrame frame;
  double lastTimeS = 0;
  for (int index = 0; (maxFrames < 0 || index < maxFrames) && !stop.requested(); ++index) {
    const auto readStart = std::chrono::steady_clock::now();
    if (!source->next(frame)) break;
    lastTimeS = frame.timeS;
    const double readMs = millisecondsSince(readStart);
    FrameResult result;
    try {
      result = pipeline->process(frame.left, frame.right, frame.timeS);
    } catch (const DisparityRangeError& error) {
      rethrowWithRangeOptions(error);
    }
    if (index == 0) {
      const std::string warning = rowOffsetWarning(pipeline->disparityRangeHistory());
      if (!warning.empty()) progress.message("warning: the stereo pair is " + warning);
    }
    if (const std::string warning = rangeTooNarrowWarning(result.disparityRangeEnds); !warning.empty()) {
      if (framesBeyondRange++ == 0) progress.message("warning: frame " + std::to_string(frame.index) + ": " + warning);
    }
    result.timesMs.videoReading += readMs;
    result.timesMs.total += readMs;
    timing.add(result);
    quality.add(result);
    if (deformationRecord && result.deformation.fitted) {
      deformationRecord->write(result.frameIndex, frame.timeS, *pipeline->deformationGraph());
    }
    if (options.liveFrames && result.tracked && result.frameIndex % options.liveEvery == 0) {
      // Numbered as the generator's groundtruth/surface_NNNNNN.ply, for `eval` frame by frame.
      writeModelFile((std::filesystem::path(*options.liveFrames) / cv::format("live_%06d.ply", result.frameIndex)).string(),
                     pipeline->liveModelSnapshot().cloud,
                     "TissueMosaic reconstruct: the fused model where the tissue is at frame " +
                         std::to_string(result.frameIndex) + " (the live surface), world frame, mm");
    }
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
    if (igtl) {
      igtl->frameProcessed(frame.index, frame.timeS, result.tracked, result.T_world_camera, result.trackingMessage,
                           result.leftRectified);
      if (result.keyFrame && igtl->modelDue()) igtl->modelUpdated(pipeline->liveModelSnapshot().cloud, frame.timeS);
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
  // The live surface (where the tissue is at the last frame) is what a viewer shows; the model at rest is exported.
  const ModelPoints liveModel = parameters.fusion.deformation ? pipeline->liveModelSnapshot() : ModelPoints{};
  if (igtl) {
    igtl->finished(parameters.fusion.deformation ? liveModel.cloud : model.cloud, lastTimeS,
                   std::to_string(frames) + " frames, " + std::to_string(model.size()) + " model points" +
                       (stop.requested() ? " (stopped by a signal)" : ""));
  }
  require(model.size() > 0, "the reconstruction produced no model points (tracking never started?)");
  OutputBatch outputs;  // the model, trajectories, snapshot and timing replace existing files together, or not at all
  writeModelFile(options.out, model.cloud, kReconstructedModelComment);
  if (options.liveOut) {
    writeModelFile(*options.liveOut, liveModel.cloud,
                   "TissueMosaic reconstruct: the fused model where the tissue is at the last frame (the live surface), "
                   "world frame, mm");
  }
  if (options.trajectory) {
    Trajectory keyFrames;
    for (const KeyFramePose& k : pipeline->keyFrames()) {
      TimedPose pose;
      pose.timeS = k.timeS;
      pose.T_world_camera = k.T_world_camera;
      keyFrames.push_back(pose);
    }
    writeTumTrajectory(*options.trajectory, keyFrames, kKeyFrameTrajectoryHeader);
  }
  if (options.framesTrajectory) {
    writeTumTrajectory(*options.framesTrajectory, framePoses,
                       "TissueMosaic reconstruct: every tracked frame, T_world_camera, mm\nt tx ty tz qx qy qz qw\n" +
                           framesLog);
  }
  if (options.canonicalOut) {
    const DeformationTracker& field = *pipeline->deformation();
    ColoredPointCloud canonical;
    for (std::size_t i = 0; i < field.canonicalPoints().size(); ++i) {
      const Eigen::Vector3d& p = field.canonicalPoints()[i];
      const Eigen::Vector3d& n = field.canonicalNormals()[i];
      canonical.pointsMm.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
      canonical.normals.emplace_back(static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z()));
    }
    writePly(*options.canonicalOut, canonical, "TissueMosaic deformation: canonical surface samples, world frame, mm");
  }
  std::string snapshotLine;
  if (options.snapshot) snapshotLine = renderSnapshot(*options.snapshot, *pipeline);

  const double hostMb = peakHostMegabytes();
  const double deviceMb = pipeline->peakDeviceBytes() / (1024.0 * 1024.0);
  std::cout << "reconstructed " << frames << " frames (" << frames - lost << " tracked, " << lost << " lost, "
            << pipeline->keyFrames().size() << " key frames) on " << deviceDescription(device) << "\n"
            << "model: " << model.size() << " points -> " << options.out << "\n"
            << "disparity range " << pipeline->disparityRangeDescription()
            << (framesBeyondRange > 0 ? "; warning: the scene outgrew it on " + std::to_string(framesBeyondRange) +
                                            " frames (most of their pixels lost)"
                                      : std::string())
            << "\n\n"
            << timing.format() << "\n"
            << cv::format("peak memory: host %.0f MiB (resident), device %.0f MiB (in use, with the CUDA context)\n",
                          hostMb, deviceMb);
  if (!snapshotLine.empty()) std::cout << snapshotLine << "\n";
  if (!dataset.description.empty()) {
    std::cout << "data set: " << dataset.description << (dataset.note.empty() ? "" : "; " + dataset.note)
              << (!options.startTum && !dataset.poses.empty() ? " (the first is the start pose)" : "") << "\n";
  }
  if (!geometry.calibrationLayout.empty()) {
    std::cout << "calibration: " << geometry.calibrationLayout
              << (geometry.imageSizeFromFrames ? ", image size from the frames" : "") << "\n";
  }
  if (source->isLive()) {
    std::cout << "live source: " << frames << " frames reconstructed, " << source->droppedFrames()
              << " dropped (newer frames came while one was reconstructed)"
              << (stop.requested() ? "; stopped by a signal" : "") << "\n";
  } else if (stop.requested()) {
    std::cout << "stopped by a signal after " << frames << " frames\n";
  }
  if (const std::string input = igtLinkInputSummary(*source); !input.empty()) std::cout << input << "\n";
  if (igtl) std::cout << igtl->summary() << "\n";
  if (options.qualityJson) quality.writeJson(*options.qualityJson);
  if (options.timingJson) {
    std::ostringstream json;
    json << "{\"device\": \"" << deviceDescription(device) << "\", \"width\": " << frameSize.width
         << ", \"height\": " << frameSize.height << ", \"frames\": " << frames << ", \"lost\": " << lost
         << ", \"key_frames\": " << pipeline->keyFrames().size() << ", \"model_points\": " << model.size()
         << ", \"live\": " << (source->isLive() ? "true" : "false") << ", \"dropped_frames\": "
         << source->droppedFrames() << ", \"stopped_by_signal\": " << (stop.requested() ? "true" : "false")
         << ", \"peak_host_mib\": " << cv::format("%.1f", hostMb) << ", \"peak_device_mib\": "
         << cv::format("%.1f", deviceMb) << ", \"disparity_range\": "
         << disparityRangeJson(pipeline->disparityRangeHistory()) << ", \"frames_beyond_disparity_range\": "
         << framesBeyondRange << ", \"lost_spans\": " << quality.lostSpansJson()
         << ", \"relocalisations\": " << quality.relocalisationsJson() << ", \"timing\": " << timing.toJson() << "}\n";
    writeStreamAtomically(*options.timingJson, "timing JSON", [&](std::ostream& out) { out << json.str(); });
  }
  outputs.commit();
  stop.throwIfRequested("after " + std::to_string(frames) + " frames");  // exit status 128 + the signal
}

}  // namespace

void setupReconstruct(CLI::App& tool, CommandUse use) {
  auto options = std::make_shared<ReconstructOptions>();
  CLI::App* command = addCommand(tool, "reconstruct", "the whole pipeline: a fused, textured point model, key-frame "
                                                     "trajectory and timing table", details);
  addInputOptions(*command, options->input);
  addGeometryOptions(*command, options->geometry);
  command->add_option("--out", options->out, "the fused model: binary PLY with colour and normals, or .vtp (VTK XML, "
                                             "LPS mark)")
      ->required()
      ->type_name("model.ply|.vtp")
      ->group(heading::output);
  command->add_option("--trajectory", options->trajectory, "the key frames' refined poses (TUM, T_world_camera, mm)")
      ->type_name("traj.txt")
      ->group(heading::output);
  command->add_option("--frames-trajectory", options->framesTrajectory, "every tracked frame's pose (TUM; lost "
                                                                        "frames as comments)")
      ->type_name("T.txt")
      ->group(heading::output);
  command->add_option("--timing-json", options->timingJson,
                      "the timing table and memory figures as JSON, with \"lost_spans\" ([[first, last], ...]: frames "
                      "reported lost) and \"relocalisations\" ([frame, ...]: the first frame tracked again after each)")
      ->type_name("t.json")
      ->group(heading::output);
  command->add_option("--quality-json", options->qualityJson,
                      "the model agreement of every frame (docs/SCENE_MOTION.md): a JSON array of {\"frame\", \"status\" "
                      "(tracked | lost | relocalised), \"median_depth_difference_mm\", \"share_within_1mm\" (null where "
                      "not measured), \"inliers\", \"key_frame\", \"moving_matches\", \"disparity_range\", \"message\", "
                      "\"scene_motion\", \"deformation_mean_mm\", \"deformation_max_mm\", "
                      "\"live_share_within_1mm\", \"rigid_share_within_1mm\" (null unless --deformation on; docs/DEFORMATION.md)}")
      ->type_name("q.json")
      ->group(heading::output);
  command->add_option("--deformation", options->deformation,
                      "fit the deformation graph over the model to every frame (fusion.deformation; docs/DEFORMATION.md): "
                      "the node motions and the live surface's agreement in --quality-json; the fused model follows "
                      "the tissue: --out holds it at rest (the first frame's state), --live-out where it is at the end")
      ->check(CLI::IsMember({"on", "off"}))
      ->type_name("on|off")
      ->group(heading::options);
  command->add_option("--deformation-out", options->deformationOut,
                      "every frame's deformation graph as JSON Lines: {\"frame\", \"time_s\", \"nodes\": [[gx, gy, gz, "
                      "tx, ty, tz, rx, ry, rz], ...]} (rest position, motion in mm, rotation vector; docs/DEFORMATION.md)")
      ->type_name("d.jsonl")
      ->group(heading::output);
  command->add_option("--canonical-out", options->canonicalOut,
                      "the deformation's canonical surface at the end: its samples where the tissue rests (the first "
                      "frame's state), with normals, as PLY (needs --deformation on; docs/DEFORMATION.md)")
      ->type_name("canonical.ply")
      ->group(heading::output);
  command->add_option("--live-out", options->liveOut,
                      "the fused model where the tissue is at the last frame (the live surface: --out's model at rest "
                      "moved by the last frame's deformation), as --out (needs --deformation on; docs/DEFORMATION.md)")
      ->type_name("live.ply|.vtp")
      ->group(heading::output);
  command->add_option("--live-frames", options->liveFrames,
                      "a folder (made if missing) for the live model every --live-every tracked frames, as "
                      "live_NNNNNN.ply (N: the frame index, as a synthetic scan's groundtruth/surface_NNNNNN.ply; needs "
                      "--deformation on)")
      ->type_name("DIR")
      ->group(heading::output);
  command->add_option("--live-every", options->liveEvery, "--live-frames: write every N-th frame's live model")
      ->check(CLI::Range(1, 1000000))
      ->type_name("N")
      ->default_val(10)
      ->group(heading::output);
  command->add_option("--snapshot", options->snapshot, "an offscreen rendering of the model and the key-frame frusta "
                                                       "(needs VTK)")
      ->type_name("view.png")
      ->group(heading::output);
  command->add_option("--start-tum", options->startTum,
                      "the first frame's pose: the first pose of this TUM file (e.g. a ground truth)")
      ->type_name("T.txt")
      ->group(heading::options);
  command->add_option("--max-frames", options->maxFrames, "stop after N frames")->group(heading::options);
  addDisparityRangeOptions(*command, options->range);
  addStereoSearchOption(*command, options->search);
  addDeviceOption(*command, options->device);
  addParamsOption(*command, options->params, "stereo, features, tracking, refinement, fusion, pipeline");
  addIgtLinkServerOptions(*command, options->igtl);
  addQuietFlag(*command, options->quiet, "no progress bar");
  command->callback([options, use] {
    if (use == CommandUse::Run) runReconstruct(*options);
  });
}

}  // namespace tissuemosaic::cli
