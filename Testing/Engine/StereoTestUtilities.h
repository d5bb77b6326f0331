#pragma once
// Helpers shared by the stereo tests: seeded textures, brute-force references, Middlebury loading and scoring.
#include "Stereo/DisparityScore.h"

#include <opencv2/core.hpp>

#include <string>

namespace tissuemosaic::test {

/// Seeded random texture (8-bit grey), blurred so it has the spatial frequencies of a real surface.
cv::Mat randomTexture(int width, int height, unsigned seed, double blurSigma = 1.0);

/// The right view of a fronto-parallel or slanted plane: right(x - d(x, y), y) = left(x, y), rendered by sampling the
/// left texture at x + d with linear interpolation; d = d0 + gx * x + gy * y.
cv::Mat shiftedView(const cv::Mat& left, double d0, double gx = 0, double gy = 0);

/// Whether two CV_32F disparity maps are the same bit for bit, NaN (no estimate) matching NaN.
bool sameDisparity(const cv::Mat& a, const cv::Mat& b);

using tissuemosaic::DisparityScore;
using tissuemosaic::scoreDisparity;

struct MiddleburyScene {
  cv::Mat left, right;     ///< BGR
  cv::Mat groundTruth;     ///< CV_32F disparity, NaN unknown
  cv::Mat nonOccluded;     ///< 8U mask
  int maxDisparity = 0;
};

/// Where the Middlebury scenes are: $TM_MIDDLEBURY_DIR when set, else the configured TM_MIDDLEBURY_DIR
/// (../shared/data/middlebury-v2 by default).
std::string middleburyDirectory();
/// Loads middleburyDirectory()/<name>; returns false when the data is absent.
bool loadMiddlebury(const std::string& name, MiddleburyScene& scene);
/// True where the test data must be there ($TM_REQUIRE_TEST_DATA=1; CI sets it, as CI always has the data):
/// missing data then fails a test instead of skipping it.
bool testDataRequired();

}  // namespace tissuemosaic::test
