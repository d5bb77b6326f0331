#pragma once
/// @file StereoMatcher.h
/// @brief Section II of the paper as one call: ZNCC matching, iterative outlier removal with hole filling, and
/// the improved Laplacian refinement, on the CPU or on a CUDA GPU.
#include "Core/Device.h"
#include "Core/Image.h"
#include "Stereo/DisparityRange.h"
#include "StereoExplanation.h"
#include "StereoParameters.h"

#include <opencv2/core.hpp>

#include <memory>
#include <string>
#include <vector>

namespace tissuemosaic {

/// Milliseconds spent in each stage of one computeDisparity call (device work waited for at each stage end).
struct StereoTimingsMs {
  double grey = 0;           ///< host: colour to 8-bit grey of both images
  double upload = 0;         ///< host to device copy of the grey pair (CUDA: queuing it; it runs beside the conversion)
  // The three stages of the paper's method; under AD-Census (StereoParameters::method) they hold its three stages:
  // census, arms, cost and aggregation; scanline optimisation and winners; median and checks.
  double zncc = 0;           ///< window statistics, cost volume, best ZNCC disparity
  double outliersHoles = 0;  ///< outlier removal alternating with both hole fillings
  double refinement = 0;     ///< improved Laplacian smoothing with o_i re-selection
  double download = 0;       ///< device to host copy of the result
  double total() const { return zncc + outliersHoles + refinement; }
};

/// How many of a frame's best ZNCC (or AD-Census) matches lie on the range's end candidates: where the scene's
/// disparities reach beyond the range, the cost is still improving at its end and the winners pile up there.
struct RangeEndCounts {
  DisparityRange range;
  long withWinner = 0;  ///< left pixels with a best match
  long atMin = 0;       ///< ... on the range's first candidate
  long atMax = 0;       ///< ... on its last one
};

/// A frame whose winners lie this often (of those with one) on an end of the range is said to have outgrown it
/// (StereoRangeEnds tests: 1-2 % on a range that holds a random texture, 57 % on one 8 px short of it).
constexpr double kRangeEndWarningShare = 0.05;
/// Empty when the range holds the frame; else one sentence with both ends' shares, which way the scene lies where one
/// end alone is over the share, and what to do.
std::string rangeTooNarrowWarning(const RangeEndCounts& counts);

class StereoMatcher {
public:
  /// Validates the parameters (throws Error). Device::Cuda throws Error when CUDA cannot be used.
  StereoMatcher(Device device, const StereoParameters& parameters);
  ~StereoMatcher();
  StereoMatcher(const StereoMatcher&) = delete;
  StereoMatcher& operator=(const StereoMatcher&) = delete;

  /// Left-view disparity (CV_32F, NaN where there is no estimate; left x matches right x - d) of a rectified
  /// pair of equal size, 8-bit grey or BGR. Throws Error on empty or mismatched images. explanation (optional):
  /// filled with how many pixels each step removed and filling gave back; counting downloads intermediate maps, so
  /// the stage timings of such a call include those waits.
  cv::Mat computeDisparity(const cv::Mat& leftRectified, const cv::Mat& rightRectified,
                           StereoTimingsMs* timings = nullptr, StereoExplanation* explanation = nullptr);
  /// computeDisparity without the download: the result stays where it was computed (lastDisparity(),
  /// lastDisparityAwayFromHighlightsView()), for callers that read it there or take only part of it to the host
  /// (8 MB a frame at 1920x1080). timings->download is 0.
  void match(const cv::Mat& leftRectified, const cv::Mat& rightRectified, StereoTimingsMs* timings = nullptr,
             StereoExplanation* explanation = nullptr);
  /// A host copy (CV_32F) of the last call's disparity: what computeDisparity returned. Throws Error before the first call.
  cv::Mat downloadLastDisparity() const;

  /// The last call's winners on the range's ends (a download of three counts per image row).
  RangeEndCounts lastRangeEndCounts() const;

  /// (pixel, disparity) cells the last call scored for ZNCC: pixels x range count under the exhaustive search,
  /// fewer under the guided one (StereoParameters::search; it downloads the candidate windows).
  long long lastCellsScored() const;

  /// Intermediate results of the last call, for tests and the GUI: integer ZNCC winners (NaN where none),
  /// and the discrete disparities after outlier removal and hole filling.
  cv::Mat lastZnccDisparity() const;
  cv::Mat lastFilledDisparity() const;
  /// The last computeDisparity result where it was computed (device memory on CUDA, host memory on the CPU), until
  /// the next call: per-frame steps on the same device read it there instead of uploading the returned Mat again.
  /// A thread other than the one that computed it may read it once that call has returned (it synchronises).
  /// Throws Error before the first call.
  ImageView<const float> lastDisparity() const;

  /// CV_8U of the last call: 1 within trackingHighlightMarginPx (a square) of a left-image highlight seed
  /// (HighlightKernels.h), 0 elsewhere and everywhere with highlight removal off. The disparity there is the
  /// surrounding tissue's, but a highlight slides over the tissue as the camera moves: tracking and fusion leave
  /// these pixels out (lastDisparityAwayFromHighlights).
  cv::Mat lastHighlightNeighbourhood() const;
  /// CV_32F of the last call: its disparity with NaN wherever lastHighlightNeighbourhood() is 1, the disparity that
  /// tracking lifts its features with and that fusion takes its points from. Made by the matcher's device, so that
  /// one map comes down instead of the mask and a copy masked on the host.
  cv::Mat lastDisparityAwayFromHighlights() const;
  /// The same map where it was computed (device memory on CUDA), valid as lastDisparity() is: what fusion's surface
  /// measurement reads without an upload.
  ImageView<const float> lastDisparityAwayFromHighlightsView() const;
  /// That map at sub-pixel points of the left image (DisparitySampling.h's rule; NaN: none), sampled where it lies:
  /// on CUDA the points go up and the samples come down (8 KB each way for 1000 features, not the 2-8 MB map).
  std::vector<float> sampleLastDisparityAwayFromHighlights(const std::vector<cv::Point2f>& pointsPx) const;

  /// Matches later pairs over this range (between frames: never while computeDisparity runs). Throws Error for a
  /// range StereoParameters refuses. A range of the same count keeps the workspace (the cost volumes); another count
  /// replaces it at the next call, as a new image size does. Cheap when the range is unchanged.
  void setDisparityRange(const DisparityRange& range);
  DisparityRange disparityRange() const;

  Device device() const;
  const StereoParameters& parameters() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
