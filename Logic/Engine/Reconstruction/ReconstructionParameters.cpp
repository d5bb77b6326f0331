#include "Reconstruction/ReconstructionParameters.h"

#include "Core/Error.h"
#include "Core/ParameterFileKeys.h"

#include <opencv2/core/persistence.hpp>

#include <filesystem>

namespace tissuemosaic {
namespace {

void writeAll(const ReconstructionParameters& p, cv::FileStorage& storage) {
  storage << "pipeline" << "{" << "extractor"
          << (p.extractor == FeatureExtractor::OpenCvOrb ? "opencv" : "tissuemosaic") << "}";
  p.stereo.write(storage);
  p.features.write(storage);
  p.tracking.write(storage);
  p.refinement.write(storage);
  p.fusion.write(storage);
  p.agreement.write(storage);
}

/// Every node and key a parameters file may hold: the defaults as writeFile() writes them.
const cv::FileStorage& knownLayout() {
  static const cv::FileStorage known = [] {
    cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    writeAll(ReconstructionParameters{}, out);
    return cv::FileStorage(out.releaseAndGetString(), cv::FileStorage::READ | cv::FileStorage::MEMORY);
  }();
  return known;
}

ReconstructionParameters readStorage(const cv::FileStorage& storage) {
  parameters::requireKnownKeys(storage.root(), knownLayout().root(), "", true);
  ReconstructionParameters p;
  p.stereo = StereoParameters::read(storage["stereo"]);
  p.features = FeatureParameters::read(storage["features"]);
  p.tracking = TrackingParameters::read(storage["tracking"]);
  p.refinement = RefinementParameters::read(storage["refinement"]);
  p.fusion = FusionParameters::read(storage["fusion"]);
  p.agreement = AgreementParameters::read(storage["agreement"]);
  const cv::FileNode extractor = storage["pipeline"]["extractor"];
  if (!extractor.empty()) {
    const std::string name = extractor.isString() ? static_cast<std::string>(extractor) : std::string();
    if (name == "opencv") p.extractor = FeatureExtractor::OpenCvOrb;
    else if (name == "tissuemosaic") p.extractor = FeatureExtractor::TissueMosaicOrb;
    else throw Error("pipeline parameter extractor must be \"opencv\" or \"tissuemosaic\"");
  }
  return p;  // each stage's read() validated its part: checked once, where it is set
}

}  // namespace

void ReconstructionParameters::validate() const {
  stereo.validate();
  features.validate();
  tracking.validate();
  refinement.validate();
  fusion.validate();
  agreement.validate();
}

ReconstructionParameters ReconstructionParameters::readFile(const std::string& path) {
  const cv::FileStorage storage = parameters::openParameterFile(path);
  try {
    return readStorage(storage);
  } catch (const Error& error) {
    throw Error("parameters file '" + path + "': " + error.what());
  } catch (const cv::Exception& error) {
    throw Error("parameters file '" + path + "': a value has the wrong type (" + error.err + ")");
  }
}

ReconstructionParameters ReconstructionParameters::parse(const std::string& yamlText) {
  const cv::FileStorage storage =
      parameters::openParameterText(yamlText, "cannot parse parameters: ", "not valid YAML/XML");
  try {
    return readStorage(storage);
  } catch (const Error& error) {
    throw Error(std::string("cannot parse parameters: ") + error.what());
  } catch (const cv::Exception& error) {
    throw Error("cannot parse parameters: a value has the wrong type (" + error.err + ")");
  }
}

void ReconstructionParameters::writeFile(const std::string& path) const {
  cv::FileStorage storage;
  try {
    storage.open(path, cv::FileStorage::WRITE);
  } catch (const cv::Exception& error) {
    throw Error("cannot write parameters file '" + path + "': " + error.err);
  }
  require(storage.isOpened(), "cannot write parameters file '" + path + "'");
  writeAll(*this, storage);
}

}  // namespace tissuemosaic
