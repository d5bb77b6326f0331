// tissuemosaic bench pnp: R1PPnP and DynamicR1PPnP against OpenCV's solvePnPRansac on synthetic matches.
#include "Arguments.h"
#include "Commands.h"

#include "Core/Error.h"
#include "Tracking/PnpBenchmark.h"

#include <iostream>

namespace tissuemosaic::cli {

namespace {
const char* const help = R"(usage: tissuemosaic bench pnp [--repeats N] [--seed S] [--quick]

Synthetic 3D-2D matches (camera 60-110 mm from a smooth surface, fx = 1000 px, 960x540, 1 px noise on inliers,
outliers = random pixels) with N in {200, 500, 1000} and outlier ratios {0.5, 0.8, 0.9, 0.95}. Runs R1PPnP,
DynamicR1PPnP (two candidate matches per point) and cv::solvePnPRansac (AP3P, 5 px, 100 and 10000 iterations) on
the same scenes, all on one thread (cv::setNumThreads(1)). Prints one JSON object: per method, outlier ratio and N,
the success rate (rotation error < 1 deg, camera-centre error < 2 mm) and the median milliseconds.
  --repeats N   scenes per case (default 40)
  --seed S      base seed (default 1)
  --quick       N = 200 and ratios 0.5, 0.9 only
)";
}  // namespace

int runBenchPnp(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"repeats", "seed", "quick"});
  PnpBenchmarkOptions options;
  options.repeats = arguments.integer("repeats", options.repeats);
  const int seed = arguments.integer("seed", 1);
  if (seed < 0) throw Error("--seed must be a non-negative integer");
  options.seed = static_cast<std::uint64_t>(seed);
  options.quick = arguments.has("quick");
  std::cout << runPnpBenchmark(options) << std::endl;
  return 0;
}

}  // namespace tissuemosaic::cli
