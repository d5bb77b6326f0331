// tissuemosaic bench orb: milliseconds (median, mean, p99) of the ORB extractor (FAST-9 + Harris ranking + grid selection +
// orientation + rotated BRIEF, 2000 features) and of the brute-force Hamming matcher (k = 3) on a synthetic scan
// frame pair; on the CPU also OpenCV's cv::ORB and cv::BFMatcher on the same frames, in the same run.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/Stopwatch.h"
#include "SyntheticScan.h"
#include "TimingStatistics.h"
#include "Tracking/OrbFeatures.h"

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <vector>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Prints one JSON object: the device, the input size and the median, mean and 99th percentile milliseconds
("median_ms", "mean_ms", "p99_ms") of extract (one frame, input on the host, keypoints and descriptors back on the
host), match (the two frames' descriptors, k = 3) and extract2_match (two extractions and a match: one tracked
frame's share) over N runs after 2 warm-up runs, on frames 0 and 2 of a synthetic scan. On the CPU it also times OpenCV's ORB (same
features, levels, FAST threshold, Harris score) and BFMatcher::knnMatch on the same frames.)";

struct BenchOrbOptions {
  int width = 960, height = 540, seed = 5, features = 2000, levels = 2;
  std::optional<int> repeats;
  DeviceOption device;
};

/// Times `work` repeats times after 2 warm-up runs into `stage` of `series`.
void time(TimingSeries& series, const std::string& stage, int repeats, const std::function<void()>& work) {
  for (int run = 0; run < repeats + 2; ++run) {
    const auto start = std::chrono::steady_clock::now();
    work();
    const double elapsed = millisecondsSince(start);
    if (run >= 2) series.add(stage, elapsed);
  }
}

void runBenchOrb(const BenchOrbOptions& settings) {
  synthetic::SyntheticScanOptions options;
  options.width = settings.width;
  options.height = settings.height;
  options.seed = static_cast<uint32_t>(settings.seed);
  options.frames = 3;
  const Device device = settings.device.resolve();
  const int repeats = settings.repeats.value_or(device == Device::Cuda ? 100 : 10);
  require(repeats >= 1 && repeats <= 10000, "--repeats must be in [1, 10000]");
  OrbParameters parameters;
  parameters.maxFeatures = settings.features;
  parameters.levels = settings.levels;

  std::fprintf(stderr, "bench orb: rendering a %dx%d synthetic frame pair...\n", options.width, options.height);
  const synthetic::SyntheticScan scan(options);
  cv::Mat greyA, greyB;
  cv::cvtColor(scan.renderFrame(0).leftRectified, greyA, cv::COLOR_BGR2GRAY);
  cv::cvtColor(scan.renderFrame(2).leftRectified, greyB, cv::COLOR_BGR2GRAY);

  OrbExtractor extractor(device, parameters);
  HammingMatcher matcher(device);
  OrbFeatures a, b;
  TimingSeries ours({"extract", "match", "extract2_match"});
  time(ours, "extract", repeats, [&] { a = extractor.extract(greyA); });
  b = extractor.extract(greyB);
  std::vector<std::vector<cv::DMatch>> matches;
  time(ours, "match", repeats, [&] { matches = matcher.match(a.descriptors, b.descriptors, 3); });
  // What tracking one frame costs: two extractions (this frame's and, in the bench, the other) and one match.
  for (std::size_t i = 0; i < ours.values("match").size(); ++i) {
    ours.add("extract2_match", 2 * ours.values("extract")[i] + ours.values("match")[i]);
  }
  if (profiling::enabled()) {
    std::fprintf(stderr, "%s:\n%s", profiling::reportKind().c_str(), profiling::report().c_str());
  }

  std::printf("{\"command\": \"bench orb\", \"device\": \"%s\", \"device_name\": \"%s\", \"width\": %d, \"height\": %d, "
              "\"levels\": %d, \"repeats\": %d, \"cpu_threads\": %d,\n",
              deviceLabel(device), deviceDescription(device).c_str(), options.width, options.height, parameters.levels,
              repeats, cpuThreadCount());
  std::printf(" \"features\": [%zu, %zu], %s", a.keypoints.size(), b.keypoints.size(), ours.json().c_str());
  if (device == Device::Cpu) {
    cv::Ptr<cv::ORB> orb = cv::ORB::create(parameters.maxFeatures, static_cast<float>(parameters.scaleFactor),
                                           parameters.levels, parameters.edgeThresholdPx, 0, 2, cv::ORB::HARRIS_SCORE,
                                           31, parameters.fastThreshold);
    std::vector<cv::KeyPoint> ka, kb;
    cv::Mat da, db;
    TimingSeries theirs({"extract", "match"});
    time(theirs, "extract", repeats, [&] { orb->detectAndCompute(greyA, cv::noArray(), ka, da); });
    orb->detectAndCompute(greyB, cv::noArray(), kb, db);
    cv::BFMatcher bf(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    time(theirs, "match", repeats, [&] { bf.knnMatch(da, db, knn, 3); });
    std::printf(",\n \"opencv\": {\"features\": [%zu, %zu], %s}", ka.size(), kb.size(), theirs.json().c_str());
  }
  std::printf("}\n");
}

}  // namespace

void setupBenchOrb(CLI::App& bench) {
  auto options = std::make_shared<BenchOrbOptions>();
  CLI::App* command = addCommand(bench, "orb", "milliseconds of ORB extraction and Hamming matching (median, mean, p99) as JSON",
                                 details);
  addImageSizeOptions(*command, options->width, options->height);
  command->add_option("--repeats", options->repeats, "timed runs (default 100 on cuda, 10 on cpu)")
      ->group(heading::options);
  command->add_option("--features", options->features, "features per frame")
      ->capture_default_str()
      ->group(heading::options);
  command->add_option("--levels", options->levels, "pyramid levels")->capture_default_str()->group(heading::options);
  command->add_option("--seed", options->seed, "random scene")->capture_default_str()->group(heading::options);
  addDeviceOption(*command, options->device);
  command->callback([options] { runBenchOrb(*options); });
}

}  // namespace tissuemosaic::cli
