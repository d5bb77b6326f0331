#include "Stereo/DisparityRangeFollower.h"

#include "Core/Error.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

namespace tissuemosaic {

struct DisparityRangeFollower::Impl {
  StereoParameters parameters;
  std::unique_ptr<DisparityRangeEstimator> estimator;  ///< Automatic only
  DisparityRangeHistory history;
  std::optional<DisparityRange> next;  ///< decided after a frame, used from the next beforeFrame on
  DisparitySample previous;            ///< the last frame's sample: how the tissue moves

  void use(const DisparityRange& range) {
    if (!history.first) {
      history.first = range;
      history.widest = range;
    } else if (range != *history.current) {
      ++history.changes;
    }
    history.current = range;
    history.widest.minPx = std::min(history.widest.minPx, range.minPx);
    history.widest.maxPx = std::max(history.widest.maxPx, range.maxPx);
  }
};

DisparityRangeFollower::DisparityRangeFollower(const StereoParameters& parameters, const RectifiedGeometry& geometry,
                                               Device device)
    : impl_(std::make_unique<Impl>()) {
  parameters.validate();
  impl_->parameters = parameters;
  impl_->history.mode = parameters.disparityRangeMode;
  if (const std::optional<DisparityRange> requested = requestedDisparityRange(parameters, &geometry)) {
    impl_->use(*requested);
  } else {
    DisparityRangeEstimatorOptions options;
    options.infinityDisparityPx = -geometry.doffsPx;
    impl_->estimator = std::make_unique<DisparityRangeEstimator>(device, options);
  }
}

DisparityRangeFollower::~DisparityRangeFollower() = default;

bool DisparityRangeFollower::automatic() const { return impl_->estimator != nullptr; }

DisparityRange DisparityRangeFollower::beforeFrame(const cv::Mat& leftRectified, const cv::Mat& rightRectified) {
  Impl& s = *impl_;
  if (!s.history.current) {
    DisparitySample sample =
        s.estimator->measure(leftRectified, rightRectified, DisparityRangeEstimator::RowCheck::Measure);
    s.history.firstMatches = sample.matches();
    s.history.rowOffsetPx = sample.rowOffsetPx;
    s.use(s.estimator->wantedRange(sample));
    s.previous = std::move(sample);
  } else if (s.next) {
    s.use(*s.next);
    s.next.reset();
  }
  return *s.history.current;
}

DisparitySample DisparityRangeFollower::measure(const cv::Mat& leftRectified, const cv::Mat& rightRectified) {
  if (!automatic()) return {};
  return impl_->estimator->measure(leftRectified, rightRectified);
}

void DisparityRangeFollower::afterFrame(const DisparitySample& sample, double predictedMoves) {
  Impl& s = *impl_;
  if (!automatic() || !s.history.current) return;
  s.next = s.estimator->followingRange(s.next.value_or(*s.history.current), sample, &s.previous, predictedMoves);
  s.previous = sample;
}

void DisparityRangeFollower::afterFrame(const cv::Mat& leftRectified, const cv::Mat& rightRectified) {
  if (automatic()) afterFrame(measure(leftRectified, rightRectified));
}

int DisparityRangeFollower::sampleEveryFrames() const {
  return automatic() ? impl_->estimator->options().sampleEveryFrames : 1;
}

const DisparityRangeHistory& DisparityRangeFollower::history() const { return impl_->history; }

cv::Mat DisparityRangeFollower::alignedRight(const cv::Mat& rightRectified) const {
  return alignRightRows(rightRectified, impl_->history.rowOffsetPx);
}

std::string DisparityRangeFollower::description() const {
  return describeDisparityRange(impl_->history, impl_->parameters);
}

std::string describeDisparityRange(const DisparityRangeHistory& history, const StereoParameters& parameters) {
  if (!history.current) return "not chosen yet";
  std::string text;
  switch (history.mode) {
    case DisparityRangeMode::Fixed: text = "fixed: "; break;
    case DisparityRangeMode::WorkingDistance:
      text = cv::format("working distance %g..%g mm: ", parameters.workingDistanceNearMm, parameters.workingDistanceFarMm);
      break;
    default: text = "auto: "; break;
  }
  text += history.current->text();
  if (history.mode == DisparityRangeMode::Automatic) {
    if (history.changes == 0) {
      text += " (from " + std::to_string(history.firstMatches) + " left-right feature matches)";
    } else {
      text += " (first " + history.first->text() + " from " + std::to_string(history.firstMatches) +
              " left-right feature matches; " + std::to_string(history.changes) +
              (history.changes == 1 ? " change" : " changes") + ", widest " + history.widest.text() + ")";
    }
  }
  const std::string warning = rowOffsetWarning(history);
  return warning.empty() ? text : text + "; " + warning;
}

std::string rowOffsetWarning(const DisparityRangeHistory& history) {
  if (history.rowOffsetPx == 0) return {};
  const double rows = std::abs(history.rowOffsetPx);
  const bool below = history.rowOffsetPx > 0;
  return cv::format("not rectified: the right view's rows lay %g px %s the left's; it is moved %g rows %s before "
                    "matching (check the calibration)",
                    rows, below ? "below" : "above", std::round(rows), below ? "up" : "down");
}

cv::Mat alignRightRows(const cv::Mat& rightRectified, double rowOffsetPx) {
  const int down = -static_cast<int>(std::lround(rowOffsetPx));
  if (down == 0) return rightRectified;
  cv::Mat aligned(rightRectified.size(), rightRectified.type(), cv::Scalar::all(0));
  const int rows = rightRectified.rows - std::abs(down);
  if (rows <= 0) return aligned;
  // aligned(y) = right(y - down)
  rightRectified.rowRange(std::max(0, -down), std::max(0, -down) + rows)
      .copyTo(aligned.rowRange(std::max(0, down), std::max(0, down) + rows));
  return aligned;
}

std::string disparityRangeJson(const DisparityRangeHistory& history) {
  const auto pair = [](const std::optional<DisparityRange>& range) {
    return range ? "[" + std::to_string(range->minPx) + ", " + std::to_string(range->maxPx) + "]" : std::string("null");
  };
  std::string json = std::string("{\"mode\": \"") + disparityRangeModeName(history.mode) + "\", \"first\": " +
                     pair(history.first) + ", \"last\": " + pair(history.current) + ", \"widest\": " +
                     pair(history.first ? std::optional<DisparityRange>(history.widest) : std::nullopt) +
                     ", \"changes\": " + std::to_string(history.changes);
  if (history.mode == DisparityRangeMode::Automatic) {
    json += ", \"first_frame_matches\": " + std::to_string(history.firstMatches) +
            cv::format(", \"row_offset_px\": %g", history.rowOffsetPx);
  }
  return json + "}";
}

}  // namespace tissuemosaic
