#include "StereoParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Core/ParameterError.h"
#include "Core/ParameterFileKeys.h"
#include "Stereo/StereoParameterTable.h"

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
  stereoParameterTable().requireInRange(*this);
  // The rules between fields.
  if (maxDisparityPx < minDisparityPx) {
    throw Error("stereo disparity range is inverted: maxDisparityPx (" + std::to_string(maxDisparityPx) +
                ") < minDisparityPx (" + std::to_string(minDisparityPx) + ")");
  }
  kStereo.requireRange("disparityCount", disparityCount(), 2, kMaxDisparityCount);
  if (!(workingDistanceFarMm > workingDistanceNearMm)) {
    throw Error("stereo working distance is inverted or empty: workingDistanceFarMm (" +
                std::to_string(workingDistanceFarMm) + ") <= workingDistanceNearMm (" +
                std::to_string(workingDistanceNearMm) + ")");
  }
  if (znccWindowPx % 2 == 0) throw Error("stereo parameter znccWindowPx must be odd");
  if (censusWidthPx % 2 == 0 || censusHeightPx % 2 == 0) throw Error("stereo census window sides must be odd");
  if (censusWidthPx * censusHeightPx - 1 > 64) {
    throw Error("stereo census window " + std::to_string(censusWidthPx) + "x" + std::to_string(censusHeightPx) +
                " has more than 64 neighbours");
  }
  kStereo.requireRange("armLongPx", armLongPx, 0, armMaxPx);
  kStereo.requireRange("pathPenaltyLarge", pathPenaltyLarge, pathPenaltySmall, 100.0f);
}

void StereoParameters::write(cv::FileStorage& storage) const { stereoParameterTable().write(*this, storage); }

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
  stereoParameterTable().read(node, p);
  if (!node.empty() && node["disparityRange"].empty() &&
      (!node["minDisparityPx"].empty() || !node["maxDisparityPx"].empty())) {
    p.disparityRangeMode = DisparityRangeMode::Fixed;  // a file that gives a range means it
  }
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
