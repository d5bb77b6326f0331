#include "Tracking/OrbFeatures.h"

#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParameterChecks.h"
#include "Tracking/OrbPipeline.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

namespace tissuemosaic {

namespace orb {

OrbLevelWorkspace::OrbLevelWorkspace(Device device, int width, int height, const CellGrid& grid_, int budget_)
    : grid(grid_), budget(budget_), scaleQ16(65536), image(device, width, height), smoothingRows(device, width, height),
      smoothed(device, width, height), fastScores(device, width, height), responses(device, width, height),
      rowCandidates(device, static_cast<std::size_t>(grid_.cellCount()) * grid_.cellSize * grid_.perCell),
      slots(device, static_cast<std::size_t>(grid_.cellCount()) * grid_.perCell), histogram(device, kResponseBins),
      cellAbove(device, grid_.cellCount()), cellAtThreshold(device, grid_.cellCount()),
      cellOffsets(device, grid_.cellCount()), control(device, kControlCount), selected(device, budget_),
      descriptors(device, static_cast<std::size_t>(budget_) * kDescriptorBytes) {}

}  // namespace orb

namespace {

constexpr parameters::Group kOrb{"ORB"};

/// splitmix64: a fixed integer generator, so the pattern is the same with every compiler and library.
uint64_t nextRandom(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// One coordinate from N(0, (31/5)^2), approximated by the sum of 12 uniform 16-bit numbers (Irwin-Hall), rounded
/// to an integer with integer arithmetic only.
int gaussianOffset(uint64_t& state) {
  int64_t sum = 0;
  for (int i = 0; i < 12; ++i) sum += static_cast<int64_t>(nextRandom(state) & 0xFFFF);
  const int64_t numerator = 31 * (sum - 6 * 65536), denominator = 5 * 65536;
  return static_cast<int>((numerator >= 0 ? numerator + denominator / 2 : numerator - denominator / 2) / denominator);
}

std::vector<int8_t> makePattern() {
  std::vector<int8_t> pattern;
  pattern.reserve(orb::kPatternPairs * 4);
  uint64_t state = 20240531;
  const int r2 = orb::kPatchRadius * orb::kPatchRadius;
  while (static_cast<int>(pattern.size()) < orb::kPatternPairs * 4) {
    int p[4];
    for (int& v : p) v = gaussianOffset(state);
    if (p[0] * p[0] + p[1] * p[1] > r2 || p[2] * p[2] + p[3] * p[3] > r2) continue;  // keep rotations in the disc
    if (p[0] == p[2] && p[1] == p[3]) continue;
    bool duplicate = false;
    for (std::size_t i = 0; i < pattern.size() && !duplicate; i += 4) {
      duplicate = (pattern[i] == p[0] && pattern[i + 1] == p[1] && pattern[i + 2] == p[2] && pattern[i + 3] == p[3]) ||
                  (pattern[i] == p[2] && pattern[i + 1] == p[3] && pattern[i + 2] == p[0] && pattern[i + 3] == p[1]);
    }
    if (duplicate) continue;
    for (int v : p) pattern.push_back(static_cast<int8_t>(v));
  }
  return pattern;
}

}  // namespace

void OrbParameters::validate() const {
  kOrb.requireRange("maxFeatures", maxFeatures, 1, 100000);
  kOrb.requireRange("levels", levels, 1, 8);
  kOrb.requireRange("scaleFactor", scaleFactor, 1.01, 2.0);
  kOrb.requireRange("fastThreshold", fastThreshold, 1, 254);
  kOrb.requireRange("edgeThresholdPx", edgeThresholdPx, orb::kPatchRadius + 1, 100);
  kOrb.requireRange("cellSizePx", cellSizePx, 4, 512);
  kOrb.requireRange("maxPerCell", maxPerCell, 1, orb::kMaxPerCell);
}

std::vector<cv::KeyPoint> toCvKeyPoints(const OrbFeatures& features, double scaleFactor) {
  std::vector<cv::KeyPoint> keypoints;
  keypoints.reserve(features.keypoints.size());
  for (const OrbKeypoint& k : features.keypoints) {
    keypoints.emplace_back(k.xPx, k.yPx, static_cast<float>(31.0 * std::pow(scaleFactor, k.level)), k.angleDeg,
                           static_cast<float>(k.response), k.level);
  }
  return keypoints;
}

cv::Mat descriptorRows(const cv::Mat& descriptors, const std::vector<int>& rows) {
  cv::Mat selected(static_cast<int>(rows.size()), descriptors.cols, descriptors.type());
  const std::size_t rowBytes = descriptors.cols * descriptors.elemSize();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    require(rows[r] >= 0 && rows[r] < descriptors.rows, "descriptorRows: a row index is outside the matrix");
    std::memcpy(selected.ptr(static_cast<int>(r)), descriptors.ptr(rows[r]), rowBytes);
  }
  return selected;
}

struct OrbExtractor::Impl {
  Device device;
  OrbParameters parameters;
  Buffer<int8_t> pattern;
  std::vector<orb::OrbLevelWorkspace> levels;
  int width = 0, height = 0;

  void prepare(int w, int h) {
    if (w == width && h == height) return;
    levels.clear();
    width = w;
    height = h;
    const OrbParameters& p = parameters;
    const int border = p.edgeThresholdPx;
    // Budgets as ORB: geometric in the level area ratio, the remainder to the last level that exists.
    const double factor = 1.0 / p.scaleFactor;
    std::vector<double> scales;
    for (int l = 0; l < p.levels; ++l) {
      const double scale = std::pow(p.scaleFactor, l);
      const int lw = static_cast<int>(std::lround(w / scale)), lh = static_cast<int>(std::lround(h / scale));
      if (lw <= 2 * border || lh <= 2 * border) break;
      scales.push_back(scale);
    }
    require(!scales.empty(), "ORB: the image (" + std::to_string(w) + "x" + std::to_string(h) +
                                 ") is too small for the feature border of " + std::to_string(border) + " px");
    const int count = static_cast<int>(scales.size());
    const double first = p.maxFeatures * (1 - factor) / (1 - std::pow(factor, count));
    int assigned = 0;
    levels.reserve(count);
    for (int l = 0; l < count; ++l) {
      const int budget = l + 1 < count ? std::max(1, static_cast<int>(std::lround(first * std::pow(factor, l))))
                                       : std::max(1, p.maxFeatures - assigned);
      assigned += budget;
      const int lw = static_cast<int>(std::lround(w / scales[l])), lh = static_cast<int>(std::lround(h / scales[l]));
      const orb::CellGrid grid{p.cellSizePx, (lw + p.cellSizePx - 1) / p.cellSizePx, (lh + p.cellSizePx - 1) / p.cellSizePx,
                               p.maxPerCell};
      levels.emplace_back(device, lw, lh, grid, budget);
      levels.back().scaleQ16 = std::llround(scales[l] * 65536.0);
    }
  }
};

OrbExtractor::OrbExtractor(Device device, const OrbParameters& parameters) : impl_(new Impl{device, parameters, {}, {}}) {
  parameters.validate();
  requireUsableDevice(device, "ORB extraction on CUDA");
  const std::vector<int8_t>& table = pattern();
  impl_->pattern = Buffer<int8_t>(device, table.size());
  impl_->pattern.upload(table.data());
}

OrbExtractor::~OrbExtractor() = default;
Device OrbExtractor::device() const { return impl_->device; }
const OrbParameters& OrbExtractor::parameters() const { return impl_->parameters; }

const std::vector<int8_t>& OrbExtractor::pattern() {
  static const std::vector<int8_t> table = makePattern();
  return table;
}

OrbFeatures OrbExtractor::extract(const cv::Mat& grey) {
  require(!grey.empty() && grey.type() == CV_8UC1, "ORB: the image must be 8-bit single-channel grey");
  const cv::Mat input = grey.isContinuous() ? grey : grey.clone();
  Impl& s = *impl_;
  s.prepare(input.cols, input.rows);
  {
    profiling::ScopedTimer timer("host: ORB upload");
    s.levels[0].image.buffer().upload(input.ptr<uint8_t>());
  }
  const orb::OrbSettings settings{s.parameters.fastThreshold, s.parameters.edgeThresholdPx};
  if (s.device == Device::Cuda) orb::runOrbPipelineCuda(s.levels.data(), static_cast<int>(s.levels.size()), settings, s.pattern.data());
  else orb::runOrbPipelineCpu(s.levels.data(), static_cast<int>(s.levels.size()), settings, s.pattern.data());

  profiling::ScopedTimer timer("host: ORB download and sort");
  struct Entry {
    OrbKeypoint keypoint;
    int64_t response;
    const uint8_t* descriptor;
  };
  std::vector<Entry> entries;
  entries.reserve(static_cast<std::size_t>(s.parameters.maxFeatures));
  std::vector<std::vector<uint8_t>> descriptorStore(s.levels.size());
  for (std::size_t l = 0; l < s.levels.size(); ++l) {
    const orb::OrbLevelWorkspace& w = s.levels[l];
    const std::vector<int> control = w.control.toHost();
    const int count = std::min(control[orb::kSelected], w.budget);
    const std::vector<orb::LevelKeypoint> selected = w.selected.toHost();
    descriptorStore[l] = w.descriptors.toHost();
    const float scale = static_cast<float>(w.scaleQ16 / 65536.0);
    for (int i = 0; i < count; ++i) {
      const orb::LevelKeypoint& f = selected[i];
      OrbKeypoint k;
      k.xPx = f.x * scale;
      k.yPx = f.y * scale;
      double angle = (f.m10 == 0 && f.m01 == 0) ? 0.0 : std::atan2(double(f.m01), double(f.m10)) * 180.0 / M_PI;
      if (angle < 0) angle += 360.0;
      k.angleDeg = static_cast<float>(angle >= 360.0 ? 0.0 : angle);
      k.response = static_cast<double>(f.response);
      k.level = static_cast<int>(l);
      k.levelX = f.x;
      k.levelY = f.y;
      entries.push_back({k, f.response, descriptorStore[l].data() + static_cast<std::size_t>(i) * orb::kDescriptorBytes});
    }
  }
  profiling::ScopedTimer sortTimer("host: ORB sort");
  // Sorted by index (entries are 56 bytes): response first, then level, row and column.
  std::vector<int> order(entries.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&entries](int i, int j) {
    const Entry &a = entries[i], &b = entries[j];
    if (a.response != b.response) return a.response > b.response;
    if (a.keypoint.level != b.keypoint.level) return a.keypoint.level < b.keypoint.level;
    if (a.keypoint.levelY != b.keypoint.levelY) return a.keypoint.levelY < b.keypoint.levelY;
    return a.keypoint.levelX < b.keypoint.levelX;
  });
  OrbFeatures features;
  features.keypoints.reserve(entries.size());
  features.descriptors.create(static_cast<int>(entries.size()), orb::kDescriptorBytes, CV_8U);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Entry& entry = entries[static_cast<std::size_t>(order[i])];
    features.keypoints.push_back(entry.keypoint);
    std::copy_n(entry.descriptor, orb::kDescriptorBytes, features.descriptors.ptr<uint8_t>(static_cast<int>(i)));
  }
  return features;
}

// ---- HammingMatcher -----------------------------------------------------------------------------------------------

struct HammingMatcher::Impl {
  Device device;
  Buffer<uint64_t> input;  ///< A rows, B rows, segment tables
  Buffer<int> output;      ///< indices, distances
};

HammingMatcher::HammingMatcher(Device device) : impl_(new Impl{device, {}, {}}) {
  requireUsableDevice(device, "Hamming matching on CUDA");
}

HammingMatcher::~HammingMatcher() = default;
Device HammingMatcher::device() const { return impl_->device; }

namespace {

void requireDescriptors(const cv::Mat& descriptors, const char* name) {
  require(descriptors.type() == CV_8UC1 && descriptors.cols == orb::kDescriptorBytes,
          std::string("Hamming matching: ") + name + " must be CV_8U with 32 bytes a row");
}

/// Copies a descriptor matrix's rows (4 words each) to `target`.
void copyDescriptors(uint64_t* target, const cv::Mat& descriptors) {
  const cv::Mat rows = descriptors.isContinuous() ? descriptors : descriptors.clone();
  std::memcpy(target, rows.data, static_cast<std::size_t>(rows.rows) * orb::kDescriptorBytes);
}

}  // namespace

std::vector<std::vector<cv::DMatch>> HammingMatcher::match(const cv::Mat& descriptorsA, const cv::Mat& descriptorsB,
                                                           int k) {
  return matchPairs({{descriptorsA, descriptorsB}}, k)[0];
}

std::vector<std::vector<std::vector<cv::DMatch>>> HammingMatcher::matchPairs(
    const std::vector<std::pair<cv::Mat, cv::Mat>>& pairs, int k) {
  require(k >= 1 && k <= orb::kMaxMatchK, "Hamming matching: k must be in [1, 8], got " + std::to_string(k));
  Impl& s = *impl_;
  std::vector<std::vector<std::vector<cv::DMatch>>> result(pairs.size());
  std::vector<int> aBegin{0}, bBegin{0};
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const cv::Mat& A = pairs[p].first;
    const cv::Mat& B = pairs[p].second;
    result[p].resize(A.empty() ? 0 : A.rows);
    // A pair with an empty side contributes no rows: its rows of A have no matches.
    const bool matched = !A.empty() && !B.empty();
    if (matched) {
      requireDescriptors(A, "descriptorsA");
      requireDescriptors(B, "descriptorsB");
    }
    aBegin.push_back(aBegin.back() + (matched ? A.rows : 0));
    bBegin.push_back(bBegin.back() + (matched ? B.rows : 0));
  }
  const int rowsA = aBegin.back();
  if (rowsA == 0) return result;
  profiling::ScopedTimer timer("host: match upload, kernel, download and lists");
  const std::size_t outputs = static_cast<std::size_t>(rowsA) * k;
  // One upload (A rows, B rows, then both segment tables as ints) and one download (indices, then distances):
  // each transfer costs tens of microseconds whatever its size.
  const std::size_t aWords = static_cast<std::size_t>(rowsA) * 4, bWords = static_cast<std::size_t>(bBegin.back()) * 4;
  const std::size_t tableWords = (aBegin.size() + bBegin.size() + 1) / 2;
  std::vector<uint64_t> staging(aWords + bWords + tableWords, 0);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    if (aBegin[p + 1] == aBegin[p]) continue;
    copyDescriptors(staging.data() + 4 * static_cast<std::size_t>(aBegin[p]), pairs[p].first);
    copyDescriptors(staging.data() + aWords + 4 * static_cast<std::size_t>(bBegin[p]), pairs[p].second);
  }
  int* tables = reinterpret_cast<int*>(staging.data() + aWords + bWords);
  std::copy(aBegin.begin(), aBegin.end(), tables);
  std::copy(bBegin.begin(), bBegin.end(), tables + aBegin.size());
  reserveBuffer(s.input, s.device, staging.size());
  reserveBuffer(s.output, s.device, 2 * outputs);
  s.input.uploadPart(staging.data(), staging.size());
  const uint64_t* deviceWords = s.input.data();
  const int* deviceTables = reinterpret_cast<const int*>(deviceWords + aWords + bWords);
  const orb::HammingKnn knn{deviceWords, deviceWords + aWords,
                            orb::MatchSegments{deviceTables, deviceTables + aBegin.size(), static_cast<int>(pairs.size())},
                            k, s.output.data(), s.output.data() + outputs};
  if (s.device == Device::Cuda) orb::hammingKnnCuda(knn, rowsA);
  else orb::hammingKnnCpu(knn, rowsA);
  std::vector<int> downloaded(2 * outputs);
  s.output.downloadPart(downloaded.data(), downloaded.size());
  const int* indices = downloaded.data();
  const int* distances = downloaded.data() + outputs;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const int first = aBegin[p];
    for (int row = first; row < aBegin[p + 1]; ++row) {
      std::vector<cv::DMatch>& list = result[p][row - first];
      for (int j = 0; j < k; ++j) {
        const std::size_t at = static_cast<std::size_t>(row) * k + j;
        if (indices[at] >= 0) list.emplace_back(row - first, indices[at], static_cast<float>(distances[at]));
      }
    }
  }
  return result;
}

}  // namespace tissuemosaic
