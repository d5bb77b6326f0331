#include "Stereo/PairDisparity.h"

namespace tissuemosaic {

PairDisparity computePairDisparity(const cv::Mat& leftRectified, const cv::Mat& rightRectified,
                                   const StereoParameters& parameters, const RectifiedGeometry& geometry, Device device,
                                   bool explain) {
  DisparityRangeFollower range(parameters, geometry, device);
  StereoMatcher matcher(device, parameters);
  matcher.setDisparityRange(range.beforeFrame(leftRectified, rightRectified));
  PairDisparity result;
  // A pair the first frame found out of rectification is matched with its right view moved onto the left's rows.
  const cv::Mat right = range.alignedRight(rightRectified);
  result.disparityPx = matcher.computeDisparity(leftRectified, right, &result.timings,
                                                explain ? &result.explanation : nullptr);
  result.rangeEnds = matcher.lastRangeEndCounts();
  if (explain) result.cellsScored = matcher.lastCellsScored();
  result.range = range.history();
  result.rangeDescription = range.description();
  return result;
}

}  // namespace tissuemosaic
