// tissuemosaic bench orb: median milliseconds of the ORB extractor (FAST-9 + Harris ranking + grid selection +
// orientation + rotated BRIEF, 2000 features) and of the brute-force Hamming matcher (k = 3) on a synthetic scan
// frame pair; on the CPU also OpenCV's cv::ORB and cv::BFMatcher on the same frames, in the same run.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/Statistics.h"
#include "Core/Stopwatch.h"
#include "SyntheticScan.h"
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

const char* const details = R"(Prints one JSON object: the device, the input size and the median milliseconds of extract (one frame, input on
the host, keypoints and descriptors back on the host) and match (the two frames' descriptors, k = 3) over N runs
after 2 warm-up runs, on frames 0 and 2 of a synthetic scan. On the CPU it also times OpenCV's ORB (same
features, levels, FAST threshold, Harris score) and BFMatcher::knnMatch on the same frames.)";

struct BenchOrbOptions {
  int width = 960, height = 540, seed = 5, features = 2000, levels = 2;
  std::optional<int> repeats;
  DeviceOption device;
};

double medianMs(int repeats, const std::function<void()>& work) {
  std::vector<double> ms;
  for (int run = 0; run < repeats + 2; ++run) {
    const auto start = std::chrono::steady_clock::now();
    work();
    const double elapsed = millisecondsSince(start);
    if (run >= 2) ms.push_back(elapsed);
  }
  return median(ms);
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
  const double extractMs = medianMs(repeats, [&] { a = extractor.extract(greyA); });
  b = extractor.extract(greyB);
  std::vector<std::vector<cv::DMatch>> matches;
  const double matchMs = medianMs(repeats, [&] { matches = matcher.match(a.descriptors, b.descriptors, 3); });
  if (profiling::enabled()) {
    std::fprintf(stderr, "%s:\n%s", profiling::reportKind().c_str(), profiling::report().c_str());
  }

  std::printf("{\"command\": \"bench orb\", \"device\": \"%s\", \"device_name\": \"%s\", \"width\": %d, \"height\": %d, "
              "\"levels\": %d, \"repeats\": %d, \"cpu_threads\": %d,\n",
              deviceLabel(device), deviceDescription(device).c_str(), options.width, options.height, parameters.levels,
              repeats, cpuThreadCount());
  std::printf(" \"features\": [%zu, %zu], \"median_ms\": {\"extract\": %.4f, \"match\": %.4f, \"extract2_match\": %.4f}",
              a.keypoints.size(), b.keypoints.size(), extractMs, matchMs, 2 * extractMs + matchMs);
  if (device == Device::Cpu) {
    cv::Ptr<cv::ORB> orb = cv::ORB::create(parameters.maxFeatures, static_cast<float>(parameters.scaleFactor),
                                           parameters.levels, parameters.edgeThresholdPx, 0, 2, cv::ORB::HARRIS_SCORE,
                                           31, parameters.fastThreshold);
    std::vector<cv::KeyPoint> ka, kb;
    cv::Mat da, db;
    const double orbMs = medianMs(repeats, [&] { orb->detectAndCompute(greyA, cv::noArray(), ka, da); });
    orb->detectAndCompute(greyB, cv::noArray(), kb, db);
    cv::BFMatcher bf(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    const double bfMs = medianMs(repeats, [&] { bf.knnMatch(da, db, knn, 3); });
    std::printf(",\n \"opencv\": {\"features\": [%zu, %zu], \"median_ms\": {\"extract\": %.4f, \"match\": %.4f}}", ka.size(),
                kb.size(), orbMs, bfMs);
  }
  std::printf("}\n");
}

}  // namespace

void setupBenchOrb(CLI::App& bench) {
  auto options = std::make_shared<BenchOrbOptions>();
  CLI::App* command = addCommand(bench, "orb", "median milliseconds of ORB extraction and Hamming matching as JSON",
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
