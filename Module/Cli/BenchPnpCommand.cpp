// tissuemosaic bench pnp: R1PPnP and DynamicR1PPnP against OpenCV's solvePnPRansac on synthetic matches.
#include "CommonOptions.h"
#include "Commands.h"

#include "Core/Error.h"
#include "Tracking/PnpBenchmark.h"

#include <iostream>

namespace tissuemosaic::cli {

namespace {
const char* const details = R"(Synthetic 3D-2D matches (camera 60-110 mm from a smooth surface, fx = 1000 px, 960x540, 1 px noise on inliers,
outliers = random pixels) with N in {200, 500, 1000} and outlier ratios {0.5, 0.8, 0.9, 0.95}. Runs R1PPnP,
DynamicR1PPnP (two candidate matches per point) and cv::solvePnPRansac (AP3P, 5 px, 100 and 10000 iterations) on
the same scenes, all on one thread (cv::setNumThreads(1)). Prints one JSON object: per method, outlier ratio and N,
the success rate (rotation error < 1 deg, camera-centre error < 2 mm) and the median milliseconds.)";

struct BenchPnpOptions {
  PnpBenchmarkOptions benchmark;
  int seed = 1;
};

void runBenchPnp(BenchPnpOptions options) {
  if (options.seed < 0) throw Error("--seed must be a non-negative integer");
  options.benchmark.seed = static_cast<std::uint64_t>(options.seed);
  std::cout << runPnpBenchmark(options.benchmark) << std::endl;
}

}  // namespace

void setupBenchPnp(CLI::App& bench) {
  auto options = std::make_shared<BenchPnpOptions>();
  CLI::App* command = addCommand(bench, "pnp", "DynamicR1PPnP against OpenCV solvePnPRansac as JSON", details);
  command->add_option("--repeats", options->benchmark.repeats, "scenes per case")
      ->capture_default_str()
      ->group(heading::options);
  command->add_option("--seed", options->seed, "base seed")->capture_default_str()->group(heading::options);
  command->add_flag("--quick", options->benchmark.quick, "N = 200 and ratios 0.5, 0.9 only")->group(heading::options);
  command->callback([options] { runBenchPnp(*options); });
}

}  // namespace tissuemosaic::cli
