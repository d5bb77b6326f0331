// tissuemosaic stereo: the left-view disparity of one stereo pair (section II), optionally depth as a coloured cloud.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "Core/StereoRig.h"
#include "IO/DisparityPfm.h"
#include "IO/ImageFile.h"
#include "IO/PointCloudPly.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/DisparityRangeEstimator.h"
#include "Stereo/DisparityRangeFollower.h"
#include "Stereo/DisparityScore.h"
#include "Stereo/PairDisparity.h"
#include "Stereo/StereoMatcher.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Left-view disparity (PFM, float, NaN where there is no estimate; a left pixel x matches right pixel x - d) by the
paper's section II: ZNCC on an 11x11 chessboard window, iterative outlier removal with hole filling, and the
improved Laplacian refinement. --method ad-census runs AD-Census instead (census + grey-difference cost,
cross-based aggregation, scanline optimisation: sharper at depth edges, see docs/STEREO.md).
The pair is rectified first when --calib is given without --rectified; the geometry (--calib, or --focal-px and
--baseline-mm) also gives --cloud its depth. --params gives the stereo parameters (node "stereo");
--min/--max-disparity, --disparity-range, --depth-range-mm and --method override it. Without a range the disparity
range is chosen from the pair (sparse feature matches, robust ends and a margin) and printed; a pair with too few
matches (dark, blurred, not rectified) is an error, never a silent default.)";

struct StereoOptions {
  std::string left, right, out;
  GeometryOptions geometry;
  std::optional<std::string> cloud, rectifiedLeft, groundTruth, method, params, explain;
  DisparityRangeOptions range;
  StereoSearchOption search;
  DeviceOption device;
};

void writeExplanation(const std::string& path, const StereoExplanation& explanation, const cv::Mat& disparity,
                      const StereoParameters& parameters, long long cellsScored) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw Error("cannot write '" + path + "'");
  const int written = std::fprintf(file, "{\"command\": \"stereo\", \"width\": %d, \"height\": %d, \"method\": \"%s\", "
                                         "\"search\": \"%s\", \"min_disparity\": %d, \"max_disparity\": %d, "
                                         "\"cells_scored\": %lld,\n \"explain\": %s}\n",
                                   disparity.cols, disparity.rows, stereoMethodName(parameters.method),
                                   stereoSearchName(parameters.search), parameters.minDisparityPx,
                                   parameters.maxDisparityPx, cellsScored, explanation.json().c_str());
  if (std::fclose(file) != 0 || written < 0) throw Error("cannot write '" + path + "'");
}

void printScore(const cv::Mat& disparity, const cv::Mat& truth) {
  const DisparityScore score = scoreDisparity(disparity, truth);
  require(score.evaluated > 0, "the ground truth has no known pixel");
  std::printf("accuracy against ground truth: density %.4f, bad-1 %.4f, bad-2 %.4f, mean abs error %.3f px "
              "(over %ld known pixels)\n",
              score.density, score.badOver1, score.badOver2, score.meanAbsError, score.evaluated);
}

void runStereo(const StereoOptions& options) {
  if (options.cloud && !options.geometry.given()) {
    throw UsageError("--cloud needs --calib (or --focal-px and --baseline-mm): depth needs the rig's focal length "
                     "and baseline");
  }
  // Every output is checked before any work: a bad secondary path found after the run would leave --out replaced.
  requireWritableOutput(options.out, "PFM");
  if (options.cloud) requireWritableOutput(*options.cloud, "PLY (--cloud)");
  if (options.rectifiedLeft) requireWritableOutput(*options.rectifiedLeft, "image (--rectified-left)");
  // The whole file is read (and checked strictly), as reconstruct reads it; stereo uses its stereo node.
  StereoParameters parameters =
      options.params ? ReconstructionParameters::readFile(*options.params).stereo : StereoParameters{};
  options.range.applyTo(parameters);
  options.search.applyTo(parameters);
  if (options.method) parameters.method = parseStereoMethod(*options.method);
  parameters.validate();
  const Device device = options.device.resolve();

  const ImagePair pair = loadImagePair(options.left, options.right);
  requireDisparityRangeMeetsImage(parameters, pair.left.cols);
  cv::Mat left = pair.left, right = pair.right;
  std::optional<StereoGeometry> geometry;
  if (options.geometry.given()) {
    geometry = resolveGeometry(options.geometry, left.size(), "--left " + options.left);
    if (geometry->rectifier) {
      cv::Mat leftRectified, rightRectified;
      geometry->rectifier->rectify(left, right, leftRectified, rightRectified);
      left = leftRectified;
      right = rightRectified;
    }
  }
  OutputBatch outputs;  // the disparity, cloud and image replace existing files together, or not at all
  if (options.rectifiedLeft) {
    writeFileAtomically(*options.rectifiedLeft, "image", [&](const std::string& temporaryPath) {
      return cv::imwrite(temporaryPath, left);
    });
  }

  requireGeometryForWorkingDistance(parameters, geometry.has_value());
  PairDisparity pairDisparity;
  try {
    pairDisparity = computePairDisparity(left, right, parameters, geometry ? geometry->rectified : RectifiedGeometry{},
                                         device, options.explain.has_value());
  } catch (const DisparityRangeError& error) {
    rethrowWithRangeOptions(error);
  }
  std::printf("disparity range %s\n", pairDisparity.rangeDescription.c_str());
  const std::string rowWarning = rowOffsetWarning(pairDisparity.range);
  if (!rowWarning.empty()) std::fprintf(stderr, "warning: the stereo pair is %s\n", rowWarning.c_str());
  const std::string rangeWarning = rangeTooNarrowWarning(pairDisparity.rangeEnds);
  if (!rangeWarning.empty()) std::fprintf(stderr, "warning: %s\n", rangeWarning.c_str());
  const cv::Mat& disparity = pairDisparity.disparityPx;
  const StereoTimingsMs& timings = pairDisparity.timings;
  const StereoExplanation& explanation = pairDisparity.explanation;
  writePfm(options.out, disparity);
  const int estimated = cv::countNonZero(disparity == disparity);
  std::printf("disparity %dx%d on %s: %d of %d pixels estimated (%.1f%%), written to %s\n", disparity.cols,
              disparity.rows, deviceDescription(device).c_str(), estimated, disparity.rows * disparity.cols,
              100.0 * estimated / (disparity.rows * disparity.cols), options.out.c_str());
  if (estimated == 0) {
    std::fprintf(stderr, "warning: no pixel has a disparity: the images may be uniform (black, saturated) or "
                         "featureless, or the range %d..%d px misses the scene\n",
                 parameters.minDisparityPx, parameters.maxDisparityPx);
  }
  // The timing fields are shared; AD-Census's three stages are named by what they are.
  const bool adCensus = parameters.method == StereoMethod::AdCensus;
  std::printf("time: %s %.2f ms, %s %.2f ms, %s %.2f ms, total %.2f ms\n", adCensus ? "cost+aggregation" : "zncc",
              timings.zncc, adCensus ? "paths+winners" : "outliers+holes", timings.outliersHoles,
              adCensus ? "median+checks" : "refinement", timings.refinement, timings.total());

  if (options.explain) {
    writeExplanation(*options.explain, explanation, disparity, parameters, pairDisparity.cellsScored);
    std::printf("removed: outside the right image %ld, textureless window %ld, at the range's end %ld, left-right "
                "check %ld, highlight %ld, outlier sweeps %ld; hole filling gave back %ld, left %ld unfilled; written "
                "to %s\n",
                explanation.outsideRightImage, explanation.texturelessWindow, explanation.rangeEnd,
                explanation.leftRightCheck, explanation.highlight, explanation.outlierSweeps, explanation.filledBack,
                explanation.notFilled, options.explain->c_str());
  }
  if (options.cloud) {
    const ColoredPointCloud cloud = disparityToPointCloud(disparity, left, geometry->rectified);
    writePly(*options.cloud, cloud, "TissueMosaic stereo cloud, mm, left rectified camera frame");
    cv::Vec3d sumMm(0, 0, 0);
    for (const cv::Point3f& p : cloud.pointsMm) sumMm += cv::Vec3d(p.x, p.y, p.z);
    const cv::Vec3d centroidMm = cloud.size() > 0 ? sumMm / static_cast<double>(cloud.size()) : sumMm;
    std::printf("point cloud: %zu points, centroid (%.3f, %.3f, %.3f) mm, written to %s\n", cloud.size(),
                centroidMm[0], centroidMm[1], centroidMm[2], options.cloud->c_str());
  }
  outputs.commit();
  if (options.groundTruth) {
    const cv::Mat truth = readPfm(*options.groundTruth);
    require(truth.channels() == 1, "--ground-truth '" + *options.groundTruth + "' is a colour PFM ('PF', " +
                                       std::to_string(truth.channels()) +
                                       " channels): a disparity map has one channel ('Pf')");
    require(truth.size() == disparity.size(),
            "--ground-truth '" + *options.groundTruth + "' is " + std::to_string(truth.cols) + "x" +
                std::to_string(truth.rows) + " but the disparity is " + std::to_string(disparity.cols) + "x" +
                std::to_string(disparity.rows));
    printScore(disparity, truth);
  }
}

}  // namespace

void setupStereo(CLI::App& tool) {
  auto options = std::make_shared<StereoOptions>();
  CLI::App* command = addCommand(tool, "stereo", "left-view disparity of one stereo pair, optionally a coloured cloud",
                                 details);
  command->add_option("--left", options->left, "left image (8-bit PNG/JPEG/...)")->required()->type_name("L.png")->group(heading::input);
  command->add_option("--right", options->right, "right image, same size")->required()->type_name("R.png")->group(heading::input);
  addGeometryOptions(*command, options->geometry);
  command->add_option("--out", options->out, "disparity output (.pfm)")->required()->type_name("d.pfm")->group(heading::output);
  command->add_option("--cloud", options->cloud, "binary PLY point cloud with colour (mm, left rectified camera "
                                                 "frame; needs the geometry)")
      ->type_name("cloud.ply")
      ->group(heading::output);
  command->add_option("--rectified-left", options->rectifiedLeft, "also write the (rectified) left image")
      ->type_name("L.png")
      ->group(heading::output);
  command->add_option("--method", options->method, "the matcher (default paper, or the parameters file's method)")
      ->type_name("paper|ad-census")
      ->group(heading::options);
  command->add_option("--ground-truth", options->groundTruth,
                      "print density, bad-1 and bad-2 against a ground-truth disparity (PFM, NaN = unknown)")
      ->type_name("GT.pfm")
      ->group(heading::options);
  command->add_option("--explain", options->explain,
                      "write JSON: how many pixels each step removed (outside the right image, textureless window, "
                      "at the range's end, left-right check, highlight, outlier sweeps), how many the hole filling "
                      "gave back and how many it left unfilled (docs/STEREO.md)")
      ->type_name("explain.json")
      ->group(heading::output);
  addDisparityRangeOptions(*command, options->range);
  addStereoSearchOption(*command, options->search);
  addDeviceOption(*command, options->device, "where to compute");
  addParamsOption(*command, options->params, "stereo");
  command->callback([options] { runStereo(*options); });
}

}  // namespace tissuemosaic::cli
