// tissuemosaic bench stereo: milliseconds per section II stage (median, mean, p99) on a synthetic pair,
// and on the CPU OpenCV's StereoSGBM (MODE_SGBM_3WAY) on the same pair and range, in the same run.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/Statistics.h"
#include "Core/Stopwatch.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/DisparityScore.h"
#include "Stereo/StereoMatcher.h"
#include "SyntheticStereoScene.h"
#include "TimingStatistics.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <vector>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Prints one JSON object: the device, the input size and the median, mean and 99th percentile milliseconds per
stage (zncc, outliers_holes, refinement, total; "median_ms", "mean_ms", "p99_ms") over N runs after 2 warm-up runs,
on a synthetic tissue pair seen with the same field of view at every size. On the CPU it also times OpenCV
StereoSGBM (MODE_SGBM_3WAY) on the same pair and disparity range (rounded up to a multiple of 16, as SGBM needs).
--method ad-census times the AD-Census matcher instead; its stages are reported under the same keys (cost and
aggregation as zncc, scanline optimisation and winners as outliers_holes, median and checks as refinement).
"explain" holds the counts of `tissuemosaic stereo --explain` for the pair, from one more, untimed run.
--params p.yml times other stereo parameters (node "stereo", e.g. a wider window at HD); the range stays the
bench's own (--disparities candidates from just below the pair's smallest true disparity), and --method, when given,
overrides the file's. --stereo-search guided times the guided search (docs/STEREO.md) and, in the same run, the
exhaustive one ("exhaustive": its accuracy, cells and total; "guided_keeps_accuracy": density at most 0.002 lower
and bad-1 at most 0.005 higher, issue 51's rule for a default). "cells_scored": the (pixel, disparity) cells ZNCC
scored.)";

struct BenchStereoOptions {
  int width = 960, height = 540, disparities = 100, seed = 7;
  std::optional<int> repeats;
  std::optional<std::string> method, params;
  StereoSearchOption search;
  DeviceOption device;
};

/// The exhaustive search's result, cells and total times on the bench's pair (the guided search's reference).
struct ExhaustiveReference {
  cv::Mat disparity;
  long long cells = 0;
  std::vector<double> totalMs;
};

ExhaustiveReference timeExhaustive(StereoMatcher&& matcher, const synthetic::SyntheticStereoPair& pair, int repeats) {
  ExhaustiveReference reference;
  for (int run = 0; run < repeats + 2; ++run) {
    StereoTimingsMs t;
    reference.disparity = matcher.computeDisparity(pair.leftRectified, pair.rightRectified, &t);
    if (run >= 2) reference.totalMs.push_back(t.total());
  }
  reference.cells = matcher.lastCellsScored();
  return reference;
}

void runBenchStereo(const BenchStereoOptions& settings) {
  synthetic::SyntheticStereoOptions options =
      synthetic::SyntheticStereoOptions::wideDisparity(settings.width, settings.height);
  options.seed = static_cast<uint32_t>(settings.seed);
  const int disparities = settings.disparities;
  const Device device = settings.device.resolve();
  // Read first: a broken file fails before the pair is rendered.
  StereoParameters parameters =
      settings.params ? ReconstructionParameters::readFile(*settings.params).stereo : StereoParameters{};
  const int repeats = settings.repeats.value_or(device == Device::Cuda ? 50 : 10);
  require(repeats >= 1 && repeats <= 10000, "--repeats must be in [1, 10000]");

  std::fprintf(stderr, "bench stereo: rendering a %dx%d synthetic pair...\n", options.width, options.height);
  const synthetic::SyntheticStereoPair pair = synthetic::renderSyntheticStereoPair(options);
  double minTruth = 1e9, maxTruth = -1e9;
  for (int i = 0; i < pair.disparityPx.rows * pair.disparityPx.cols; ++i) {
    const float t = pair.disparityPx.at<float>(i);
    if (!std::isfinite(t)) continue;
    minTruth = std::min<double>(minTruth, t);
    maxTruth = std::max<double>(maxTruth, t);
  }
  require(minTruth < 1e9, "the synthetic pair has no visible surface");

  const int minDisparityPx = static_cast<int>(std::floor(minTruth)) - 2;
  parameters.setFixedDisparityRange(minDisparityPx, minDisparityPx + disparities - 1);
  if (settings.method) parameters.method = parseStereoMethod(*settings.method);
  settings.search.applyTo(parameters);
  StereoMatcher matcher(device, parameters);  // validates the parameters
  // The pair's disparities grow with the width: at 3840x2160 they span more than 256 candidates.
  const bool rangeHoldsTruth = maxTruth <= parameters.maxDisparityPx;
  if (!rangeHoldsTruth) {
    std::fprintf(stderr, "warning: bench stereo: the range %d..%d px does not hold the pair's true disparities "
                 "%.1f..%.1f px (more --disparities)\n", parameters.minDisparityPx, parameters.maxDisparityPx,
                 minTruth, maxTruth);
  }

  // The guided search is judged against the exhaustive one on the same pair, in the same run.
  std::optional<ExhaustiveReference> exhaustive;
  if (parameters.search == StereoSearch::Guided && parameters.method == StereoMethod::Paper) {
    StereoParameters exhaustiveParameters = parameters;
    exhaustiveParameters.search = StereoSearch::Exhaustive;
    exhaustive = timeExhaustive(StereoMatcher(device, exhaustiveParameters), pair, repeats);
  }

  TimingSeries timings({"zncc", "outliers_holes", "refinement", "total", "upload"});
  cv::Mat disparity;
  for (int run = 0; run < repeats + 2; ++run) {
    StereoTimingsMs t;
    disparity = matcher.computeDisparity(pair.leftRectified, pair.rightRectified, &t);
    if (run < 2) continue;
    timings.add("zncc", t.zncc);
    timings.add("outliers_holes", t.outliersHoles);
    timings.add("refinement", t.refinement);
    timings.add("total", t.total());
    timings.add("upload", t.upload);
    std::fprintf(stderr, "\rbench stereo: run %d/%d", run - 1, repeats);
  }
  std::fprintf(stderr, "\n");
  if (profiling::enabled()) {
    std::fprintf(stderr, "%s, over %d runs:\n%s", profiling::reportKind().c_str(), repeats + 2,
                 profiling::report().c_str());
  }
  const DisparityScore ours = scoreDisparity(disparity, pair.disparityPx);
  StereoExplanation explanation;  // an extra run: counting waits between the steps, so it is not timed
  matcher.computeDisparity(pair.leftRectified, pair.rightRectified, nullptr, &explanation);
  const long long cells = matcher.lastCellsScored();

  std::printf("{\"command\": \"bench stereo\", \"device\": \"%s\", \"device_name\": \"%s\", \"width\": %d, "
              "\"height\": %d, \"method\": \"%s\", \"disparities\": %d, \"min_disparity\": %d, \"repeats\": %d, \"cpu_threads\": %d, "
              "\"search\": \"%s\",\n",
              deviceLabel(device), deviceDescription(device).c_str(), options.width, options.height,
              stereoMethodName(parameters.method), disparities, parameters.minDisparityPx, repeats, cpuThreadCount(),
              stereoSearchName(parameters.search));
  std::printf(" %s,\n", timings.json().c_str());
  std::printf(" \"accuracy\": {\"density\": %.4f, \"bad1\": %.4f},\n \"true_disparity_px\": [%.1f, %.1f], "
              "\"range_holds_truth\": %s, \"cells_scored\": %lld,\n \"explain\": %s",
              ours.density, ours.badOver1, minTruth, maxTruth, rangeHoldsTruth ? "true" : "false", cells,
              explanation.json().c_str());
  if (exhaustive) {
    const DisparityScore reference = scoreDisparity(exhaustive->disparity, pair.disparityPx);
    const bool keeps = ours.density >= reference.density - 0.002 && ours.badOver1 <= reference.badOver1 + 0.005;
    std::printf(",\n \"exhaustive\": {\"density\": %.4f, \"bad1\": %.4f, \"cells_scored\": %lld, "
                "\"total_median_ms\": %.4f, \"total_mean_ms\": %.4f},\n \"guided_keeps_accuracy\": %s, "
                "\"guided_over_exhaustive_total\": %.4f",
                reference.density, reference.badOver1, exhaustive->cells, median(exhaustive->totalMs),
                mean(exhaustive->totalMs), keeps ? "true" : "false",
                median(timings.values("total")) / median(exhaustive->totalMs));
  }

  if (device == Device::Cpu) {
    const int sgbmDisparities = (disparities + 15) / 16 * 16;
    const int block = 5;
    cv::Ptr<cv::StereoSGBM> sgbm = cv::StereoSGBM::create(parameters.minDisparityPx, sgbmDisparities, block,
                                                          8 * block * block, 32 * block * block, 1, 63, 10, 100, 2,
                                                          cv::StereoSGBM::MODE_SGBM_3WAY);
    cv::Mat leftGrey, rightGrey, sgbmDisparity;
    cv::cvtColor(pair.leftRectified, leftGrey, cv::COLOR_BGR2GRAY);
    cv::cvtColor(pair.rightRectified, rightGrey, cv::COLOR_BGR2GRAY);
    std::vector<double> sgbmMs;
    for (int run = 0; run < repeats + 2; ++run) {
      const auto start = std::chrono::steady_clock::now();
      sgbm->compute(leftGrey, rightGrey, sgbmDisparity);
      const double ms = millisecondsSince(start);
      if (run >= 2) sgbmMs.push_back(ms);
    }
    cv::Mat sgbmFloat;
    sgbmDisparity.convertTo(sgbmFloat, CV_32F, 1.0 / 16.0);
    sgbmFloat.setTo(NAN, sgbmDisparity < (parameters.minDisparityPx - 1) * 16);
    const DisparityScore theirs = scoreDisparity(sgbmFloat, pair.disparityPx);
    const double oursMs = median(timings.values("total")), sgbmMedian = median(sgbmMs);
    std::printf(",\n \"opencv_sgbm_3way\": {\"median_ms\": %.4f, \"mean_ms\": %.4f, \"p99_ms\": %.4f, "
                "\"num_disparities\": %d, \"block_size\": %d, \"density\": %.4f, \"bad1\": %.4f},\n "
                "\"total_over_sgbm\": %.4f",
                sgbmMedian, mean(sgbmMs), percentile99(sgbmMs), sgbmDisparities, block, theirs.density,
                theirs.badOver1, oursMs / sgbmMedian);
  }
  std::printf("}\n");
}

}  // namespace

void setupBenchStereo(CLI::App& bench) {
  auto options = std::make_shared<BenchStereoOptions>();
  CLI::App* command = addCommand(bench, "stereo", "milliseconds per stereo stage (median, mean, p99) as JSON", details);
  addImageSizeOptions(*command, options->width, options->height);
  command->add_option("--repeats", options->repeats, "timed runs (default 50 on cuda, 10 on cpu)")
      ->group(heading::options);
  command->add_option("--disparities", options->disparities, "disparity range searched")
      ->capture_default_str()
      ->group(heading::options);
  command->add_option("--seed", options->seed, "random scene")->capture_default_str()->group(heading::options);
  command->add_option("--method", options->method, "the matcher (default: the parameters', paper)")
      ->type_name("paper|ad-census")
      ->group(heading::options);
  addStereoSearchOption(*command, options->search);
  addParamsOption(*command, options->params, "stereo");
  addDeviceOption(*command, options->device);
  command->callback([options] { runBenchStereo(*options); });
}

}  // namespace tissuemosaic::cli
