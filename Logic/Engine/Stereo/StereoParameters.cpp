#include "StereoParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Core/ParameterError.h"
#include "Core/ParameterFileKeys.h"

#include <opencv2/core.hpp>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kStereo{"stereo"};

}  // namespace

const char* stereoMethodName(StereoMethod method) { return method == StereoMethod::AdCensus ? "ad-census" : "paper"; }

StereoMethod parseStereoMethod(const std::string& name) {
  if (name == "paper") return StereoMethod::Paper;
  if (name == "ad-census") return StereoMethod::AdCensus;
  throw Error("unknown stereo method '" + name + "' (choices: paper, ad-census)");
}

const char* stereoSearchName(StereoSearch search) { return search == StereoSearch::Guided ? "guided" : "exhaustive"; }

StereoSearch parseStereoSearch(const std::string& name) {
  if (name == "exhaustive") return StereoSearch::Exhaustive;
  if (name == "guided") return StereoSearch::Guided;
  throw Error("unknown stereo search '" + name + "' (choices: exhaustive, guided)");
}

const char* disparityRangeModeName(DisparityRangeMode mode) {
  switch (mode) {
    case DisparityRangeMode::Fixed: return "fixed";
    case DisparityRangeMode::WorkingDistance: return "working-distance";
    default: return "auto";
  }
}

DisparityRangeMode parseDisparityRangeMode(const std::string& name) {
  if (name == "auto") return DisparityRangeMode::Automatic;
  if (name == "fixed") return DisparityRangeMode::Fixed;
  if (name == "working-distance") return DisparityRangeMode::WorkingDistance;
  throw Error("unknown disparity range mode '" + name + "' (choices: auto, fixed, working-distance)");
}

void StereoParameters::validate() const {
  kStereo.requireRange("minDisparityPx", minDisparityPx, -1000, 1000);
  kStereo.requireRange("maxDisparityPx", maxDisparityPx, -1000, 1000);
  if (maxDisparityPx < minDisparityPx) {
    throw Error("stereo disparity range is inverted: maxDisparityPx (" + std::to_string(maxDisparityPx) +
                ") < minDisparityPx (" + std::to_string(minDisparityPx) + ")");
  }
  kStereo.requireRange("disparityCount", disparityCount(), 2, 1024);
  kStereo.requireRange("workingDistanceNearMm", workingDistanceNearMm, 1.0f, 10000.0f);
  kStereo.requireRange("workingDistanceFarMm", workingDistanceFarMm, 1.0f, 10000.0f);
  if (!(workingDistanceFarMm > workingDistanceNearMm)) {
    throw Error("stereo working distance is inverted or empty: workingDistanceFarMm (" +
                std::to_string(workingDistanceFarMm) + ") <= workingDistanceNearMm (" +
                std::to_string(workingDistanceNearMm) + ")");
  }
  kStereo.requireRange("znccWindowPx", znccWindowPx, 3, 19);  // exact int32 ZNCC up to 19x19
  if (znccWindowPx % 2 == 0) throw Error("stereo parameter znccWindowPx must be odd");
  kStereo.requireRange("minWindowStdDev", minWindowStdDev, 0.0f, 100.0f);
  kStereo.requireRange("leftRightMaxDifferencePx", leftRightMaxDifferencePx, -1, 1000);
  kStereo.requireRange("rangeEndMarginPx", rangeEndMarginPx, -1, 100);
  kStereo.requireRange("refineMaxDeviationPx", refineMaxDeviationPx, -1.0f, 1000.0f);
  kStereo.requireRange("holeMaxEdgeDifferencePx", holeMaxEdgeDifferencePx, -1.0f, 1000.0f);
  kStereo.requireRange("specularMinGrey", specularMinGrey, 1.0f, 256.0f);
  kStereo.requireRange("specularMarginPx", specularMarginPx, 0, 20);
  kStereo.requireRange("specularMaxRadiusPx", specularMaxRadiusPx, 1, 100);
  kStereo.requireRange("specularMinContrastGrey", specularMinContrastGrey, 0.0f, 255.0f);
  kStereo.requireRange("specularViewToleranceGrey", specularViewToleranceGrey, 0.0f, 255.0f);
  kStereo.requireRange("trackingHighlightMarginPx", trackingHighlightMarginPx, 0, 50);
  kStereo.requireRange("outlierIterations", outlierIterations, 0, 10);
  kStereo.requireRange("outlierRadiusStartPx", outlierRadiusStartPx, 1, 200);
  kStereo.requireRange("outlierRadiusStepPx", outlierRadiusStepPx, 0, 200);
  kStereo.requireRange("outlierSmoothnessPx", outlierSmoothnessPx, 0.0f, 100.0f);
  kStereo.requireRange("holeRadialRadiusPx", holeRadialRadiusPx, 0, 500);
  kStereo.requireRange("holeRadialMinLines", holeRadialMinLines, 1, 4);
  kStereo.requireRange("holeDiscRadiusPx", holeDiscRadiusPx, 0, 200);
  kStereo.requireRange("holeDiscMinValidFraction", holeDiscMinValidFraction, 0.0f, 1.0f);
  kStereo.requireRange("refineIterations", refineIterations, 0, 100);
  kStereo.requireRange("refineRadiusPx", refineRadiusPx, 1, 200);
  kStereo.requireRange("refineAlpha", refineAlpha, 0.0f, 1.0f);
  kStereo.requireRange("refineEta", refineEta, 0.0f, 100.0f);
  kStereo.requireRange("refineSearchPx", refineSearchPx, 0, 50);
  kStereo.requireRange("censusWidthPx", censusWidthPx, 1, 15);
  kStereo.requireRange("censusHeightPx", censusHeightPx, 1, 15);
  if (censusWidthPx % 2 == 0 || censusHeightPx % 2 == 0) throw Error("stereo census window sides must be odd");
  if (censusWidthPx * censusHeightPx - 1 > 64) {
    throw Error("stereo census window " + std::to_string(censusWidthPx) + "x" + std::to_string(censusHeightPx) +
                " has more than 64 neighbours");
  }
  kStereo.requireRange("censusLambda", censusLambda, 0.01f, 1000.0f);
  kStereo.requireRange("absoluteDifferenceLambda", absoluteDifferenceLambda, 0.01f, 1000.0f);
  kStereo.requireRange("armMaxPx", armMaxPx, 0, 127);  // windows of at most 255 x 255 pixels: counts fit 16 bits
  kStereo.requireRange("armLongPx", armLongPx, 0, armMaxPx);
  kStereo.requireRange("armLimitGrey", armLimitGrey, 1, 256);
  kStereo.requireRange("armLongLimitGrey", armLongLimitGrey, 1, 256);
  kStereo.requireRange("aggregationIterations", aggregationIterations, 0, 8);
  kStereo.requireRange("pathPenaltySmall", pathPenaltySmall, 0.0f, 100.0f);
  kStereo.requireRange("pathPenaltyLarge", pathPenaltyLarge, pathPenaltySmall, 100.0f);
  kStereo.requireRange("pathEdgeGrey", pathEdgeGrey, 1, 256);
}

void StereoParameters::write(cv::FileStorage& storage) const {
  storage << "stereo" << "{";
  storage << "method" << stereoMethodName(method);
  storage << "search" << stereoSearchName(search);
  storage << "disparityRange" << disparityRangeModeName(disparityRangeMode);
  storage << "minDisparityPx" << minDisparityPx << "maxDisparityPx" << maxDisparityPx;
  storage << "workingDistanceNearMm" << workingDistanceNearMm << "workingDistanceFarMm" << workingDistanceFarMm;
  storage << "znccWindowPx" << znccWindowPx << "minWindowStdDev" << minWindowStdDev;
  storage << "leftRightMaxDifferencePx" << leftRightMaxDifferencePx << "refineMaxDeviationPx" << refineMaxDeviationPx;
  storage << "rangeEndMarginPx" << rangeEndMarginPx << "holeMaxEdgeDifferencePx" << holeMaxEdgeDifferencePx;
  storage << "specularMinGrey" << specularMinGrey << "specularMarginPx" << specularMarginPx;
  storage << "specularMaxRadiusPx" << specularMaxRadiusPx << "specularMinContrastGrey" << specularMinContrastGrey;
  storage << "specularViewToleranceGrey" << specularViewToleranceGrey;
  storage << "trackingHighlightMarginPx" << trackingHighlightMarginPx;
  storage << "outlierIterations" << outlierIterations << "outlierRadiusStartPx" << outlierRadiusStartPx;
  storage << "outlierRadiusStepPx" << outlierRadiusStepPx << "outlierSmoothnessPx" << outlierSmoothnessPx;
  storage << "holeRadialRadiusPx" << holeRadialRadiusPx << "holeRadialMinLines" << holeRadialMinLines;
  storage << "holeDiscRadiusPx" << holeDiscRadiusPx << "holeDiscMinValidFraction" << holeDiscMinValidFraction;
  storage << "refineIterations" << refineIterations << "refineRadiusPx" << refineRadiusPx;
  storage << "refineAlpha" << refineAlpha << "refineEta" << refineEta << "refineSearchPx" << refineSearchPx;
  storage << "censusWidthPx" << censusWidthPx << "censusHeightPx" << censusHeightPx << "censusLambda" << censusLambda;
  storage << "absoluteDifferenceLambda" << absoluteDifferenceLambda << "armMaxPx" << armMaxPx << "armLongPx" << armLongPx;
  storage << "armLimitGrey" << armLimitGrey << "armLongLimitGrey" << armLongLimitGrey;
  storage << "aggregationIterations" << aggregationIterations << "pathPenaltySmall" << pathPenaltySmall;
  storage << "pathPenaltyLarge" << pathPenaltyLarge << "pathEdgeGrey" << pathEdgeGrey;
  storage << "}";
}

StereoParameters StereoParameters::forImageWidth(int widthPx) const {
  StereoParameters scaled = *this;
  if (widthPx <= kHighlightSizesWidthPx) return scaled;
  const auto scale = [widthPx](int px) {
    return static_cast<int>((static_cast<long>(px) * widthPx + kHighlightSizesWidthPx / 2) / kHighlightSizesWidthPx);
  };
  scaled.specularMarginPx = scale(specularMarginPx);
  scaled.specularMaxRadiusPx = scale(specularMaxRadiusPx);
  scaled.trackingHighlightMarginPx = scale(trackingHighlightMarginPx);
  return scaled;
}

StereoParameters StereoParameters::read(const cv::FileNode& node) {
  StereoParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'stereo' parameter node must be a map");
  if (!node["method"].empty()) {
    if (!node["method"].isString()) throw Error("stereo parameter method must be a string (paper or ad-census)");
    p.method = parseStereoMethod(static_cast<std::string>(node["method"]));
  }
  if (!node["search"].empty()) {
    if (!node["search"].isString()) throw Error("stereo parameter search must be a string (exhaustive or guided)");
    p.search = parseStereoSearch(static_cast<std::string>(node["search"]));
  }
  kStereo.readKey(node, "minDisparityPx", p.minDisparityPx);
  kStereo.readKey(node, "maxDisparityPx", p.maxDisparityPx);
  kStereo.readKey(node, "workingDistanceNearMm", p.workingDistanceNearMm);
  kStereo.readKey(node, "workingDistanceFarMm", p.workingDistanceFarMm);
  if (!node["disparityRange"].empty()) {
    if (!node["disparityRange"].isString()) {
      throw Error("stereo parameter disparityRange must be a string (auto, fixed or working-distance)");
    }
    p.disparityRangeMode = parseDisparityRangeMode(static_cast<std::string>(node["disparityRange"]));
  } else if (!node["minDisparityPx"].empty() || !node["maxDisparityPx"].empty()) {
    p.disparityRangeMode = DisparityRangeMode::Fixed;  // a file that gives a range means it
  }
  kStereo.readKey(node, "znccWindowPx", p.znccWindowPx);
  kStereo.readKey(node, "minWindowStdDev", p.minWindowStdDev);
  kStereo.readKey(node, "leftRightMaxDifferencePx", p.leftRightMaxDifferencePx);
  kStereo.readKey(node, "rangeEndMarginPx", p.rangeEndMarginPx);
  kStereo.readKey(node, "refineMaxDeviationPx", p.refineMaxDeviationPx);
  kStereo.readKey(node, "holeMaxEdgeDifferencePx", p.holeMaxEdgeDifferencePx);
  kStereo.readKey(node, "specularMinGrey", p.specularMinGrey);
  kStereo.readKey(node, "specularMarginPx", p.specularMarginPx);
  kStereo.readKey(node, "specularMaxRadiusPx", p.specularMaxRadiusPx);
  kStereo.readKey(node, "specularMinContrastGrey", p.specularMinContrastGrey);
  kStereo.readKey(node, "specularViewToleranceGrey", p.specularViewToleranceGrey);
  kStereo.readKey(node, "trackingHighlightMarginPx", p.trackingHighlightMarginPx);
  kStereo.readKey(node, "outlierIterations", p.outlierIterations);
  kStereo.readKey(node, "outlierRadiusStartPx", p.outlierRadiusStartPx);
  kStereo.readKey(node, "outlierRadiusStepPx", p.outlierRadiusStepPx);
  kStereo.readKey(node, "outlierSmoothnessPx", p.outlierSmoothnessPx);
  kStereo.readKey(node, "holeRadialRadiusPx", p.holeRadialRadiusPx);
  kStereo.readKey(node, "holeRadialMinLines", p.holeRadialMinLines);
  kStereo.readKey(node, "holeDiscRadiusPx", p.holeDiscRadiusPx);
  kStereo.readKey(node, "holeDiscMinValidFraction", p.holeDiscMinValidFraction);
  kStereo.readKey(node, "refineIterations", p.refineIterations);
  kStereo.readKey(node, "refineRadiusPx", p.refineRadiusPx);
  kStereo.readKey(node, "refineAlpha", p.refineAlpha);
  kStereo.readKey(node, "refineEta", p.refineEta);
  kStereo.readKey(node, "refineSearchPx", p.refineSearchPx);
  kStereo.readKey(node, "censusWidthPx", p.censusWidthPx);
  kStereo.readKey(node, "censusHeightPx", p.censusHeightPx);
  kStereo.readKey(node, "censusLambda", p.censusLambda);
  kStereo.readKey(node, "absoluteDifferenceLambda", p.absoluteDifferenceLambda);
  kStereo.readKey(node, "armMaxPx", p.armMaxPx);
  kStereo.readKey(node, "armLongPx", p.armLongPx);
  kStereo.readKey(node, "armLimitGrey", p.armLimitGrey);
  kStereo.readKey(node, "armLongLimitGrey", p.armLongLimitGrey);
  kStereo.readKey(node, "aggregationIterations", p.aggregationIterations);
  kStereo.readKey(node, "pathPenaltySmall", p.pathPenaltySmall);
  kStereo.readKey(node, "pathPenaltyLarge", p.pathPenaltyLarge);
  kStereo.readKey(node, "pathEdgeGrey", p.pathEdgeGrey);
  p.validate();
  return p;
}

StereoParameters StereoParameters::readFile(const std::string& path) {
  const cv::FileStorage storage = parameters::openParameterFile(path);
  try {
    // The stereo node's keys are checked here; a whole pipeline's file is checked by ReconstructionParameters.
    cv::FileStorage known(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    StereoParameters{}.write(known);
    const cv::FileStorage knownRead(known.releaseAndGetString(), cv::FileStorage::READ | cv::FileStorage::MEMORY);
    parameters::requireKnownKeys(storage["stereo"], knownRead["stereo"], "stereo", false);
    return read(storage["stereo"]);
  } catch (const Error& error) {
    throw Error("parameters file '" + path + "': " + error.what());
  } catch (const cv::Exception& error) {
    throw Error("parameters file '" + path + "': a value has the wrong type (" + error.err + ")");
  }
}

void StereoParameters::writeFile(const std::string& path) const {
  cv::FileStorage storage(path, cv::FileStorage::WRITE);
  if (!storage.isOpened()) throw Error("cannot write parameters file '" + path + "'");
  write(storage);
}

void requireDisparityRangeMeetsImage(const StereoParameters& parameters, int widthPx) {
  if (parameters.disparityRangeMode != DisparityRangeMode::Fixed) return;  // the others are measured or derived
  if (parameters.minDisparityPx < widthPx && parameters.maxDisparityPx > -widthPx) return;
  throw ParameterError("disparityRange",
                       cv::format("the disparity range %d..%d px lies beyond the %d-pixel-wide frames: no left pixel "
                                  "can match a right one (set the range within +-%d px)",
                                  parameters.minDisparityPx, parameters.maxDisparityPx, widthPx, widthPx - 1));
}

}  // namespace tissuemosaic
