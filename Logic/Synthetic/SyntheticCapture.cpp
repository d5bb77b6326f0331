#include "SyntheticCapture.h"

#include <cmath>

namespace tissuemosaic::synthetic {

std::vector<double> exposureOffsetsS(double exposureMs) {
  if (!(exposureMs > 0)) return {0.0};
  const int half = std::max(1, static_cast<int>(std::ceil(0.5 * exposureMs / kMotionBlurStepMs)));
  std::vector<double> offsets;
  for (int k = -half; k <= half; ++k) offsets.push_back(k == 0 ? 0.0 : 1e-3 * exposureMs * k / (2.0 * half));
  return offsets;
}

std::vector<double> fieldOffsetsS(bool interlaced, double fps) {
  if (!interlaced) return {0.0};
  return {0.0, 0.5 / fps};
}

void accumulateField(const cv::Mat& render, int rowParity, cv::Mat& sum) {
  CV_Assert(render.type() == CV_8UC3);
  if (sum.empty()) sum = cv::Mat::zeros(render.size(), CV_32FC3);
  for (int y = 0; y < render.rows; ++y) {
    if (rowParity >= 0 && (y & 1) != rowParity) continue;
    const cv::Vec3b* in = render.ptr<cv::Vec3b>(y);
    cv::Vec3f* out = sum.ptr<cv::Vec3f>(y);
    for (int x = 0; x < render.cols; ++x) out[x] += cv::Vec3f(in[x][0], in[x][1], in[x][2]);
  }
}

cv::Mat averagedImage(const cv::Mat& sum, int count) {
  cv::Mat image;
  // Sums of at most a few dozen 8-bit values are exact in float: an unchanged pixel averages back to itself.
  sum.convertTo(image, CV_8UC3, 1.0 / count);
  return image;
}

}  // namespace tissuemosaic::synthetic
