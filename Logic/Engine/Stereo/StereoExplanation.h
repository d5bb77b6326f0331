#pragma once
/// @file StereoExplanation.h
/// @brief Why a disparity map is empty where it is: how many pixels each step of one computeDisparity call removed,
/// and how many the hole filling gave back. Counted only when asked for (StereoMatcher::computeDisparity's
/// explanation argument): the counts download intermediate maps, which the normal path never does.
#include <string>

namespace tissuemosaic {

/// Pixel counts of one frame. The removed counts are disjoint and follow the pipeline's order, so
///   estimated = pixels - (outsideRightImage + texturelessWindow + rangeEnd + leftRightCheck + highlight
///                         + outlierSweeps)
///               + filledBack,
/// and notFilled = pixels - the estimates after the last round of hole filling. Steps a method does not have
/// (AD-Census: textureless windows, outlier sweeps, hole filling) count 0.
struct StereoExplanation {
  long pixels = 0;
  long outsideRightImage = 0;  ///< no candidate match inside the right image, or (at the output) the match's
                               ///< matching window leaves it
  long texturelessWindow = 0;  ///< no ZNCC: the left window, or every candidate's right window, is textureless
  long rangeEnd = 0;           ///< winners at (or within rangeEndMarginPx of) an end of the range: the true match
                               ///< most likely lies beyond it
  long leftRightCheck = 0;     ///< winners the right view's winner disagrees with
  long highlight = 0;          ///< estimates on or matched into a specular highlight (HighlightKernels.h)
  long outlierSweeps = 0;      ///< removed by the outlier tests of all rounds (a pixel refilled and removed again
                               ///< counts again, and so does its refilling)
  long filledBack = 0;         ///< given an estimate by the hole filling of all rounds
  long notFilled = 0;          ///< without an estimate after the last round of hole filling
  long estimated = 0;          ///< with an estimate in the output

  long removed() const {
    return outsideRightImage + texturelessWindow + rangeEnd + leftRightCheck + highlight + outlierSweeps;
  }
  /// One JSON object: {"pixels": .., "estimated": .., "density": .., "removed": {"outside_right_image": ..,
  /// "textureless_window": .., "range_end": .., "left_right_check": .., "highlight": .., "outlier_sweeps": ..},
  /// "filled_back": .., "not_filled": ..}.
  std::string json() const;
};

}  // namespace tissuemosaic
