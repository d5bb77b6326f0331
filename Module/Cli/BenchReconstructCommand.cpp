// tissuemosaic bench reconstruct: the paper's runtime table (per key frame and per other frame) of the whole
// pipeline on a synthetic scan rendered in-process before timing, with the key-frame trajectory error.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/Statistics.h"
#include "IO/MeshPly.h"
#include "IO/PointCloudPly.h"
#include "IO/TrajectoryTum.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "Reconstruction/TimingTable.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include <opencv2/core/utility.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Renders a synthetic scan (before timing), then runs the whole reconstruction on it (stereo, tracking, key-frame
refinement, TSDF fusion) starting from the true first pose, and prints one JSON object: the median, mean and 99th
percentile milliseconds per stage for key frames and for the other frames (the paper's runtime table under "timing",
each with "median_ms", "mean_ms" and "p99_ms"; video_reading is 0:
the frames are in memory), the key-frame position error against the ground truth (no alignment), the model's distances to the true
surface (RMSE, 95th percentile, shares beyond 1, 5 and 50 mm), the share of the key frames' stereo estimates
that are gross errors (> 3 px from the truth, or where the truth has no surface), the model size
and the peak host and device memory. "stereo_parts_*_ms" and "tracking_parts_*_ms" split the stereo and ORB +
voting stages over all frames (host grey conversion and copies beside the GPU's stages; extraction, matching,
sub-pixel refinement, voting), "refinement_parts_*_ms" the key frames' refinement. The range searched is fixed by
default, so that figures compare across sizes and runs: the paper's -20..80 px scaled by width / 960 (--disparities
N changes its count); --disparity-range auto times the automatic range (the scene's, about 36 candidates on the
default scan) and the Disparity range options ask for others. "disparity_range_px" is the widest range searched,
"disparity_range" says how the ranges were chosen and "key_frame_true_disparity_px" gives the key frames' true
disparities: the scan keeps its field of view and working distance at every size, so its disparities grow with the
width. Where the bench's own range cannot hold the first frame's true disparities (--disparities 256 at 3840x2160:
-80..175 px against 220-298 px), it is moved onto them, keeping its count ("disparity_range_moved_to_scene": true).
"frames_beyond_disparity_range" counts the frames whose best matches piled up on an end of the range (the scene
outgrew it; `reconstruct` warns and counts the same), with a warning on stderr at the first.

--stream renders each frame just before it is processed (outside the timed stages) instead of all of them first,
so that the peak host memory is the pipeline's own: for long runs (a 5-minute scan at 30 fps is --frames 9000).
--chunk N (with --stream, default 1) renders N frames at a time, then processes them one after another: the
renderer's threads then do not run between every two frames (in 300-frame runs on the GPU machine that made the
key frames 10-25 % slower), while the host memory holds only N frames (about 7 MB each at 960x540, with the ground truth).
"memory" lists the resident host memory, the peak device memory and the model size at each quarter of the run:
bounded memory shows as a plateau. --supersampling (default 2) sets the renderer's anti-aliasing; 1 renders about
4x faster. --threads N caps the engine's CPU threads (the oneTBB loops: guided matching, DynamicR1PPnP solves, ...;
default all cores); "cpu_threads" reports the cap.

--soak-frames N processes N frames instead of the scan's own: the rendered scan played forward and back (frames
0, 1, ..., F-1, F-2, ..., 0, 1, ...), so that a long run (108000 frames: an hour of 30 fps video) costs the
rendering of F frames only and the camera never jumps. "memory" then samples the four quarters of the N frames:
host and device memory flat after the first quarter is what a long scan needs. Not with --stream or --out.

--out DIR also writes DIR/model.ply (the fused model), DIR/keyframes.txt (TUM) and the scan's ground truth
DIR/groundtruth/surface.ply (the surface both eyes saw) and DIR/groundtruth/trajectory.txt, for
`tissuemosaic eval` on a machine that has it.)";

struct BenchReconstructOptions {
  int width = 960, height = 540, frames = 60, seed = 1;
  std::optional<int> supersampling, chunk, threads, disparities, soakFrames;
  std::optional<std::string> params, out;
  bool stream = false;
  DisparityRangeOptions range;
  StereoSearchOption search;
  DeviceOption device;
};


/// Named fields of a timing struct (RefinementPartsMs, StereoTimingsMs, ...) and each field's values over the frames
/// added, printed as one JSON object of a statistic per field.
template <class Parts>
struct PartSeries {
  std::vector<std::pair<const char*, double Parts::*>> fields;
  std::vector<std::vector<double>> values = std::vector<std::vector<double>>(fields.size());

  void add(const Parts& parts) {
    for (std::size_t i = 0; i < fields.size(); ++i) values[i].push_back(parts.*fields[i].second);
  }
  template <class Statistic>
  std::string json(Statistic statistic) const {
    std::string json = "{";
    for (std::size_t i = 0; i < fields.size(); ++i) {
      json += cv::format("%s\"%s\": %.4f", i ? ", " : "", fields[i].first, statistic(values[i]));
    }
    return json + "}";
  }
};

/// Host and device memory and the model size after `frame` frames.
struct MemorySample {
  int frame;
  double hostMib, peakDeviceMib;
  std::size_t modelPoints;
};

/// The resident set of this process now (/proc/self/statm), MiB; 0 where that file does not exist.
double residentHostMib() {
  std::FILE* file = std::fopen("/proc/self/statm", "r");
  if (!file) return 0;
  long pages = 0, resident = 0;
  const int read = std::fscanf(file, "%ld %ld", &pages, &resident);
  std::fclose(file);
  return read == 2 ? resident * (sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0)) : 0;
}

/// The bench's range where it holds the true disparities (NaN: no surface) with a margin of 8 px + 10 % of their
/// span; else the same count of candidates centred on them, or, fewer than they need, starting just below them.
void fitBenchRangeToScene(StereoParameters& stereo, const cv::Mat& truePx) {
  double low = INFINITY, high = -INFINITY;
  for (int i = 0; i < truePx.rows * truePx.cols; ++i) {
    const float t = truePx.at<float>(i);
    if (!std::isfinite(t)) continue;
    low = std::min<double>(low, t);
    high = std::max<double>(high, t);
  }
  if (!(low <= high)) return;
  const double margin = 8 + 0.1 * (high - low);
  if (stereo.minDisparityPx <= low - margin && stereo.maxDisparityPx >= high + margin) return;
  const int count = stereo.disparityCount();
  const int start = count >= (high - low) + 2 * margin ? static_cast<int>(std::lround((low + high - (count - 1)) / 2))
                                                       : static_cast<int>(std::floor(low - margin));
  stereo.setFixedDisparityRange(start, start + count - 1);
}

void runBenchReconstruct(const BenchReconstructOptions& settings) {
  synthetic::SyntheticScanOptions options;
  options.width = settings.width;
  options.height = settings.height;
  options.frames = settings.frames;
  options.seed = static_cast<uint32_t>(settings.seed);
  options.supersampling = settings.supersampling.value_or(options.supersampling);
  require(options.frames >= 3, "--frames must be at least 3");
  const bool stream = settings.stream;
  const int chunk = settings.chunk.value_or(1);
  require(chunk >= 1, "--chunk must be at least 1");
  require(stream || !settings.chunk, "--chunk needs --stream");
  const int framesToProcess = settings.soakFrames.value_or(options.frames);
  require(!settings.soakFrames || (*settings.soakFrames >= 1 && !stream && !settings.out),
          "--soak-frames needs a positive count and neither --stream nor --out");
  // The scan frame shown as the k-th processed frame: the scan itself, or played forward and back (--soak-frames).
  const auto scanFrameOf = [&](int k) {
    if (!settings.soakFrames) return k;
    const int period = 2 * options.frames - 2, phase = k % period;
    return phase < options.frames ? phase : period - phase;
  };
  const Device device = settings.device.resolve();
  std::optional<tbb::global_control> threadCap;
  if (settings.threads) {
    require(*settings.threads >= 1, "--threads must be at least 1");
    threadCap.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(*settings.threads));
  }
  ReconstructionParameters parameters;
  if (settings.params) parameters = ReconstructionParameters::readFile(*settings.params);
  applyBenchDisparityRange(parameters.stereo, options.width, settings.disparities, settings.params.has_value());
  settings.range.applyTo(parameters.stereo);
  settings.search.applyTo(parameters.stereo);
  parameters.validate();

  const synthetic::SyntheticScan scan(options);
  std::vector<synthetic::SyntheticScanFrame> rendered;
  if (!stream) {
    for (int k = 0; k < scan.frameCount(); ++k) {
      std::fprintf(stderr, "\rbench reconstruct: rendering frame %d/%d", k + 1, scan.frameCount());
      rendered.push_back(scan.renderFrame(k));
    }
    std::fprintf(stderr, "\n");
  }
  std::vector<MemorySample> memory;
  // The bench's own range (no file, no range option) is moved onto the scene where it cannot hold the first frame's
  // true disparities: at 3840x2160, -80..175 px (256 candidates) missed the scan's 220-298 px and lost 59 of 60 frames.
  const DisparityRangeOptions& asked = settings.range;
  const bool benchRange = !settings.params && !asked.minPx && !asked.maxPx && !asked.range && !asked.depthMm;
  const std::optional<DisparityRange> benchRangeBefore =
      benchRange ? std::optional<DisparityRange>(DisparityRange{parameters.stereo.minDisparityPx,
                                                                parameters.stereo.maxDisparityPx})
                 : std::nullopt;
  if (benchRange) {
    const cv::Mat truth = stream ? scan.renderFrame(0).disparityPx : rendered.front().disparityPx;
    fitBenchRangeToScene(parameters.stereo, truth);
    if (parameters.stereo.minDisparityPx != benchRangeBefore->minPx) {
      std::fprintf(stderr, "bench reconstruct: the range %s does not hold the scene's disparities: searching %d..%d px "
                   "(%d candidates) instead\n", benchRangeBefore->text().c_str(), parameters.stereo.minDisparityPx,
                   parameters.stereo.maxDisparityPx, parameters.stereo.disparityCount());
    }
  }
  int framesBeyondRange = 0;  // frames whose scene outgrew the range (rangeTooNarrowWarning)

  ReconstructionPipeline pipeline(scan.geometry(), parameters, device, scan.T_world_camera(0));
  pipeline.setFrameDisparityKept(false);  // as `reconstruct` runs it; the key frames' maps come down after their timing
  TimingTable timing;
  int lost = 0;
  // The refinement's parts per key frame, by their JSON names (RefinementPartsMs).
  PartSeries<RefinementPartsMs> refinementParts{{{"surface", &RefinementPartsMs::surface},
                                                 {"model_sample", &RefinementPartsMs::modelSample},
                                                 {"icp_selection", &RefinementPartsMs::icpSelection},
                                                 {"key_frame_matching", &RefinementPartsMs::keyFrameMatching},
                                                 {"intermediate_matching", &RefinementPartsMs::intermediateMatching},
                                                 {"solve", &RefinementPartsMs::solve},
                                                 {"matching_call", &RefinementPartsMs::matchingCall},
                                                 {"surface_wait", &RefinementPartsMs::surfaceWait},
                                                 {"solve_call", &RefinementPartsMs::solveCall}}};
  // The stereo and ORB + voting stages' parts over all frames: the host's share (grey, copies) beside the GPU's.
  PartSeries<StereoTimingsMs> stereoParts{{{"grey", &StereoTimingsMs::grey},
                                           {"upload", &StereoTimingsMs::upload},
                                           {"zncc", &StereoTimingsMs::zncc},
                                           {"outliers_holes", &StereoTimingsMs::outliersHoles},
                                           {"refinement", &StereoTimingsMs::refinement},
                                           {"download", &StereoTimingsMs::download}}};
  PartSeries<TrackingPartsMs> trackingParts{{{"extract_and_lift", &TrackingPartsMs::extract},
                                             {"match", &TrackingPartsMs::match},
                                             {"subpixel", &TrackingPartsMs::subPixel},
                                             {"vote", &TrackingPartsMs::vote}}};
  // Each key frame's total and main parts: what the median and the mean of the timing table are made of.
  std::string keyFramesJson;
  // How the refinement matched (RefinementParameters::guidedSearchRadiusPx), summed over the key frames.
  int keyFramesMatched = 0, keyFramesGuided = 0, intermediateFrames = 0, intermediateFramesGuided = 0;
  // Stereo against the truth on the key frames (what fusion receives): the worst share of gross errors (> 3 px).
  double worstKeyFrameGross = 0, keyFrameGrossSum = 0;
  int worstKeyFrame = -1, keyFramesScored = 0;
  // The true disparities of the key frames: whether the range searched held the scene.
  float trueDisparityMin = INFINITY, trueDisparityMax = -INFINITY;
  // The automatic range's measurements (every few frames, beside the frames), and what frames waited for them.
  std::vector<double> rangeMs, rangeWaitMs;
  const double frameIntervalS = scan.timeS(1) - scan.timeS(0);
  for (int k = 0; k < framesToProcess; ++k) {
    if (stream && k % chunk == 0) {  // the next chunk, rendered before any of it is processed
      rendered.clear();
      for (int j = k; j < std::min(k + chunk, scan.frameCount()); ++j) rendered.push_back(scan.renderFrame(j));
    }
    const synthetic::SyntheticScanFrame& frame = rendered[static_cast<std::size_t>(stream ? k % chunk : scanFrameOf(k))];
    if (!settings.soakFrames || k % 100 == 0 || k + 1 == framesToProcess) {
      std::fprintf(stderr, "\rbench reconstruct: frame %d/%d", k + 1, framesToProcess);
    }
    const FrameResult result = pipeline.process(frame.leftRectified, frame.rightRectified, k * frameIntervalS);
    const int quarter = framesToProcess / 4;
    if (k + 1 == framesToProcess || (quarter > 0 && (k + 1) % quarter == 0 && memory.size() < 3)) {
      memory.push_back({k + 1, residentHostMib(), pipeline.peakDeviceBytes() / (1024.0 * 1024.0), pipeline.modelPointCount()});
      const MemorySample& sample = memory.back();
      // Said as it happens too: a long run cut short still tells how its memory went.
      std::fprintf(stderr, "\nbench reconstruct: after %d frames: host resident %.1f MiB, device peak %.1f MiB, %zu model "
                   "points, %zu key frames\n", sample.frame, sample.hostMib, sample.peakDeviceMib, sample.modelPoints,
                   pipeline.keyFrames().size());
    }
    lost += !result.tracked;
    if (const std::string warning = rangeTooNarrowWarning(result.disparityRangeEnds); !warning.empty()) {
      if (framesBeyondRange++ == 0) std::fprintf(stderr, "\nwarning: frame %d: %s\n", k, warning.c_str());
    }
    if (k > 0) {
      stereoParts.add(result.stereoPartsMs);
      if (result.disparityRangeMs > 0) rangeMs.push_back(result.disparityRangeMs);
      rangeWaitMs.push_back(result.disparityRangeWaitMs);
      trackingParts.add(result.trackingPartsMs);
    }
    if (result.keyFrame && k > 0) {
      refinementParts.add(result.refinementPartsMs);
      const RefinementPartsMs& parts = result.refinementPartsMs;
      keyFramesJson += cv::format(
          "%s{\"frame\": %d, \"total_ms\": %.3f, \"matching_call_ms\": %.3f, \"key_frame_matching_ms\": %.3f, "
          "\"solve_call_ms\": %.3f, \"matched_key_frames\": %d, \"guided_key_frames\": %d}",
          keyFramesJson.empty() ? "" : ", ", k, result.timesMs.total, parts.matchingCall,
          parts.keyFrameMatching, parts.solveCall, result.matchedKeyFrames, result.guidedKeyFrames);
      keyFramesMatched += result.matchedKeyFrames;
      keyFramesGuided += result.guidedKeyFrames;
      intermediateFrames += result.intermediateFrames;
      intermediateFramesGuided += result.guidedIntermediateFrames;
    }
    if (result.keyFrame) {
      const cv::Mat disparityPx = pipeline.downloadLastDisparity();
      int gross = 0, estimates = 0;
      for (int y = 0; y < frame.disparityPx.rows; ++y) {
        for (int x = 0; x < frame.disparityPx.cols; ++x) {
          const float estimate = disparityPx.at<float>(y, x), truth = frame.disparityPx.at<float>(y, x);
          if (std::isfinite(truth)) {
            trueDisparityMin = std::min(trueDisparityMin, truth);
            trueDisparityMax = std::max(trueDisparityMax, truth);
          }
          if (!std::isfinite(estimate)) continue;
          ++estimates;
          gross += !std::isfinite(truth) || std::abs(estimate - truth) > 3;
        }
      }
      const double share = estimates ? static_cast<double>(gross) / estimates : 0;
      keyFrameGrossSum += share;
      ++keyFramesScored;
      if (share > worstKeyFrameGross) {
        worstKeyFrameGross = share;
        worstKeyFrame = k;
      }
    }
    if (k > 0) timing.add(result);  // the first frame has nothing to track or refine
  }
  std::fprintf(stderr, "\n");

  double errorSum2 = 0;
  for (const KeyFramePose& k : pipeline.keyFrames()) {
    const Eigen::Matrix4d truth = scan.T_world_camera(scanFrameOf(k.frameIndex));
    errorSum2 += (k.T_world_camera.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).squaredNorm();
  }
  const double keyFrameErrorMm = std::sqrt(errorSum2 / static_cast<double>(std::max<std::size_t>(1, pipeline.keyFrames().size())));
  // The model against the analytic true surface.
  const ModelPoints model = pipeline.modelSnapshot();
  std::vector<double> distances;
  distances.reserve(model.size());
  double distance2 = 0;
  for (const cv::Point3f& p : model.cloud.pointsMm) {
    distances.push_back(scan.surface().distanceMm(p.x, p.y, p.z));
    distance2 += distances.back() * distances.back();
  }
  std::sort(distances.begin(), distances.end());
  const double modelRmseMm = distances.empty() ? 0 : std::sqrt(distance2 / distances.size());
  const double modelP95Mm = distances.empty() ? 0 : distances[static_cast<std::size_t>(0.95 * (distances.size() - 1))];
  const auto shareBeyond = [&](double mm) {
    return distances.empty() ? 0.0
                             : static_cast<double>(distances.end() - std::upper_bound(distances.begin(), distances.end(), mm)) /
                                   distances.size();
  };
  if (settings.out) {
    const std::filesystem::path folder(*settings.out);
    std::filesystem::create_directories(folder / "groundtruth");
    writePly((folder / "model.ply").string(), model.cloud, "TissueMosaic bench reconstruct: world frame of the scan, mm");
    Trajectory keyFrames, truth;
    for (const KeyFramePose& k : pipeline.keyFrames()) {
      TimedPose pose;
      pose.timeS = k.timeS;
      pose.T_world_camera = k.T_world_camera;
      keyFrames.push_back(pose);
    }
    for (int k = 0; k < scan.frameCount(); ++k) {
      TimedPose pose;
      pose.timeS = scan.timeS(k);
      pose.T_world_camera = scan.T_world_camera(k);
      truth.push_back(pose);
    }
    writeTumTrajectory((folder / "keyframes.txt").string(), keyFrames, "key frames, T_world_camera, mm");
    writeTumTrajectory((folder / "groundtruth" / "trajectory.txt").string(), truth, "ground truth, T_world_camera, mm");
    writeMeshPly((folder / "groundtruth" / "surface.ply").string(), scan.seenSurfaceMesh(0.5),
                 "the true surface seen by both eyes, world frame, mm");
  }
  if (profiling::enabled()) {
    std::fprintf(stderr, "%s:\n%s", profiling::reportKind().c_str(), profiling::report().c_str());
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto meanOf = [](const std::vector<double>& values) { return mean(values); };
  const DisparityRangeHistory& ranges = pipeline.disparityRangeHistory();
  const DisparityRange searched =
      ranges.first ? ranges.widest : DisparityRange{parameters.stereo.minDisparityPx, parameters.stereo.maxDisparityPx};
  std::string memoryJson = "[";
  for (std::size_t i = 0; i < memory.size(); ++i) {
    memoryJson += cv::format("%s{\"frame\": %d, \"host_resident_mib\": %.1f, \"peak_device_mib\": %.1f, \"model_points\": %zu}",
                             i ? ", " : "", memory[i].frame, memory[i].hostMib, memory[i].peakDeviceMib,
                             memory[i].modelPoints);
  }
  memoryJson += "]";
  std::printf("{\"command\": \"bench reconstruct\", \"device\": \"%s\", \"device_name\": \"%s\", \"width\": %d, "
              "\"height\": %d, \"frames\": %d, \"lost\": %d, \"frames_beyond_disparity_range\": %d, \"cpu_threads\": %d, \"key_frames\": %zu, "
              "\"model_points\": %zu, \"key_frame_position_rmse_mm\": %.4f, \"model_rmse_mm\": %.4f, \"model_p95_mm\": %.4f, \"peak_host_mib\": %.1f, "
              "\"peak_device_mib\": %.1f, \"disparity_range_px\": [%d, %d], \"disparity_range_moved_to_scene\": %s, "
              "\"key_frame_true_disparity_px\": [%.1f, "
              "%.1f],\n \"model_share_beyond_mm\": {\"1\": %.6f, \"5\": %.6f, \"50\": %.6f}, "
              "\"model_max_mm\": %.2f, \"key_frame_stereo_gross_share\": {\"mean\": %.5f, \"worst\": %.5f, "
              "\"worst_frame\": %d},\n \"memory\": %s,\n \"refinement_parts_median_ms\": %s,\n "
              "\"refinement_parts_max_ms\": %s,\n \"refinement_parts_mean_ms\": %s,\n \"refinement_parts_p99_ms\": %s,\n "
              "\"stereo_parts_median_ms\": %s,\n \"stereo_parts_mean_ms\": %s,\n \"stereo_parts_p99_ms\": %s,\n "
              "\"tracking_parts_median_ms\": %s,\n \"tracking_parts_mean_ms\": %s,\n \"tracking_parts_p99_ms\": %s,\n "
              "\"refinement_matching\": {\"key_frames_matched\": %d, "
              "\"key_frames_guided\": %d, \"intermediate_frames\": %d, \"intermediate_frames_guided\": %d},\n \"key_frame_detail\": [%s],\n \"disparity_range\": %s, \"disparity_range_median_ms\": %.3f, "
              "\"disparity_range_wait_p99_ms\": %.3f,\n \"timing\": %s}\n",
              deviceLabel(device), deviceDescription(device).c_str(), options.width, options.height, framesToProcess,
              lost, framesBeyondRange, cpuThreadCount(), pipeline.keyFrames().size(), model.size(), keyFrameErrorMm, modelRmseMm, modelP95Mm,
              usage.ru_maxrss / 1024.0, pipeline.peakDeviceBytes() / (1024.0 * 1024.0), searched.minPx, searched.maxPx,
              benchRangeBefore && benchRangeBefore->minPx != parameters.stereo.minDisparityPx ? "true" : "false",
              trueDisparityMin, trueDisparityMax, shareBeyond(1), shareBeyond(5),
              shareBeyond(50), distances.empty() ? 0.0 : distances.back(),
              keyFramesScored ? keyFrameGrossSum / keyFramesScored : 0.0, worstKeyFrameGross, worstKeyFrame,
              memoryJson.c_str(), refinementParts.json(median).c_str(), refinementParts.json(largest).c_str(),
              refinementParts.json(meanOf).c_str(), refinementParts.json(percentile99).c_str(),
              stereoParts.json(median).c_str(), stereoParts.json(meanOf).c_str(), stereoParts.json(percentile99).c_str(),
              trackingParts.json(median).c_str(), trackingParts.json(meanOf).c_str(),
              trackingParts.json(percentile99).c_str(),
              keyFramesMatched, keyFramesGuided, intermediateFrames,
              intermediateFramesGuided, keyFramesJson.c_str(),
              disparityRangeJson(pipeline.disparityRangeHistory()).c_str(), median(rangeMs), percentile99(rangeWaitMs),
              timing.toJson().c_str());
}

}  // namespace

void setupBenchReconstruct(CLI::App& bench) {
  auto options = std::make_shared<BenchReconstructOptions>();
  CLI::App* command = addCommand(bench, "reconstruct", "median milliseconds per stage and per key/other frame of the "
                                                      "whole pipeline as JSON", details);
  command->add_option("--out", options->out, "also write the model, key frames and the scan's ground truth here")
      ->type_name("DIR")
      ->group(heading::output);
  addImageSizeOptions(*command, options->width, options->height);
  command->add_option("--frames", options->frames, "frames of the scan (at least 3)")
      ->capture_default_str()
      ->group(heading::options);
  command->add_option("--seed", options->seed, "random scene and path")->capture_default_str()->group(heading::options);
  command->add_flag("--stream", options->stream, "render each frame (or chunk) just before it is processed")
      ->group(heading::options);
  command->add_option("--chunk", options->chunk, "with --stream: frames rendered at a time (default 1)")
      ->group(heading::options);
  command->add_option("--supersampling", options->supersampling, "the renderer's N x N rays per pixel (default 2)")
      ->group(heading::options);
  command->add_option("--soak-frames", options->soakFrames,
                      "process N frames: the scan played forward and back (a long run; see below)")
      ->group(heading::options);
  command->add_option("--threads", options->threads, "cap on the engine's CPU threads (default all cores)")
      ->group(heading::options);
  addBenchDisparitiesOption(*command, options->disparities);
  addDisparityRangeOptions(*command, options->range);
  addStereoSearchOption(*command, options->search);
  addDeviceOption(*command, options->device);
  addParamsOption(*command, options->params, "stereo, features, tracking, refinement, fusion, pipeline");
  command->callback([options] { runBenchReconstruct(*options); });
}

}  // namespace tissuemosaic::cli
