// tissuemosaic stereo: the left-view disparity of one stereo pair (section II), optionally depth as a coloured cloud.
#include "Arguments.h"
#include "Commands.h"
#include "Core/Error.h"
#include "Core/StereoRig.h"
#include "IO/DisparityPfm.h"
#include "IO/ImageFile.h"
#include "IO/PointCloudPly.h"
#include "Stereo/DisparityScore.h"
#include "Stereo/StereoMatcher.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace tissuemosaic::cli {

namespace {

const char* const help = R"(usage: tissuemosaic stereo --left L.png --right R.png --out d.pfm [options]

Left-view disparity (PFM, float, NaN where there is no estimate; a left pixel x matches right pixel x - d) by the
paper's section II: ZNCC on an 11x11 chessboard window, iterative outlier removal with hole filling, and the
improved Laplacian refinement. --method ad-census runs AD-Census instead (census + grey-difference cost,
cross-based aggregation, scanline optimisation: sharper at depth edges, see docs/STEREO.md).

  --left, --right PATH       the stereo pair (8-bit PNG/JPEG/...; rectified unless --calib is given)
  --out PATH                 disparity output (.pfm)
  --min-disparity A          smallest candidate disparity in px (default -20)
  --max-disparity B          largest candidate disparity in px, inclusive (default 80)
  --calib rig.yml            OpenCV stereo calibration (K1 D1 K2 D2 R T imageSize): the pair is rectified
                             first, and --cloud becomes available
  --cloud PATH               binary PLY point cloud (mm, left rectified camera frame) with colour
  --method paper|ad-census   the matcher (default paper, or the parameters file's "method")
  --params p.yml             stereo parameters file (node "stereo"); --min/--max-disparity and --method
                             override it
  --device cpu|cuda|auto     where to compute (default auto)
  --ground-truth GT.pfm      print density, bad-1 and bad-2 against a ground-truth disparity (NaN = unknown)
  --rectified-left PATH      also write the rectified left image (with --calib)
  --explain PATH             write JSON: how many pixels each step removed (outside the right image,
                             textureless window, left-right check, highlight, outlier sweeps), how many the hole
                             filling gave back and how many it left unfilled (see docs/STEREO.md)
)";

void writeExplanation(const std::string& path, const StereoExplanation& explanation, const cv::Mat& disparity,
                      const StereoParameters& parameters) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw Error("cannot write '" + path + "'");
  const int written = std::fprintf(file, "{\"command\": \"stereo\", \"width\": %d, \"height\": %d, \"method\": \"%s\", "
                                         "\"min_disparity\": %d, \"max_disparity\": %d,\n \"explain\": %s}\n",
                                   disparity.cols, disparity.rows, stereoMethodName(parameters.method),
                                   parameters.minDisparityPx, parameters.maxDisparityPx, explanation.json().c_str());
  if (std::fclose(file) != 0 || written < 0) throw Error("cannot write '" + path + "'");
}

void printScore(const cv::Mat& disparity, const cv::Mat& truth) {
  const DisparityScore score = scoreDisparity(disparity, truth);
  require(score.evaluated > 0, "the ground truth has no known pixel");
  std::printf("accuracy against ground truth: density %.4f, bad-1 %.4f, bad-2 %.4f, mean abs error %.3f px "
              "(over %ld known pixels)\n",
              score.density, score.badOver1, score.badOver2, score.meanAbsError, score.evaluated);
}

}  // namespace

int runStereo(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"left", "right", "out", "min-disparity", "max-disparity", "calib", "cloud", "params", "device",
                       "method", "ground-truth", "rectified-left", "explain", "help"});
  const std::string leftPath = arguments.required("left");
  const std::string rightPath = arguments.required("right");
  const std::string outPath = arguments.required("out");
  if (arguments.has("cloud") && !arguments.has("calib")) {
    throw Error("--cloud needs --calib: depth needs the rig's focal length and baseline");
  }

  StereoParameters parameters = arguments.has("params") ? StereoParameters::readFile(arguments.required("params"))
                                                        : StereoParameters{};
  parameters.minDisparityPx = arguments.integer("min-disparity", parameters.minDisparityPx);
  parameters.maxDisparityPx = arguments.integer("max-disparity", parameters.maxDisparityPx);
  if (arguments.has("method")) parameters.method = parseStereoMethod(arguments.required("method"));
  parameters.validate();
  const Device device = parseDevice(arguments.text("device", "auto"));

  const ImagePair pair = loadImagePair(leftPath, rightPath);
  cv::Mat left = pair.left, right = pair.right;

  std::unique_ptr<StereoRectifier> rectifier;
  if (arguments.has("calib")) {
    const StereoCalibration calibration = StereoCalibration::read(arguments.required("calib"));
    rectifier = std::make_unique<StereoRectifier>(calibration);
    cv::Mat leftRectified, rightRectified;
    rectifier->rectify(left, right, leftRectified, rightRectified);
    left = leftRectified;
    right = rightRectified;
    if (arguments.has("rectified-left") && !cv::imwrite(arguments.required("rectified-left"), left)) {
      throw Error("cannot write '" + arguments.required("rectified-left") + "'");
    }
  }

  StereoMatcher matcher(device, parameters);
  StereoTimingsMs timings;
  StereoExplanation explanation;
  const bool explain = arguments.has("explain");
  const cv::Mat disparity = matcher.computeDisparity(left, right, &timings, explain ? &explanation : nullptr);
  writePfm(outPath, disparity);
  const int estimated = cv::countNonZero(disparity == disparity);
  std::printf("disparity %dx%d on %s: %d of %d pixels estimated (%.1f%%), written to %s\n", disparity.cols,
              disparity.rows, deviceDescription(device).c_str(), estimated, disparity.rows * disparity.cols,
              100.0 * estimated / (disparity.rows * disparity.cols), outPath.c_str());
  // The timing fields are shared; AD-Census's three stages are named by what they are.
  const bool adCensus = parameters.method == StereoMethod::AdCensus;
  std::printf("time: %s %.2f ms, %s %.2f ms, %s %.2f ms, total %.2f ms\n", adCensus ? "cost+aggregation" : "zncc",
              timings.zncc, adCensus ? "paths+winners" : "outliers+holes", timings.outliersHoles,
              adCensus ? "median+checks" : "refinement", timings.refinement, timings.total());

  if (explain) {
    writeExplanation(arguments.required("explain"), explanation, disparity, parameters);
    std::printf("removed: outside the right image %ld, textureless window %ld, left-right check %ld, highlight %ld, "
                "outlier sweeps %ld; hole filling gave back %ld, left %ld unfilled; written to %s\n",
                explanation.outsideRightImage, explanation.texturelessWindow, explanation.leftRightCheck,
                explanation.highlight, explanation.outlierSweeps, explanation.filledBack, explanation.notFilled,
                arguments.required("explain").c_str());
  }
  if (arguments.has("cloud")) {
    const ColoredPointCloud cloud = disparityToPointCloud(disparity, left, rectifier->geometry());
    writePly(arguments.required("cloud"), cloud, "TissueMosaic stereo cloud, mm, left rectified camera frame");
    std::printf("point cloud: %zu points written to %s\n", cloud.size(), arguments.required("cloud").c_str());
  }
  if (arguments.has("ground-truth")) printScore(disparity, readPfm(arguments.required("ground-truth")));
  return 0;
}

}  // namespace tissuemosaic::cli
