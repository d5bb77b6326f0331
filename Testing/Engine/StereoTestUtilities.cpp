#include "StereoTestUtilities.h"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <random>

namespace tissuemosaic::test {

bool sameDisparity(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != CV_32F || b.type() != CV_32F) return false;
  for (int y = 0; y < a.rows; ++y) {
    for (int x = 0; x < a.cols; ++x) {
      const float p = a.at<float>(y, x), q = b.at<float>(y, x);
      if (std::memcmp(&p, &q, sizeof p) != 0 && !(std::isnan(p) && std::isnan(q))) return false;
    }
  }
  return true;
}

cv::Mat randomTexture(int width, int height, unsigned seed, double blurSigma) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 255.0f);
  cv::Mat noise(height, width, CV_32F);
  for (int i = 0; i < width * height; ++i) noise.at<float>(i) = uniform(random);
  if (blurSigma > 0) cv::GaussianBlur(noise, noise, cv::Size(0, 0), blurSigma);
  cv::normalize(noise, noise, 10, 245, cv::NORM_MINMAX);
  cv::Mat texture;
  noise.convertTo(texture, CV_8U);
  return texture;
}

cv::Mat shiftedView(const cv::Mat& left, double d0, double gx, double gy) {
  // right(xr, y) = left(xr + d, y) where d is the disparity of the left pixel that lands on xr.
  // For a plane d = d0 + gx * x + gy * y: xl = xr + d0 + gx * xl + gy * y  =>  xl = (xr + d0 + gy * y) / (1 - gx).
  cv::Mat mapX(left.size(), CV_32F), mapY(left.size(), CV_32F);
  for (int y = 0; y < left.rows; ++y) {
    for (int x = 0; x < left.cols; ++x) {
      mapX.at<float>(y, x) = static_cast<float>((x + d0 + gy * y) / (1.0 - gx));
      mapY.at<float>(y, x) = static_cast<float>(y);
    }
  }
  cv::Mat right;
  cv::remap(left, right, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return right;
}

}  // namespace tissuemosaic::test
