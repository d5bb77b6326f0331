#pragma once
/// @file ReconstructionParameters.h
/// @brief The one parameter object of the whole reconstruction (paper sections II-III): stereo, features and
/// tracking, key-frame refinement and fusion. The command line, the parameter files, the logic and the GUI panel
/// all edit this object; each stage's struct stays the single source of its own defaults.
#include "Core/Device.h"
#include "Fusion/FusionParameters.h"
#include "Fusion/ModelAgreement.h"
#include "Refinement/RefinementParameters.h"
#include "Stereo/StereoParameters.h"
#include "Tracking/FrameTracker.h"
#include "Tracking/StereoFeatures.h"
#include "Tracking/TrackingParameters.h"

#include <string>

namespace tissuemosaic {

struct ReconstructionParameters {
  StereoParameters stereo;
  FeatureParameters features;
  TrackingParameters tracking;
  RefinementParameters refinement;
  FusionParameters fusion;
  AgreementParameters agreement;  ///< the quality signal's sampling, traffic light and loss thresholds
  FeatureExtractor extractor = FeatureExtractor::TissueMosaicOrb;  ///< runs on the pipeline's device

  /// Throws Error naming the first parameter that is out of range.
  void validate() const;
  /// Parameter files are OpenCV YAML/XML with one node per stage ("stereo", "features", "tracking", "refinement",
  /// "fusion", "agreement") and "pipeline" (extractor: "opencv" | "tissuemosaic"); missing nodes and keys keep their defaults, and the result is validated.
  static ReconstructionParameters readFile(const std::string& path);
  /// Reads the same format from text in memory (e.g. a preset in a Qt resource).
  static ReconstructionParameters parse(const std::string& yamlText);
  void writeFile(const std::string& path) const;
};

}  // namespace tissuemosaic
