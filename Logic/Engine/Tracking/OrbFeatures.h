#pragma once
/// @file OrbFeatures.h
/// @brief ORB features (FAST-9 corners ranked by Harris response, intensity-centroid orientation, rotated BRIEF
/// with 256 pairs) and a brute-force Hamming matcher, written once for the CPU and CUDA backends
/// (OrbKernels.h, OrbPipeline.inl). Both backends give identical keypoints and descriptors: every step is integer
/// arithmetic, and the few float operations (the rotation of the pattern) are IEEE basic operations that round
/// the same on both (-ffp-contract=off / -fmad=false).
///
/// Selection: per pyramid level, FAST corners that are 3x3 maxima of the FAST score are ranked by Harris
/// response; each grid cell keeps its best maxPerCell (so features spread over the image); of those the level
/// keeps its budget by response, where responses are compared in 1/16-octave bins and the last bin that fits is
/// taken in cell order (a deterministic rule that a GPU computes with a histogram and a stable compaction).
/// The output is sorted by (response desc, level, y, x).
#include "Core/Device.h"

#include <opencv2/core.hpp>
#include <opencv2/core/types.hpp>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace tissuemosaic {

struct OrbParameters {
  int maxFeatures = 2000;    ///< features kept over all levels
  int levels = 2;            ///< pyramid levels (1 = the full image only)
  double scaleFactor = 1.2;  ///< size ratio between adjacent levels
  int fastThreshold = 10;    ///< FAST-9: 9 contiguous circle pixels all brighter or all darker by more than this
  int edgeThresholdPx = 19;  ///< border without features at each level (>= 16: pattern and orientation radius 15)
  int cellSizePx = 24;       ///< grid cell side at each level
  int maxPerCell = 4;        ///< features a cell can contribute (1..8)

  /// Throws Error naming the first parameter out of range.
  void validate() const;
};

struct OrbKeypoint {
  float xPx = 0, yPx = 0;   ///< in the full-resolution image (level coordinates times scale^level)
  float angleDeg = 0;       ///< orientation of the intensity centroid, [0, 360), image axes (x right, y down)
  double response = 0;      ///< Harris response 25 det(M) - trace(M)^2 of 3x3 Sobel gradients over 7x7 (> 0)
  int level = 0;
  int levelX = 0, levelY = 0;  ///< integer position at its level
};

struct OrbFeatures {
  std::vector<OrbKeypoint> keypoints;
  cv::Mat descriptors;  ///< CV_8U, one 32-byte row per keypoint (bit j of byte b: pair 8b + j, I(p) < I(q))
};

/// cv::KeyPoint views of the keypoints (size 31 * scale^level, octave = level), for OpenCV-based code.
std::vector<cv::KeyPoint> toCvKeyPoints(const OrbFeatures& features, double scaleFactor);

/// The given rows of a descriptor matrix (any type), in the given order, as a new matrix. One memcpy a row: with
/// Mat::row().copyTo() a thousand rows took 0.12 ms, paid at every tracked frame.
cv::Mat descriptorRows(const cv::Mat& descriptors, const std::vector<int>& rows);

class OrbExtractor {
public:
  /// Throws Error for invalid parameters, or for Device::Cuda in a build or on a machine without CUDA.
  OrbExtractor(Device device, const OrbParameters& parameters = {});
  ~OrbExtractor();
  OrbExtractor(const OrbExtractor&) = delete;
  OrbExtractor& operator=(const OrbExtractor&) = delete;

  /// Features of an 8-bit grey image (CV_8UC1). Throws Error for other types or an image too small for one cell
  /// inside the border.
  OrbFeatures extract(const cv::Mat& grey);

  Device device() const;
  const OrbParameters& parameters() const;
  /// The 256 test pairs (x1, y1, x2, y2), each point within radius 15 of the keypoint: fixed, generated from a
  /// seeded Gaussian (sigma 31/5, BRIEF's G II) by an integer generator, the same on every machine.
  static const std::vector<int8_t>& pattern();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class HammingMatcher {
public:
  /// Throws Error for Device::Cuda in a build or on a machine without CUDA.
  explicit HammingMatcher(Device device);
  ~HammingMatcher();
  HammingMatcher(const HammingMatcher&) = delete;
  HammingMatcher& operator=(const HammingMatcher&) = delete;

  /// For every row of descriptorsA (CV_8U, 32 bytes a row) its k nearest rows of descriptorsB by Hamming
  /// distance, nearest first, ties by lower index (queryIdx = A row, trainIdx = B row, distance in bits): the same
  /// shape as cv::BFMatcher::knnMatch. Rows have fewer than k matches only when B has fewer than k rows.
  /// 1 <= k <= 8.
  std::vector<std::vector<cv::DMatch>> match(const cv::Mat& descriptorsA, const cv::Mat& descriptorsB, int k = 3);
  /// Several (A, B) pairs at once (one upload, one launch): result[p] equals match(pairs[p].first,
  /// pairs[p].second, k). An empty A or B gives no matches for that pair.
  std::vector<std::vector<std::vector<cv::DMatch>>> matchPairs(const std::vector<std::pair<cv::Mat, cv::Mat>>& pairs,
                                                               int k = 3);

  Device device() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
