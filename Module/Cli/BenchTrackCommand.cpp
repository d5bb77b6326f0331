// tissuemosaic bench track: median milliseconds per frame of the tracking stages (ORB + voting, DynamicR1PPnP) on
// a synthetic scan rendered in-process, with the stereo depth computed on the same device.
#include "Arguments.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/Statistics.h"
#include "Stereo/StereoMatcher.h"
#include "SyntheticScan.h"
#include "Tracking/FrameTracker.h"


#include <algorithm>
#include <cstdio>
#include <iostream>
#include <vector>

namespace tissuemosaic::cli {

namespace {

const char* const help = R"(usage: tissuemosaic bench track [--width 960] [--height 540] [--frames 20] [--device cpu|cuda|auto]
                              [--features opencv|tissuemosaic] [--seed S]

Renders a synthetic scan (before timing), computes each frame's disparity on the device, then tracks the frames and prints one JSON
object with the median milliseconds per tracked frame of ORB + matching + histogram voting ("orb_voting"), of
DynamicR1PPnP ("pnp") and their sum ("tracking"), plus the stereo stage for reference. Features default to
TissueMosaic's extractor on CUDA and to OpenCV's on the CPU.
)";


}  // namespace

int runBenchTrack(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"width", "height", "frames", "device", "features", "seed", "help"});
  synthetic::SyntheticScanOptions options;
  options.width = arguments.integer("width", 960);
  options.height = arguments.integer("height", 540);
  options.frames = arguments.integer("frames", 20);
  options.seed = static_cast<uint32_t>(arguments.integer("seed", 1));
  require(options.frames >= 3, "--frames must be at least 3");
  const Device device = parseDevice(arguments.text("device", "auto"));
  FrameTrackerOptions trackerOptions;
  const std::string features = arguments.text("features", device == Device::Cuda ? "tissuemosaic" : "opencv");
  require(features == "opencv" || features == "tissuemosaic", "--features must be opencv or tissuemosaic");
  if (features == "tissuemosaic") {
    trackerOptions.extractor = FeatureExtractor::TissueMosaicOrb;
    trackerOptions.featureDevice = device;
  }

  const synthetic::SyntheticScan scan(options);
  StereoMatcher matcher(device, StereoParameters{});
  FrameTracker tracker(scan.geometry(), trackerOptions, scan.T_world_camera(0));
  std::vector<double> orbVoting, pnp, tracking, stereo, extract, matching, subPixel, voting;
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
    const cv::Mat disparity = matcher.computeDisparity(frame.leftRectified, frame.rightRectified, &stereoMs);
    const TrackResult result = tracker.track(frame.leftRectified, disparity);
    lost += !result.tracked;
    if (k < 2) continue;  // warm-up (and the first frame has nothing to match)
    orbVoting.push_back(result.orbVotingMs);
    pnp.push_back(result.pnpMs);
    extract.push_back(result.extractMs);
    matching.push_back(result.matchMs);
    subPixel.push_back(result.subPixelMs);
    voting.push_back(result.voteMs);
    tracking.push_back(result.orbVotingMs + result.pnpMs);
    stereo.push_back(stereoMs.total());
  }
  std::fprintf(stderr, "\n");
  if (profiling::enabled()) {
    std::fprintf(stderr, "%s:\n%s", profiling::reportKind().c_str(), profiling::report().c_str());
  }
  std::printf("{\"command\": \"bench track\", \"device\": \"%s\", \"device_name\": \"%s\", \"features\": \"%s\", "
              "\"width\": %d, \"height\": %d, \"frames\": %d, \"lost\": %d, \"cpu_threads\": %d,\n"
              " \"median_ms\": {\"orb_voting\": %.4f, \"pnp\": %.4f, \"tracking\": %.4f, \"stereo\": %.4f},\n"
              " \"orb_voting_parts_median_ms\": {\"extract_and_lift\": %.4f, \"match\": %.4f, \"subpixel\": %.4f, "
              "\"vote\": %.4f}}\n",
              deviceLabel(device), deviceDescription(device).c_str(), features.c_str(), options.width, options.height,
              options.frames, lost, cpuThreadCount(), median(orbVoting), median(pnp), median(tracking), median(stereo),
              median(extract), median(matching), median(subPixel), median(voting));
  return 0;
}

}  // namespace tissuemosaic::cli
