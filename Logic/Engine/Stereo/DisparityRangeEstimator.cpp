#include "Stereo/DisparityRangeEstimator.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Core/PixelFormat.h"
#include "Tracking/LeftRightMatching.h"
#include "Tracking/OrbFeatures.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kEstimator{"disparity range estimator"};

std::vector<float> sortedCopy(std::vector<float> values) {
  std::sort(values.begin(), values.end());
  return values;
}

/// Linear interpolation between the order statistics of sorted values.
double quantile(const std::vector<float>& sorted, double q) {
  if (sorted.empty()) return 0;
  const double position = q * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double a = position - static_cast<double>(below);
  return sorted[below] * (1 - a) + sorted[above] * a;
}

/// Drops the matches no tissue can give before the robust ends are taken: a disparity below the one of a point at
/// infinity (behind the camera). A blurred or dark frame gives far fewer true matches while its wrong ones stay
/// (repeated texture, glints): on real in-vivo frames 3-8 % of 150-200 matches lay at -260..-100 px with the tissue
/// at 22..114 px, more than the 2 % the quantiles pass, and the range followed them to -268 px; others lay near
/// 165 px. On the near side a match is dropped beyond Tukey's far-out fence, nearFenceIqr interquartile ranges above
/// the upper quartile, the range counted at least a quarter of the upper quartile's distance from infinity (a narrow
/// view of flat tissue keeps the nearer parts of its relief).
/// Returns the share of the matches dropped.
double keepPlausibleMatches(std::vector<float>& disparitiesPx, std::vector<cv::Point2f>& pointsPx,
                            const DisparityRangeEstimatorOptions& options) {
  if (disparitiesPx.empty()) return 0;
  const std::size_t given = disparitiesPx.size();
  const double lowest = options.infinityDisparityPx - options.minMarginPx;
  const std::vector<float> sorted = sortedCopy(disparitiesPx);
  const double q1 = quantile(sorted, 0.25), q3 = quantile(sorted, 0.75);
  const double highest = q3 + options.nearFenceIqr * std::max(q3 - q1, 0.25 * (q3 - options.infinityDisparityPx));
  std::size_t kept = 0;
  for (std::size_t i = 0; i < disparitiesPx.size(); ++i) {
    if (!(disparitiesPx[i] >= lowest && disparitiesPx[i] <= highest)) continue;
    disparitiesPx[kept] = disparitiesPx[i];
    if (!pointsPx.empty()) pointsPx[kept] = pointsPx[i];
    ++kept;
  }
  disparitiesPx.resize(kept);
  if (!pointsPx.empty()) pointsPx.resize(kept);
  return 1.0 - static_cast<double>(kept) / static_cast<double>(given);
}

/// d = a + b x + c y: the disparities of a plane in front of a rectified pair.
struct AffineDisparity {
  double a = 0, b = 0, c = 0;
  double residualSigmaPx = 0;  ///< robust standard deviation of the matches it was fitted to, about it
  double at(const cv::Point2f& p) const { return a + b * p.x + c * p.y; }
};

/// The part of the left view that the right view sees too, for disparities about typicalPx.
cv::Rect2d overlap(cv::Size imageSize, double typicalPx) {
  const double x0 = std::clamp(typicalPx, 0.0, imageSize.width - 1.0);
  const double x1 = std::clamp(imageSize.width - 1.0 + typicalPx, 0.0, imageSize.width - 1.0);
  return {x0, 0, x1 - x0, imageSize.height - 1.0};
}

/// A plane fitted to the sample's matches by least squares, twice more without the matches off it by more than
/// max(1.5 px, 3 robust standard deviations). None when the matches do not spread over the view both eyes see (their
/// standard deviation at least an eighth of its width and height: the slopes would be guesses), or too few remain.
std::optional<AffineDisparity> fitAffineDisparity(const DisparitySample& sample, const cv::Rect2d& seen, int minMatches) {
  const std::size_t n = sample.pointsPx.size();
  if (n < static_cast<std::size_t>(std::max(minMatches, 3)) || seen.area() <= 0) return std::nullopt;
  cv::Scalar meanPoint, spread;
  cv::meanStdDev(sample.pointsPx, meanPoint, spread);
  if (spread[0] < seen.width / 8 || spread[1] < seen.height / 8) return std::nullopt;
  std::vector<char> used(n, 1);
  AffineDisparity plane;
  for (int round = 0; round < 3; ++round) {
    cv::Matx33d normal = cv::Matx33d::zeros();
    cv::Vec3d right(0, 0, 0);
    int count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!used[i]) continue;
      const cv::Vec3d row(1, sample.pointsPx[i].x, sample.pointsPx[i].y);
      normal += row * row.t();
      right += row * static_cast<double>(sample.disparitiesPx[i]);
      ++count;
    }
    if (count < std::max(minMatches, 3)) return std::nullopt;
    cv::Vec3d solution;
    if (!cv::solve(normal, right, solution, cv::DECOMP_CHOLESKY)) return std::nullopt;
    plane = {solution[0], solution[1], solution[2]};
    std::vector<float> residuals(n);
    for (std::size_t i = 0; i < n; ++i) residuals[i] = static_cast<float>(sample.disparitiesPx[i] - plane.at(sample.pointsPx[i]));
    std::vector<float> absolute;
    for (std::size_t i = 0; i < n; ++i) {
      if (used[i]) absolute.push_back(std::abs(residuals[i]));
    }
    const double limit = std::max(1.5, 3 * 1.4826 * quantile(sortedCopy(absolute), 0.5));
    for (std::size_t i = 0; i < n; ++i) used[i] = std::abs(residuals[i]) <= limit;
    plane.residualSigmaPx = 1.4826 * quantile(sortedCopy(absolute), 0.5);
  }
  return plane;
}

}  // namespace

void DisparityRangeEstimatorOptions::validate() const {
  kEstimator.requireRange("maxFeatures", maxFeatures, 50, 100000);
  kEstimator.requireRange("fastThreshold", fastThreshold, 1, 254);
  kEstimator.requireRange("weakTextureMatches", weakTextureMatches, 0, 100000);
  kEstimator.requireRange("weakFastThreshold", weakFastThreshold, 1, 254);
  kEstimator.requireRange("saturatedGrey", saturatedGrey, 1, 256);
  kEstimator.requireRange("measureWidthPx", measureWidthPx, 64, 100000);
  kEstimator.requireRange("minMatches", minMatches, 3, 100000);
  kEstimator.requireRange("planeTolerancePx", planeTolerancePx, 0.0, 1000.0);
  kEstimator.requireRange("planeToleranceFraction", planeToleranceFraction, 0.0, 1.0);
  kEstimator.requireRange("lowQuantile", lowQuantile, 0.0, 0.5);
  kEstimator.requireRange("highQuantile", highQuantile, 0.5, 1.0);
  kEstimator.requireRange("marginFraction", marginFraction, 0.0, 10.0);
  kEstimator.requireRange("minMarginPx", minMarginPx, 0.0, 1000.0);
  kEstimator.requireRange("farMarginFraction", farMarginFraction, 0.0, 10.0);
  kEstimator.requireRange("infinityDisparityPx", infinityDisparityPx, -10000.0, 10000.0);
  kEstimator.requireRange("nearFenceIqr", nearFenceIqr, 1.0, 1000.0);
  kEstimator.requireRange("maxImplausibleShare", maxImplausibleShare, 0.0, 1.0);
  kEstimator.requireRange("keepMarginFraction", keepMarginFraction, 0.0, 1.0);
  kEstimator.requireRange("maxWidthFactor", maxWidthFactor, 1.0, 10.0);
  kEstimator.requireRange("maxWidthSlackPx", maxWidthSlackPx, 0.0, 1000.0);
  kEstimator.requireRange("maxSpanGrowth", maxSpanGrowth, 1.0, 1000.0);
  kEstimator.requireRange("sampleEveryFrames", sampleEveryFrames, 1, 30);
  kEstimator.requireRange("rowSearchPx", rowSearchPx, 1.5, 100.0);
  kEstimator.requireRange("maxRowOffsetPx", maxRowOffsetPx, 0.0, 100.0);
}

namespace {

OrbParameters sparseOrbParameters(const DisparityRangeEstimatorOptions& options, int fastThreshold) {
  OrbParameters orb;
  orb.maxFeatures = options.maxFeatures;
  orb.levels = 1;  // pixel-accurate positions
  orb.fastThreshold = fastThreshold;
  return orb;
}

/// Pixels within 5 px of a saturated one: highlights sit on a different surface point in each eye, and their
/// flat insides give identical descriptors anywhere along the row.
cv::Mat saturatedNeighbourhood(const cv::Mat& grey, int saturatedGrey) {
  cv::Mat saturated = grey >= saturatedGrey, near;
  cv::dilate(saturated, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(11, 11)));
  return near;
}

}  // namespace

struct DisparityRangeEstimator::Impl {
  DisparityRangeEstimatorOptions options;
  Device device;
  OrbExtractor extractor;                       ///< fastThreshold
  std::unique_ptr<OrbExtractor> weakExtractor;  ///< weakFastThreshold, made when first needed

  Impl(Device d, const DisparityRangeEstimatorOptions& o)
      : options((o.validate(), o)), device(d), extractor(d, sparseOrbParameters(o, o.fastThreshold)) {}

  /// Margins below and above robust ends lowPx..highPx. Below (the far side) it is capped to farMarginFraction of
  /// the lowest disparity's distance from infinity: a margin of the span's share there would reach depths several
  /// times the farthest tissue (a 30..160 px view would search down to 10 px, 3x as deep), where only outliers lie.
  struct Margins {
    double belowPx, abovePx;
  };
  Margins marginsPx(double lowPx, double highPx) const {
    const double margin = std::max(options.minMarginPx, options.marginFraction * (highPx - lowPx));
    const double farCap = std::max(options.minMarginPx, options.farMarginFraction * (lowPx - options.infinityDisparityPx));
    return {std::min(margin, farCap), margin};
  }
  DisparityRange wanted(double lowPx, double highPx) const {
    const Margins margins = marginsPx(lowPx, highPx);
    return disparityRangeOnGrid(lowPx - margins.belowPx, highPx + margins.abovePx);
  }

  /// Both views' features, with one extractor.
  struct ViewFeatures {
    OrbFeatures left, right;
  };
  /// The kept matches' disparities and left positions.
  struct Matched {
    std::vector<float> disparitiesPx;
    std::vector<float> rowOffsetsPx;  ///< right y - left y, one per disparity
    std::vector<cv::Point2f> pointsPx;
    int leftFeatures = 0, rightFeatures = 0;
  };
  /// Matches along the rows left y + rowOffsetPx (+- rowTolerancePx) of the right view, at the measuring scale.
  Matched match(const ViewFeatures& features, int imageWidth, int borderPx, const cv::Mat& leftSaturated,
                const cv::Mat& rightSaturated, double rowOffsetPx, double rowTolerancePx) const {
    const OrbFeatures &leftFeatures = features.left, &rightFeatures = features.right;
    // What a rectified rig can show at all: up to half the image width either way.
    LeftRightMatchOptions matching;
    matching.minDisparityPx = -0.5 * imageWidth;
    matching.maxDisparityPx = 0.5 * imageWidth;
    matching.rowOffsetPx = rowOffsetPx;
    matching.rowTolerancePx = rowTolerancePx;
    std::vector<LeftRightMatch> matches;
    for (const LeftRightMatch& m : matchLeftRight(leftFeatures, rightFeatures, matching)) {
      const OrbKeypoint &l = leftFeatures.keypoints[m.left], &r = rightFeatures.keypoints[m.right];
      if (!leftSaturated.at<uint8_t>(l.levelY, l.levelX) && !rightSaturated.at<uint8_t>(r.levelY, r.levelX)) {
        matches.push_back(m);
      }
    }
    matches = consistentMatches(matches, leftFeatures);
    // A band of the left view as wide as the disparity (its left band for positive disparities) shows what the
    // right view does not, and the right view has the opposite band: a feature there has no true partner among the
    // other view's features, and its match, if any, is wrong (and biased towards zero). Such matches are dropped,
    // the bands' width taken from the median disparity.
    Matched kept;
    kept.leftFeatures = static_cast<int>(leftFeatures.keypoints.size());
    kept.rightFeatures = static_cast<int>(rightFeatures.keypoints.size());
    for (const LeftRightMatch& m : matches) kept.disparitiesPx.push_back(m.disparityPx);
    const double typicalPx = quantile(sortedCopy(kept.disparitiesPx), 0.5);
    kept.disparitiesPx.clear();
    const auto featured = [&](double x) { return x >= borderPx && x <= imageWidth - 1 - borderPx; };
    for (const LeftRightMatch& m : matches) {
      const OrbKeypoint& keypoint = leftFeatures.keypoints[m.left];
      if (featured(keypoint.xPx - typicalPx) && featured(rightFeatures.keypoints[m.right].xPx + typicalPx)) {
        kept.disparitiesPx.push_back(m.disparityPx);
        kept.rowOffsetsPx.push_back(m.rowOffsetPx);
        kept.pointsPx.emplace_back(keypoint.xPx, keypoint.yPx);
      }
    }
    return kept;
  }

  /// The offset between the views' rows at the measuring scale that the matches found over rowSearchPx either way
  /// suggest: their median, where it is more than maxRowOffsetPx (full-size); else 0. measure() takes it where more
  /// matches come out along the offset rows than along equal ones: a pair whose rows disagree finds few, and mostly
  /// wrong, matches along equal rows, and their disparities spread over the whole image width.
  double suggestedRowOffset(const ViewFeatures& features, int imageWidth, int borderPx, const cv::Mat& leftSaturated,
                            const cv::Mat& rightSaturated, int scale) const {
    const Matched searched = match(features, imageWidth, borderPx, leftSaturated, rightSaturated, 0,
                                   options.rowSearchPx / scale);
    if (static_cast<int>(searched.rowOffsetsPx.size()) < options.minMatches) return 0;
    const double offsetPx = std::round(quantile(sortedCopy(searched.rowOffsetsPx), 0.5));
    return std::abs(offsetPx) * scale <= options.maxRowOffsetPx ? 0 : offsetPx;
  }

  static constexpr double kRowTolerancePx = LeftRightMatchOptions{}.rowTolerancePx;
};

DisparityRangeEstimator::DisparityRangeEstimator(Device device, const DisparityRangeEstimatorOptions& options)
    : impl_(std::make_unique<Impl>(device, options)) {}

DisparityRangeEstimator::~DisparityRangeEstimator() = default;

const DisparityRangeEstimatorOptions& DisparityRangeEstimator::options() const { return impl_->options; }
Device DisparityRangeEstimator::device() const { return impl_->device; }

DisparitySample DisparityRangeEstimator::measure(const cv::Mat& leftRectified, const cv::Mat& rightRectified,
                                                 RowCheck rows) {
  const cv::Mat fullLeft = toGrey8(leftRectified, "disparity range: the left image");
  const cv::Mat fullRight = toGrey8(rightRectified, "disparity range: the right image");
  require(fullLeft.size() == fullRight.size(), "disparity range: the left and right images differ in size");
  Impl& s = *impl_;
  // Wide images are measured at a half (a quarter, ...) of their size: a range needs no pixel-exact disparities, and
  // ORB's cost falls with the square of the scale.
  int scale = 1;
  while (fullLeft.cols / scale > s.options.measureWidthPx) scale *= 2;
  cv::Mat left = fullLeft, right = fullRight;
  if (scale > 1) {
    cv::resize(fullLeft, left, cv::Size(), 1.0 / scale, 1.0 / scale, cv::INTER_AREA);
    cv::resize(fullRight, right, cv::Size(), 1.0 / scale, 1.0 / scale, cv::INTER_AREA);
  }
  const OrbParameters& orb = s.extractor.parameters();
  const int smallest = 2 * orb.edgeThresholdPx + orb.cellSizePx;
  if (left.cols < smallest || left.rows < smallest) return {};  // no room for features: no matches

  const cv::Mat leftSaturated = saturatedNeighbourhood(left, s.options.saturatedGrey);
  const cv::Mat rightSaturated = saturatedNeighbourhood(right, s.options.saturatedGrey);
  const int borderPx = orb.edgeThresholdPx;
  const Impl::ViewFeatures features{s.extractor.extract(left), s.extractor.extract(right)};
  Impl::Matched matched = s.match(features, left.cols, borderPx, leftSaturated, rightSaturated, 0, Impl::kRowTolerancePx);
  double rowOffsetPx = 0;  // at the measuring scale
  if (rows == RowCheck::Measure) {
    const double suggestedPx = s.suggestedRowOffset(features, left.cols, borderPx, leftSaturated, rightSaturated, scale);
    if (suggestedPx != 0) {
      Impl::Matched alongOffset =
          s.match(features, left.cols, borderPx, leftSaturated, rightSaturated, suggestedPx, Impl::kRowTolerancePx);
      if (alongOffset.disparitiesPx.size() > matched.disparitiesPx.size()) {
        matched = std::move(alongOffset);
        rowOffsetPx = suggestedPx;
      }
    }
  }
  if (static_cast<int>(matched.disparitiesPx.size()) < s.options.weakTextureMatches &&
      s.options.weakFastThreshold < s.options.fastThreshold) {
    if (!s.weakExtractor) {
      s.weakExtractor = std::make_unique<OrbExtractor>(s.device, sparseOrbParameters(s.options, s.options.weakFastThreshold));
    }
    const Impl::ViewFeatures weakFeatures{s.weakExtractor->extract(left), s.weakExtractor->extract(right)};
    Impl::Matched weak =
        s.match(weakFeatures, left.cols, borderPx, leftSaturated, rightSaturated, rowOffsetPx, Impl::kRowTolerancePx);
    if (weak.disparitiesPx.size() > matched.disparitiesPx.size()) matched = std::move(weak);
  }
  // Back to full-size pixels (pixel centres: x = (x' + 0.5) scale - 0.5).
  for (float& d : matched.disparitiesPx) d *= static_cast<float>(scale);
  for (cv::Point2f& p : matched.pointsPx) p = (p + cv::Point2f(0.5f, 0.5f)) * static_cast<float>(scale) - cv::Point2f(0.5f, 0.5f);
  DisparitySample measured = sample(std::move(matched.disparitiesPx), matched.leftFeatures, matched.rightFeatures,
                                    std::move(matched.pointsPx), fullLeft.size());
  measured.rowOffsetPx = rowOffsetPx * scale;
  return measured;
}

DisparitySample DisparityRangeEstimator::sample(std::vector<float> disparitiesPx, int leftFeatures, int rightFeatures,
                                                std::vector<cv::Point2f> pointsPx, cv::Size imageSize) const {
  require(pointsPx.empty() || pointsPx.size() == disparitiesPx.size(),
          "disparity range: one point per disparity, or none");
  DisparitySample sample;
  sample.implausibleShare = keepPlausibleMatches(disparitiesPx, pointsPx, impl_->options);
  sample.disparitiesPx = std::move(disparitiesPx);
  sample.pointsPx = std::move(pointsPx);
  sample.leftFeatures = leftFeatures;
  sample.rightFeatures = rightFeatures;
  const std::vector<float> sorted = sortedCopy(sample.disparitiesPx);
  sample.lowPx = quantile(sorted, impl_->options.lowQuantile);
  sample.highPx = quantile(sorted, impl_->options.highQuantile);
  sample.medianPx = quantile(sorted, 0.5);
  const cv::Rect2d seen = overlap(imageSize, sample.medianPx);
  const std::optional<AffineDisparity> plane = fitAffineDisparity(sample, seen, impl_->options.minMatches);
  const double planeTolerancePx = std::max(impl_->options.planeTolerancePx,
                                           impl_->options.planeToleranceFraction * (sample.highPx - sample.lowPx));
  if (plane && plane->residualSigmaPx <= planeTolerancePx) {
    for (const cv::Point2d corner : {seen.tl(), seen.br(), cv::Point2d(seen.x, seen.y + seen.height),
                                     cv::Point2d(seen.x + seen.width, seen.y)}) {
      const double d = plane->at(cv::Point2f(corner));
      sample.lowPx = std::min(sample.lowPx, d);
      sample.highPx = std::max(sample.highPx, d);
    }
  }
  return sample;
}

DisparityRange DisparityRangeEstimator::wantedRange(const DisparitySample& sample) const {
  if (sample.matches() < impl_->options.minMatches) {
    throw DisparityRangeError("cannot choose the disparity range automatically: the stereo pair gave " +
                std::to_string(sample.matches()) + " left-right feature matches (" +
                std::to_string(sample.leftFeatures) + " features left, " + std::to_string(sample.rightFeatures) +
                " right), at least " + std::to_string(impl_->options.minMatches) +
                " are needed. Is the frame dark, blurred or without texture, or the pair not rectified? Give the "
                "disparity range or the working distance instead");
  }
  return impl_->wanted(sample.lowPx, sample.highPx);
}

DisparityRange DisparityRangeEstimator::followingRange(const DisparityRange& current, const DisparitySample& sample,
                                                      const DisparitySample* previous, double predictedMoves) const {
  const DisparityRangeEstimatorOptions& o = impl_->options;
  if (sample.matches() < o.minMatches) return current;  // nothing to go by (smoke, a blurred frame): stay
  if (sample.highPx - sample.lowPx > o.maxSpanGrowth * current.count()) return current;  // not the tissue
  if (sample.implausibleShare > o.maxImplausibleShare) return current;  // random matches: no tissue in view
  // The ends of the frames the range will serve: as far further as the tissue keeps moving by the last of them
  // (never less than this frame's). The median moves with the tissue, while an end can jump with a few wrong matches.
  double low = sample.lowPx, high = sample.highPx;
  if (previous && previous->matches() >= o.minMatches) {
    const double movePx = (sample.medianPx - previous->medianPx) * predictedMoves;
    low += std::min(0.0, movePx);
    high += std::max(0.0, movePx);
  }
  DisparityRange wanted;
  try {
    wanted = impl_->wanted(low, high);
  } catch (const Error&) {
    return current;  // beyond what the matcher takes: not the tissue
  }
  const Impl::Margins margins = impl_->marginsPx(low, high);
  const int widest = std::max(static_cast<int>(o.maxWidthFactor * (high - low) + o.maxWidthSlackPx),
                              wanted.maxPx - wanted.minPx + kDisparityRangeGridPx);
  const bool holds = current.minPx <= low - o.keepMarginFraction * margins.belowPx &&
                     current.maxPx >= high + o.keepMarginFraction * margins.abovePx;
  const bool tooWide = current.maxPx - current.minPx > widest;
  if (holds && !tooWide) return current;
  if (tooWide || current.count() < wanted.count()) return wanted;
  // Wide enough, misplaced: the same count centred over the wanted range, on the grid.
  const int spareSteps = (current.count() - wanted.count()) / kDisparityRangeGridPx;
  DisparityRange moved;
  moved.minPx = wanted.minPx - (spareSteps / 2) * kDisparityRangeGridPx;
  moved.maxPx = moved.minPx + current.count() - 1;
  return moved;
}

}  // namespace tissuemosaic
