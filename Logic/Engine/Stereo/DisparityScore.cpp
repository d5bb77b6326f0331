#include "DisparityScore.h"

#include "Core/Error.h"

#include <cmath>

namespace tissuemosaic {

DisparityScore scoreDisparity(const cv::Mat& estimate, const cv::Mat& groundTruth, const cv::Mat& mask) {
  require(estimate.type() == CV_32F && groundTruth.type() == CV_32F, "disparity scoring needs CV_32F maps");
  require(estimate.size() == groundTruth.size(), "the ground truth's size differs from the disparity's");
  require(mask.empty() || (mask.type() == CV_8U && mask.size() == estimate.size()),
          "the evaluation mask must be 8-bit and of the disparity's size");
  DisparityScore score;
  long bad1 = 0, bad2 = 0;
  double absSum = 0;
  for (int y = 0; y < estimate.rows; ++y) {
    const float* value = estimate.ptr<float>(y);
    const float* truth = groundTruth.ptr<float>(y);
    const uchar* inside = mask.empty() ? nullptr : mask.ptr<uchar>(y);
    for (int x = 0; x < estimate.cols; ++x) {
      if ((inside && !inside[x]) || !std::isfinite(truth[x])) continue;
      ++score.evaluated;
      if (!std::isfinite(value[x])) continue;
      ++score.estimated;
      const double error = std::abs(value[x] - truth[x]);
      absSum += error;
      bad1 += error > 1.0;
      bad2 += error > 2.0;
    }
  }
  if (score.evaluated) score.density = static_cast<double>(score.estimated) / score.evaluated;
  if (score.estimated) {
    score.badOver1 = static_cast<double>(bad1) / score.estimated;
    score.badOver2 = static_cast<double>(bad2) / score.estimated;
    score.meanAbsError = absSum / score.estimated;
  }
  return score;
}

}  // namespace tissuemosaic
