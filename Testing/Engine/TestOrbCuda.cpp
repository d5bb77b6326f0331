// The CUDA ORB extractor and Hamming matcher against the CPU ones (ctest label "cuda"; skipped with a message
// where no GPU exists). Both run the same integer functors, so keypoints and descriptors must be identical, and
// so must the matches. Inputs are rendered in-process (no image codecs on the GPU machine).
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Tracking/OrbFeatures.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

using namespace tissuemosaic;

namespace {

bool requireCuda() {
  if (cudaAvailable()) return true;
  std::printf("no usable CUDA device: %s\n", cudaUnavailableReason().c_str());
  return false;
}

cv::Mat scanGrey(int width, int height, int frame) {
  synthetic::SyntheticScanOptions options;
  options.width = width;
  options.height = height;
  options.frames = 4;
  options.seed = 5;
  const synthetic::SyntheticScan scan(options);
  cv::Mat grey;
  cv::cvtColor(scan.renderFrame(frame).leftRectified, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

/// Keypoints and descriptors differing between the two backends (0 = identical).
OrbFeatures compareExtractors(const cv::Mat& grey, const OrbParameters& parameters, const char* what) {
  OrbExtractor cpu(Device::Cpu, parameters), gpu(Device::Cuda, parameters);
  const OrbFeatures a = cpu.extract(grey), b = gpu.extract(grey);
  EXPECT_EQ(a.keypoints.size(), b.keypoints.size()) << what;
  long differentKeypoints = 0, differentDescriptors = 0;
  const std::size_t n = std::min(a.keypoints.size(), b.keypoints.size());
  for (std::size_t i = 0; i < n; ++i) {
    const OrbKeypoint &p = a.keypoints[i], &q = b.keypoints[i];
    differentKeypoints += p.level != q.level || p.levelX != q.levelX || p.levelY != q.levelY ||
                          p.response != q.response || p.angleDeg != q.angleDeg || p.xPx != q.xPx || p.yPx != q.yPx;
    const bool differ = cv::norm(a.descriptors.row(static_cast<int>(i)), b.descriptors.row(static_cast<int>(i)),
                                 cv::NORM_HAMMING) != 0;
    if (differ && differentDescriptors < 6) {
      std::printf("  descriptor %zu (level %d, %d, %d, angle %.4f) differs in pairs:", i, p.level, p.levelX, p.levelY,
                  p.angleDeg);
      for (int bit = 0; bit < 256; ++bit) {
        const int x = (a.descriptors.at<uint8_t>(static_cast<int>(i), bit / 8) >> (bit % 8)) & 1;
        const int y = (b.descriptors.at<uint8_t>(static_cast<int>(i), bit / 8) >> (bit % 8)) & 1;
        if (x != y) std::printf(" %d(cpu %d)", bit, x);
      }
      std::printf("\n");
    }
    differentDescriptors += differ;
  }
  std::printf("%s: %zu CPU / %zu CUDA features, %ld keypoints and %ld descriptors differ\n", what, a.keypoints.size(),
              b.keypoints.size(), differentKeypoints, differentDescriptors);
  EXPECT_GT(n, 0u);
  EXPECT_EQ(differentKeypoints, 0) << what;
  EXPECT_EQ(differentDescriptors, 0) << what;
  return a;
}

}  // namespace

TEST(OrbCuda, ExtractsTheSameFeaturesAsTheCpu) {
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  OrbParameters parameters;  // 2000 features, 2 levels
  compareExtractors(scanGrey(960, 540, 0), parameters, "scan frame 960x540, 2 levels");
  parameters.levels = 4;
  parameters.maxFeatures = 3000;
  parameters.fastThreshold = 6;
  parameters.cellSizePx = 17;
  parameters.maxPerCell = 8;
  compareExtractors(scanGrey(641, 359, 1), parameters, "scan frame 641x359, 4 levels, threshold 6, 17 px cells");
  parameters = OrbParameters{};
  parameters.maxFeatures = 100000;  // every candidate: the threshold bin is not reached
  compareExtractors(scanGrey(480, 270, 2), parameters, "scan frame 480x270, every candidate");
  cv::Mat shapes(200, 260, CV_8U, cv::Scalar(120));
  cv::rectangle(shapes, cv::Rect(40, 50, 70, 90), cv::Scalar(220), cv::FILLED);
  cv::circle(shapes, cv::Point(180, 100), 40, cv::Scalar(20), cv::FILLED);
  compareExtractors(shapes, OrbParameters{}, "hand-made shapes 260x200");
}

TEST(OrbCuda, MatchesPairsWithTiesLikeTheCpu) {
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  cv::Mat a(500, 32, CV_8U), b(700, 32, CV_8U);
  cv::randu(a, 0, 256);
  cv::randu(b, 0, 256);
  // Exact duplicates and near copies: equal distances must resolve to the lower index on both backends.
  for (int i = 0; i < 200; ++i) {
    a.row(i).copyTo(b.row(3 * i));
    if (i % 4 == 0) a.row(i).copyTo(b.row(3 * i + 1));
    b.at<uint8_t>(3 * i + 2, i % 32) = a.at<uint8_t>(i, i % 32) ^ 1;
  }
  const std::vector<std::pair<cv::Mat, cv::Mat>> pairs{{a, b}, {b.rowRange(0, 300), a}, {a, b.rowRange(5, 7)}};
  HammingMatcher cpu(Device::Cpu), gpu(Device::Cuda);
  for (int k : {1, 3, 8}) {
    const auto x = cpu.matchPairs(pairs, k), y = gpu.matchPairs(pairs, k);
    long different = 0, compared = 0;
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      ASSERT_EQ(x[p].size(), y[p].size());
      for (std::size_t i = 0; i < x[p].size(); ++i) {
        different += x[p][i].size() != y[p][i].size();
        for (std::size_t j = 0; j < std::min(x[p][i].size(), y[p][i].size()); ++j, ++compared) {
          different += x[p][i][j].trainIdx != y[p][i][j].trainIdx || x[p][i][j].distance != y[p][i][j].distance;
        }
      }
    }
    std::printf("k = %d: %ld matches compared, %ld differ\n", k, compared, different);
    EXPECT_EQ(different, 0);
  }
}

TEST(OrbCuda, MatchesLikeTheCpu) {
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  OrbExtractor extractor(Device::Cpu);
  const OrbFeatures a = extractor.extract(scanGrey(960, 540, 0)), b = extractor.extract(scanGrey(960, 540, 2));
  HammingMatcher cpu(Device::Cpu), gpu(Device::Cuda);
  for (int k : {1, 3, 8}) {
    const auto x = cpu.match(a.descriptors, b.descriptors, k), y = gpu.match(a.descriptors, b.descriptors, k);
    ASSERT_EQ(x.size(), y.size());
    long different = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      different += x[i].size() != y[i].size();
      for (std::size_t j = 0; j < std::min(x[i].size(), y[i].size()); ++j) {
        different += x[i][j].trainIdx != y[i][j].trainIdx || x[i][j].distance != y[i][j].distance;
      }
    }
    std::printf("k = %d: %zu rows, %ld matches differ\n", k, x.size(), different);
    EXPECT_EQ(different, 0);
  }
}

