#pragma once
/// @file ModelAgreement.h
/// @brief The quality signal of every tracked frame (not in the paper): how well the fused model, seen from the
/// frame's estimated pose, agrees with the frame's own stereo depth. On a sampled grid of pixels (every
/// sampleStridePx-th in x and y) where the frame has a depth within the working range and the model's z-buffer at
/// the pose holds a point: the median absolute depth difference (mm) and the share of those pixels within 1 mm.
/// A wrong pose, tissue that moved, or an instrument in front of the tissue all show as disagreement; new tissue
/// that the model has not seen yet does not (it has no model point) but lowers the overlap.
///
/// PointFusion::measureAgreement computes it on the fusion's device (Fusion/AgreementKernels.h). The parameters
/// here judge it: the traffic light the user sees, and when a frame's pose counts as unsupported (lost).
#include <limits>
#include <string>

namespace cv {
class FileStorage;
class FileNode;
}  // namespace cv

namespace tissuemosaic {

struct ModelAgreement {
  static constexpr double kToleranceMm = 1.0;  ///< the share's tolerance
  bool measured = false;         ///< false: no model, or no sampled pixel where both the frame and the model have depth
  int measuredSamples = 0;       ///< sampled pixels with a stereo depth
  int overlapSamples = 0;        ///< ... of them where the model has a point too
  double medianDepthDifferenceMm = std::numeric_limits<double>::quiet_NaN();
  double shareWithin1mm = std::numeric_limits<double>::quiet_NaN();
  /// Share of the sampled pixels with a stereo depth where the model has a point (0 without depth).
  double overlap() const { return measuredSamples > 0 ? static_cast<double>(overlapSamples) / measuredSamples : 0.0; }
};

/// What the user sees: green, amber, red; None when nothing could be measured.
enum class AgreementLevel { None, Good, Fair, Poor };
const char* agreementLevelName(AgreementLevel level);  ///< "none", "good", "fair", "poor"

struct AgreementParameters {
  int sampleStridePx = 2;         ///< one pixel in stride x stride is compared
  // The traffic light.
  double goodShare = 0.8;         ///< green: at least this share within 1 mm ...
  double goodMedianMm = 0.5;      ///< ... and a median difference at most this
  double poorShare = 0.5;         ///< red: a share below this ...
  double poorMedianMm = 1.5;      ///< ... or a median above this; amber between
  // Loss and relocalisation.
  /// A tracked frame whose agreement collapsed (share below lostShare and median above lostMedianMm, over at least
  /// minOverlap of its depth samples) has an unsupported pose: it is reported lost and not fused.
  double lostShare = 0.1;
  double lostMedianMm = 3.0;
  double minOverlap = 0.05;
  /// A relocalised pose is accepted only where the model agrees this well (share within 1 mm, over at least
  /// minOverlap of the frame's depth samples).
  double relocalisationMinShare = 0.4;

  AgreementLevel level(const ModelAgreement& agreement) const;
  /// True when the agreement says the pose is not supported (see lostShare).
  bool collapsed(const ModelAgreement& agreement) const;
  /// Throws Error naming the first parameter that is out of range.
  void validate() const;
  /// Writes the parameters under the node name "agreement".
  void write(cv::FileStorage& storage) const;
  /// Reads an "agreement" node; missing keys keep their defaults, keys of the wrong type are an error. Validates.
  static AgreementParameters read(const cv::FileNode& agreementNode);
};

}  // namespace tissuemosaic
