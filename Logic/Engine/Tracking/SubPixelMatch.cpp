#include "Tracking/SubPixelMatch.h"

#include "Core/Buffer.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Tracking/OrbPipeline.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace tissuemosaic {

namespace {

/// A device copy of one image, named by the caller's id (-1: none, reusable at once).
struct DeviceImage {
  int64_t id = -1;
  uint64_t lastUse = 0;
  Buffer<uint8_t> pixels;
};

}  // namespace

struct SubPixelMatcher::Impl {
  Device device;
  int halfWindowPx;
  float maxShiftPx;
  std::vector<DeviceImage> deviceImages;  ///< CUDA only: a small least-recently-used cache
  std::size_t retained = 0;               ///< slots kept before the least recently used is reused
  long long uploads = 0;
  uint64_t calls = 0;
  Buffer<uint8_t> input;  ///< image pointer table, then the queries
  Buffer<subpixel::Answer> answers;

  /// The device copy of image i of this call: cached under its id, or uploaded into the least recently used slot
  /// that this call has not taken yet.
  const uint8_t* deviceCopy(const cv::Mat& image, int64_t id) {
    const std::size_t pixels = image.total();
    if (id >= 0) {
      for (DeviceImage& slot : deviceImages) {
        if (slot.id == id && slot.pixels.size() == pixels) {
          slot.lastUse = calls;
          return slot.pixels.data();
        }
      }
    }
    DeviceImage* victim = nullptr;
    if (deviceImages.size() >= retained) {
      for (DeviceImage& slot : deviceImages) {
        if (slot.lastUse == calls) continue;  // taken by this call
        if (!victim || slot.lastUse < victim->lastUse) victim = &slot;
      }
    }
    if (!victim) {
      deviceImages.emplace_back();
      victim = &deviceImages.back();
    }
    if (victim->pixels.size() != pixels) victim->pixels = Buffer<uint8_t>(device, pixels);
    victim->pixels.upload(image.ptr<uint8_t>());
    ++uploads;
    victim->id = id;
    victim->lastUse = calls;
    return victim->pixels.data();
  }
};

SubPixelMatcher::SubPixelMatcher(Device device, double maxShiftPx, int halfWindowPx)
    : impl_(new Impl{device, halfWindowPx, static_cast<float>(maxShiftPx), {}, 0, 0, 0, {}, {}}) {
  require(halfWindowPx >= 1 && halfWindowPx <= subpixel::kMaxHalfWindowPx,
          "sub-pixel matching: the half window must be 1 to " + std::to_string(subpixel::kMaxHalfWindowPx) + " px");
  require(maxShiftPx > 0 && std::isfinite(maxShiftPx), "sub-pixel matching: the largest shift must be positive");
  requireUsableDevice(device, "sub-pixel matching on CUDA");
}

SubPixelMatcher::~SubPixelMatcher() = default;
Device SubPixelMatcher::device() const { return impl_->device; }
void SubPixelMatcher::forgetImages() { impl_->deviceImages.clear(); }
void SubPixelMatcher::setRetainedImages(int count) { impl_->retained = static_cast<std::size_t>(std::max(0, count)); }
long long SubPixelMatcher::uploadedImages() const { return impl_->uploads; }

std::vector<SubPixelMatchAnswer> SubPixelMatcher::refine(const std::vector<cv::Mat>& images,
                                                         const std::vector<SubPixelMatchQuery>& queries,
                                                         const std::vector<int64_t>& imageIds) {
  std::vector<SubPixelMatchAnswer> answers(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) answers[i].toPx = queries[i].toPx;
  if (queries.empty()) return answers;
  require(!images.empty(), "sub-pixel matching: no images");
  const cv::Size size = images[0].size();
  for (const cv::Mat& image : images) {
    require(image.type() == CV_8UC1 && image.size() == size && !image.empty(),
            "sub-pixel matching: the images must be 8-bit grey and of one size");
  }
  require(imageIds.empty() || imageIds.size() == images.size(),
          "sub-pixel matching: " + std::to_string(imageIds.size()) + " image ids for " + std::to_string(images.size()) +
              " images");
  const int count = static_cast<int>(images.size());
  std::vector<subpixel::Query> hostQueries(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const SubPixelMatchQuery& q = queries[i];
    if (q.referenceImage < 0 || q.referenceImage >= count || q.image < 0 || q.image >= count) {
      throw Error("sub-pixel matching: a query names an image outside the list of " + std::to_string(count));
    }
    hostQueries[i] = {q.referenceImage, q.image, q.fromPx.x, q.fromPx.y, q.toPx.x, q.toPx.y};
  }

  profiling::ScopedTimer timer("host: sub-pixel upload, kernel and download");
  Impl& s = *impl_;
  ++s.calls;
  // The CPU reads the images in place; CUDA reads device copies (cached by id).
  std::vector<cv::Mat> continuous(images.size());
  std::vector<const uint8_t*> table(images.size());
  for (int i = 0; i < count; ++i) {
    continuous[i] = images[i].isContinuous() ? images[i] : images[i].clone();
    table[i] = s.device == Device::Cuda ? s.deviceCopy(continuous[i], imageIds.empty() ? -1 : imageIds[i])
                                        : continuous[i].ptr<uint8_t>();
  }
  // One upload: the image table, then the queries (a transfer costs tens of microseconds whatever its size).
  static_assert(alignof(subpixel::Query) <= sizeof(const uint8_t*), "queries follow the pointer table");
  const std::size_t tableBytes = table.size() * sizeof(const uint8_t*);
  std::vector<uint8_t> staging(tableBytes + hostQueries.size() * sizeof(subpixel::Query));
  std::memcpy(staging.data(), table.data(), tableBytes);
  std::memcpy(staging.data() + tableBytes, hostQueries.data(), hostQueries.size() * sizeof(subpixel::Query));
  reserveBuffer(s.input, s.device, staging.size());
  reserveBuffer(s.answers, s.device, queries.size());
  s.input.uploadPart(staging.data(), staging.size());
  const subpixel::LucasKanadeRefine refine{reinterpret_cast<const uint8_t* const*>(s.input.data()), size.width,
                                           size.height,
                                           reinterpret_cast<const subpixel::Query*>(s.input.data() + tableBytes),
                                           s.answers.data(), s.halfWindowPx, s.maxShiftPx};
  if (s.device == Device::Cuda) orb::refineSubPixelCuda(refine, static_cast<int>(queries.size()));
  else orb::refineSubPixelCpu(refine, static_cast<int>(queries.size()));
  std::vector<subpixel::Answer> hostAnswers(queries.size());
  s.answers.downloadPart(hostAnswers.data(), hostAnswers.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    answers[i].locked = hostAnswers[i].locked != 0;
    if (answers[i].locked) answers[i].toPx = cv::Point2f(hostAnswers[i].x, hostAnswers[i].y);
  }
  return answers;
}

}  // namespace tissuemosaic
