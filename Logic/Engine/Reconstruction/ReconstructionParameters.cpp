#include "Reconstruction/ReconstructionParameters.h"

#include "Core/Error.h"

#include <opencv2/core/persistence.hpp>

#include <filesystem>

namespace tissuemosaic {
namespace {

ReconstructionParameters readStorage(const cv::FileStorage& storage) {
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
  p.validate();
  return p;
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
  require(std::filesystem::is_regular_file(path), "cannot open parameters file '" + path + "': file does not exist");
  cv::FileStorage storage;
  try {
    storage.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& error) {
    // error.err, not what(): OpenCV's source file and line mean nothing to a user.
    throw Error("cannot read parameters file '" + path + "': not a valid YAML/XML file (" + error.err + ")");
  }
  require(storage.isOpened(), "cannot read parameters file '" + path + "': not a valid YAML/XML file");
  try {
    return readStorage(storage);
  } catch (const Error& error) {
    throw Error("parameters file '" + path + "': " + error.what());
  } catch (const cv::Exception& error) {
    throw Error("parameters file '" + path + "': a value has the wrong type (" + error.err + ")");
  }
}

ReconstructionParameters ReconstructionParameters::parse(const std::string& yamlText) {
  cv::FileStorage storage;
  try {
    storage.open(yamlText, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& error) {
    throw Error("cannot parse parameters: not valid YAML/XML (" + error.err + ")");
  }
  require(storage.isOpened(), "cannot parse parameters");
  try {
    return readStorage(storage);
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
  storage << "pipeline" << "{" << "extractor"
          << (extractor == FeatureExtractor::OpenCvOrb ? "opencv" : "tissuemosaic") << "}";
  stereo.write(storage);
  features.write(storage);
  tracking.write(storage);
  refinement.write(storage);
  fusion.write(storage);
  agreement.write(storage);
}

}  // namespace tissuemosaic
