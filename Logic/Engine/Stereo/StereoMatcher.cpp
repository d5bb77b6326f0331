#include "StereoMatcher.h"

#include "Core/Error.h"
#include "Core/PixelFormat.h"
#include "Core/Stopwatch.h"
#include "DisparitySampling.h"
#include "StereoPipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace tissuemosaic {

namespace stereo {

namespace {

/// Pixels of the buffers that only the paper's method uses (0 under AD-Census), and of those only one backend uses.
std::size_t pixelsIf(bool used, int width, int height) { return used ? static_cast<std::size_t>(width) * height : 0; }

}  // namespace

StereoWorkspace::StereoWorkspace(Device device_, StereoMethod method_, int width_, int height_, int disparityCount_)
    : device(device_), method(method_), width(width_), height(height_), disparityCount(disparityCount_),
      leftGreyStaging(device, pixelsIf(device == Device::Cuda, width, height)),
      rightGreyStaging(device, pixelsIf(device == Device::Cuda, width, height)),
      leftGrey(device, width, height), rightGrey(device, width, height),
      left(device, width, height), right(device, width, height),
      columnEven(device, paperWidth(), height), columnOdd(device, paperWidth(), height),
      columnEvenSq(device, paperWidth(), height), columnOddSq(device, paperWidth(), height),
      sumLeft(device, paperWidth(), height), inverseNormLeft(device, paperWidth(), height),
      sumRight(device, paperWidth(), height), inverseNormRight(device, paperWidth(), height),
      volume(device, static_cast<std::size_t>(disparityCount) * pixelsIf(paper(), width, height), HostPages::Huge),
      znccDisparity(device, width, height), rightZnccDisparity(device, width, height),
      rightWinnerKeys(device, pixelsIf(paper() && device == Device::Cuda, width, height)),
      discrete(device, width, height), discreteScratch(device, paperWidth(), height),
      filledDisparity(device, width, height),
      smoothed(device, width, height), smoothedPrevious(device, paperWidth(), height), correction(device, width, height),
      leftHighlightSeeds(device, width, height), rightHighlightSeeds(device, width, height),
      leftNearHighlight(device, width, height), rightNearHighlight(device, width, height),
      highlightNeighbourhood(device, width, height), awayFromHighlights(device, width, height),
      radialHitDistance(device, 8 * pixelsIf(paper() && device == Device::Cpu, width, height)),
      radialHitValue(device, 8 * pixelsIf(paper() && device == Device::Cpu, width, height)),
      rayPasses(device, 8 * pixelsIf(paper() && device == Device::Cpu, width, height)),
      rowSum(device, static_cast<std::size_t>(width) * height), rowCount(device, static_cast<std::size_t>(width) * height),
      rangeEndRowCounts(device, 3 * static_cast<std::size_t>(height)) {
  rightWinnerKeys.setZero();  // the GPU launcher leaves them zero after each frame
  if (!paper()) adCensus = std::make_unique<AdCensusWorkspace>(device, width, height, disparityCount);
}

GuidedWorkspace::GuidedWorkspace(Device device, int width, int height, int coarseDisparityCount)
    : coarse(std::make_unique<StereoWorkspace>(device, StereoMethod::Paper, (width + 1) / 2, (height + 1) / 2,
                                               coarseDisparityCount)),
      windowLow(device, width, height), windowHigh(device, width, height), fellBack(device, width, height) {}

StereoParameters guidedCoarseParameters(const StereoParameters& p) {
  StereoParameters coarse = p;
  coarse.search = StereoSearch::Exhaustive;
  const auto floorHalf = [](int v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); };
  coarse.minDisparityPx = floorHalf(p.minDisparityPx);
  coarse.maxDisparityPx = -floorHalf(-p.maxDisparityPx);
  coarse.specularMarginPx = p.specularMarginPx / 2;
  coarse.specularMaxRadiusPx = std::max(1, p.specularMaxRadiusPx / 2);
  coarse.trackingHighlightMarginPx = p.trackingHighlightMarginPx / 2;
  return coarse;
}

long long cellsScored(const StereoWorkspace& w) {
  const long long pixels = static_cast<long long>(w.width) * w.height;
  if (!w.lastSearchGuided) return pixels * w.disparityCount;
  const std::vector<int16_t> low = w.guided->windowLow.buffer().toHost(), high = w.guided->windowHigh.buffer().toHost();
  const std::vector<uint8_t> fellBack = w.guided->fellBack.buffer().toHost();
  long long cells = 0;
  for (std::size_t i = 0; i < low.size(); ++i) cells += high[i] - low[i] + 1 + (fellBack[i] ? w.disparityCount : 0);
  return cells;
}

AdCensusWorkspace::AdCensusWorkspace(Device device, int width, int height, int disparityCount)
    : leftCensus(device, static_cast<std::size_t>(width) * height),
      rightCensus(device, static_cast<std::size_t>(width) * height),
      leftArms(device, 4 * static_cast<std::size_t>(width) * height),
      rightArms(device, 4 * static_cast<std::size_t>(width) * height),
      cost(device, static_cast<std::size_t>(width) * height * disparityCount),
      packedWindows(device, static_cast<std::size_t>(width) * height * disparityCount),
      prefix(device, static_cast<std::size_t>(width + 1) * (height + 1) * disparityCount),
      pathCost(device, static_cast<std::size_t>(width) * height * disparityCount) {}

}  // namespace stereo

namespace {

/// From this many pixels an image is converted to grey in bands on the thread pool. At 1920x1080 the conversion of
/// the pair took 1.6 ms of the stereo thread, the frame's critical path there (H100 host, 2026-11-26); at 960x540
/// (0.4 ms) the tracking thread beside it is as long, and bands taken from it cost it as much as they saved.
constexpr std::size_t kBandedGreyMinPixels = 1'000'000;
constexpr int kGreyBands = 8;

cv::Mat downloadMap(const Image<float>& image) {
  cv::Mat result(image.height(), image.width(), CV_32F);
  image.buffer().download(result.ptr<float>());
  return result;
}

cv::Mat downloadDiscrete(const Image<int16_t>& image) {
  const std::vector<int16_t> values = image.buffer().toHost();
  cv::Mat result(image.height(), image.width(), CV_32F);
  for (std::size_t i = 0; i < values.size(); ++i) {
    result.at<float>(static_cast<int>(i)) = values[i] == stereo::kNoDisparity ? NAN : static_cast<float>(values[i]);
  }
  return result;
}

}  // namespace

struct StereoMatcher::Impl {
  Device device;
  StereoParameters parameters;
  std::unique_ptr<stereo::StereoWorkspace> workspace;
};

StereoMatcher::StereoMatcher(Device device, const StereoParameters& parameters) : impl_(new Impl{device, parameters, {}}) {
  parameters.validate();
  requireUsableDevice(device, "CUDA stereo matching");
}

StereoMatcher::~StereoMatcher() = default;

Device StereoMatcher::device() const { return impl_->device; }

void StereoMatcher::setDisparityRange(const DisparityRange& range) {
  StereoParameters changed = impl_->parameters;
  changed.minDisparityPx = range.minPx;
  changed.maxDisparityPx = range.maxPx;
  changed.validate();
  impl_->parameters = changed;  // a new count replaces the workspace at the next computeDisparity
}

DisparityRange StereoMatcher::disparityRange() const {
  return {impl_->parameters.minDisparityPx, impl_->parameters.maxDisparityPx};
}
const StereoParameters& StereoMatcher::parameters() const { return impl_->parameters; }

cv::Mat StereoMatcher::computeDisparity(const cv::Mat& leftRectified, const cv::Mat& rightRectified,
                                        StereoTimingsMs* timings, StereoExplanation* explanation) {
  StereoTimingsMs local;
  StereoTimingsMs& t = timings ? *timings : local;
  match(leftRectified, rightRectified, &t, explanation);
  const auto start = std::chrono::steady_clock::now();
  cv::Mat disparity = downloadLastDisparity();
  t.download = millisecondsSince(start);
  return disparity;
}

cv::Mat StereoMatcher::downloadLastDisparity() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return downloadMap(impl_->workspace->smoothed);
}

void StereoMatcher::match(const cv::Mat& leftRectified, const cv::Mat& rightRectified, StereoTimingsMs* timings,
                          StereoExplanation* explanation) {
  const StereoParameters& p = impl_->parameters;
  require(leftRectified.size() == rightRectified.size(),
          "the left and right images differ in size (" + std::to_string(leftRectified.cols) + "x" +
              std::to_string(leftRectified.rows) + " vs " + std::to_string(rightRectified.cols) + "x" +
              std::to_string(rightRectified.rows) + ")");
  StereoTimingsMs local;
  StereoTimingsMs& t = timings ? *timings : local;
  requireGrey8Convertible(leftRectified, "the left image");
  requireGrey8Convertible(rightRectified, "the right image");
  // The smallest image is the method's own matching window: a window's sums need that many pixels of image.
  const bool adCensus = p.method == StereoMethod::AdCensus;
  const int minimumWidth = adCensus ? p.censusWidthPx : p.znccWindowPx;
  const int minimumHeight = adCensus ? p.censusHeightPx : p.znccWindowPx;
  require(leftRectified.cols >= minimumWidth && leftRectified.rows >= minimumHeight,
          "the images (" + std::to_string(leftRectified.cols) + "x" + std::to_string(leftRectified.rows) +
              ") are smaller than the " + (adCensus ? "census" : "ZNCC") + " window (" +
              std::to_string(minimumWidth) + "x" + std::to_string(minimumHeight) + " px)");
  auto& workspace = impl_->workspace;
  if (!workspace || workspace->width != leftRectified.cols || workspace->height != leftRectified.rows ||
      workspace->disparityCount != p.disparityCount()) {
    // The method is the matcher's for its lifetime; the image size and the range's count can change.
    workspace = std::make_unique<stereo::StereoWorkspace>(impl_->device, p.method, leftRectified.cols,
                                                          leftRectified.rows, p.disparityCount());
  }
  // 8-bit grey: a quarter of the float image's bytes to upload; the pipeline widens it on the device. On CUDA each
  // image is converted into page-locked memory and its upload queued at once, so the left image travels while the
  // right one is converted, and the kernels queue behind both without the host waiting. The staging memory is
  // written again only at the next call, after this one has waited for the device (the stage clock's end).
  const bool cuda = impl_->device == Device::Cuda;
  const auto convertAndUpload = [&](const cv::Mat& image, Image<uint8_t>& grey, PinnedHostBuffer<uint8_t>& staging,
                                    const char* what) {
    auto start = std::chrono::steady_clock::now();
    cv::Mat hostGrey(image.rows, image.cols, CV_8UC1, cuda ? staging.data() : grey.buffer().data());
    convertToGrey8(image, hostGrey, what, image.total() >= kBandedGreyMinPixels ? kGreyBands : 1);
    t.grey += millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    if (cuda) grey.buffer().uploadQueued(staging.data());  // page-locked: the copy runs while the host goes on
    t.upload += millisecondsSince(start);
  };
  t.grey = t.upload = 0;
  convertAndUpload(leftRectified, workspace->leftGrey, workspace->leftGreyStaging, "the left image");
  convertAndUpload(rightRectified, workspace->rightGrey, workspace->rightGreyStaging, "the right image");

  t.download = 0;
  const StereoParameters sized = p.forImageWidth(leftRectified.cols);
  if (cuda) stereo::runStereoPipelineCuda(*workspace, sized, t, explanation);
  else stereo::runStereoPipelineCpu(*workspace, sized, t, explanation);
}

RangeEndCounts StereoMatcher::lastRangeEndCounts() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  const std::vector<int32_t> rows = impl_->workspace->rangeEndRowCounts.toHost();
  RangeEndCounts counts;
  counts.range = disparityRange();
  for (std::size_t i = 0; i + 2 < rows.size(); i += 3) {
    counts.withWinner += rows[i];
    counts.atMin += rows[i + 1];
    counts.atMax += rows[i + 2];
  }
  return counts;
}

std::string rangeTooNarrowWarning(const RangeEndCounts& counts) {
  if (counts.withWinner <= 0) return {};
  const double high = static_cast<double>(counts.atMax) / counts.withWinner;
  const double low = static_cast<double>(counts.atMin) / counts.withWinner;
  if (high < kRangeEndWarningShare && low < kRangeEndWarningShare) return {};
  // One end alone over the share says which way the scene lies; both (winners strewn over a range far from the
  // scene, as on fine texture) say only that it lies outside.
  const char* where = low < kRangeEndWarningShare ? "above" : high < kRangeEndWarningShare ? "below" : "beyond";
  return cv::format("the disparity range %s cannot hold the scene: %.0f%% of the pixels' best matches lie on its upper "
                    "end (%d px) and %.0f%% on its lower end (%d px), so the scene's disparities reach %s it and those "
                    "pixels are lost; widen the range (--disparity-range, --disparities) or let it be chosen "
                    "automatically (--disparity-range auto)",
                    counts.range.text().c_str(), 100.0 * high, counts.range.maxPx, 100.0 * low, counts.range.minPx,
                    where);
}

long long StereoMatcher::lastCellsScored() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return stereo::cellsScored(*impl_->workspace);
}

cv::Mat StereoMatcher::lastZnccDisparity() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return downloadDiscrete(impl_->workspace->znccDisparity);
}

ImageView<const float> StereoMatcher::lastDisparity() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return impl_->workspace->smoothed.view();
}

cv::Mat StereoMatcher::lastFilledDisparity() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return downloadDiscrete(impl_->workspace->filledDisparity);
}

cv::Mat StereoMatcher::lastHighlightNeighbourhood() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  const Image<uint8_t>& mask = impl_->workspace->highlightNeighbourhood;
  cv::Mat result(mask.height(), mask.width(), CV_8U);
  mask.buffer().download(result.ptr<uint8_t>());
  return result;
}

ImageView<const float> StereoMatcher::lastDisparityAwayFromHighlightsView() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return impl_->workspace->awayFromHighlights.view();
}

std::vector<float> StereoMatcher::sampleLastDisparityAwayFromHighlights(const std::vector<cv::Point2f>& pointsPx) const {
  const ImageView<const float> map = lastDisparityAwayFromHighlightsView();
  std::vector<float> disparitiesPx(pointsPx.size());
  if (pointsPx.empty()) return disparitiesPx;
  if (impl_->device == Device::Cpu) {
    for (std::size_t i = 0; i < pointsPx.size(); ++i) disparitiesPx[i] = sampleDisparityPx(map, pointsPx[i].x, pointsPx[i].y);
    return disparitiesPx;
  }
  static_assert(sizeof(cv::Point2f) == 2 * sizeof(float), "points are uploaded as x, y pairs");
  const int count = static_cast<int>(pointsPx.size());
  Buffer<float> points(Device::Cuda, 2 * pointsPx.size()), samples(Device::Cuda, pointsPx.size());
  points.upload(&pointsPx[0].x);
  sampleDisparitiesCuda(map, points.data(), samples.data(), count);
  samples.download(disparitiesPx.data());
  return disparitiesPx;
}

cv::Mat StereoMatcher::lastDisparityAwayFromHighlights() const {
  require(impl_->workspace != nullptr, "no disparity has been computed yet");
  return downloadMap(impl_->workspace->awayFromHighlights);
}

}  // namespace tissuemosaic
