// tissuemosaic bench track: milliseconds per frame (median, mean, p99) of the tracking stages (ORB + voting, DynamicR1PPnP) on
// a synthetic scan rendered in-process, with the stereo depth computed on the same device.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/Statistics.h"
#include "Stereo/StereoMatcher.h"
#include "SyntheticScan.h"
#include "TimingStatistics.h"
#include "Tracking/FrameTracker.h"


#include <algorithm>
#include <cstdio>
#include <iostream>
#include <vector>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Renders a synthetic scan (before timing), computes each frame's disparity on the device, then tracks the frames and
prints one JSON object with the median, mean and 99th percentile milliseconds per tracked frame ("median_ms",
"mean_ms", "p99_ms") of ORB + matching + histogram voting ("orb_voting"), of DynamicR1PPnP ("pnp") and their sum
("tracking"), plus the stereo stage for reference, and "disparity_range_px", the range the stereo searched.)";

struct BenchTrackOptions {
  int width = 960, height = 540, frames = 20, seed = 1;
  std::optional<int> disparities;
  std::optional<std::string> features;
  DeviceOption device;
};

void runBenchTrack(const BenchTrackOptions& settings) {
  synthetic::SyntheticScanOptions options;
  options.width = settings.width;
  options.height = settings.height;
  options.frames = settings.frames;
  options.seed = static_cast<uint32_t>(settings.seed);
  require(options.frames >= 3, "--frames must be at least 3");
  const Device device = settings.device.resolve();
  FrameTrackerOptions trackerOptions;
  const std::string features = settings.features.value_or(device == Device::Cuda ? "tissuemosaic" : "opencv");
  require(features == "opencv" || features == "tissuemosaic", "--features must be opencv or tissuemosaic");
  if (features == "tissuemosaic") {
    trackerOptions.extractor = FeatureExtractor::TissueMosaicOrb;
    trackerOptions.featureDevice = device;
  }

  const synthetic::SyntheticScan scan(options);
  StereoParameters stereoParameters;
  applyBenchDisparityRange(stereoParameters, options.width, settings.disparities, false);
  StereoMatcher matcher(device, stereoParameters);
  FrameTracker tracker(scan.geometry(), trackerOptions, scan.T_world_camera(0));
  TimingSeries stages({"orb_voting", "pnp", "tracking", "stereo"});
  TimingSeries orbVotingParts({"extract_and_lift", "match", "subpixel", "vote"});
  int lost = 0;
  // Rendered before timing (as bench reconstruct does): the renderer's all-core bursts between frames would
  // otherwise cool the caches and the thread pool that tracking's CPU steps use.
  std::vector<synthetic::SyntheticScanFrame> frames;
  for (int k = 0; k < scan.frameCount(); ++k) {
    std::fprintf(stderr, "\rbench track: rendering frame %d/%d", k + 1, scan.frameCount());
    frames.push_back(scan.renderFrame(k));
  }
  std::fprintf(stderr, "\n");
  for (int k = 0; k < scan.frameCount(); ++k) {
    std::fprintf(stderr, "\rbench track: frame %d/%d", k + 1, scan.frameCount());
    const synthetic::SyntheticScanFrame& frame = frames[static_cast<std::size_t>(k)];
    StereoTimingsMs stereoMs;
    matcher.computeDisparity(frame.leftRectified, frame.rightRectified, &stereoMs);
    const cv::Mat disparity = matcher.lastDisparityAwayFromHighlights();
    const TrackResult result = tracker.track(frame.leftRectified, disparity);
    lost += !result.tracked;
    if (k < 2) continue;  // warm-up (and the first frame has nothing to match)
    stages.add("orb_voting", result.timesMs.orbVoting);
    stages.add("pnp", result.timesMs.pnp);
    stages.add("tracking", result.timesMs.orbVoting + result.timesMs.pnp);
    stages.add("stereo", stereoMs.total());
    orbVotingParts.add("extract_and_lift", result.timesMs.extract);
    orbVotingParts.add("match", result.timesMs.match);
    orbVotingParts.add("subpixel", result.timesMs.subPixel);
    orbVotingParts.add("vote", result.timesMs.vote);
  }
  std::fprintf(stderr, "\n");
  if (profiling::enabled()) {
    std::fprintf(stderr, "%s:\n%s", profiling::reportKind().c_str(), profiling::report().c_str());
  }
  std::printf("{\"command\": \"bench track\", \"device\": \"%s\", \"device_name\": \"%s\", \"features\": \"%s\", "
              "\"width\": %d, \"height\": %d, \"frames\": %d, \"lost\": %d, \"cpu_threads\": %d, "
              "\"disparity_range_px\": [%d, %d],\n %s,\n %s}\n",
              deviceLabel(device), deviceDescription(device).c_str(), features.c_str(), options.width, options.height,
              options.frames, lost, cpuThreadCount(), stereoParameters.minDisparityPx, stereoParameters.maxDisparityPx,
              stages.json().c_str(), orbVotingParts.json("orb_voting_parts_").c_str());
}

}  // namespace

void setupBenchTrack(CLI::App& bench) {
  auto options = std::make_shared<BenchTrackOptions>();
  CLI::App* command = addCommand(bench, "track", "milliseconds per frame of ORB + voting and DynamicR1PPnP (median, "
                                                "mean, p99) as JSON", details);
  addImageSizeOptions(*command, options->width, options->height);
  command->add_option("--frames", options->frames, "frames of the scan (at least 3)")
      ->capture_default_str()
      ->group(heading::options);
  command->add_option("--seed", options->seed, "random scene and path")->capture_default_str()->group(heading::options);
  command->add_option("--features", options->features, "ORB implementation (default tissuemosaic on cuda, opencv on "
                                                        "cpu)")
      ->type_name("opencv|tissuemosaic")
      ->group(heading::options);
  addBenchDisparitiesOption(*command, options->disparities);
  addDeviceOption(*command, options->device);
  command->callback([options] { runBenchTrack(*options); });
}

}  // namespace tissuemosaic::cli
