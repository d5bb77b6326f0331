#pragma once
/// @file SubPixelMatch.h
/// @brief Sub-pixel refinement of feature matches (not in the paper): ORB keypoints sit on a pixel (or pyramid
/// level) grid, good to about a pixel, and frame-to-frame pose noise accumulates as drift. A translation-only
/// inverse-compositional Lucas-Kanade moves each match so that the window around it best matches the window around
/// its reference pixel. All matches of a call are refined at once, on the CPU or CUDA from one source
/// (SubPixelKernels.h).
#include "Core/Device.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace tissuemosaic {

/// The window half size the tracker and the refiner use: 11 x 11 windows, as the ZNCC window.
constexpr int kSubPixelHalfWindowPx = 5;

/// One match: fromPx in image `referenceImage`, toPx (the start) in image `image` of the call's image list.
struct SubPixelMatchQuery {
  int referenceImage = 0;
  int image = 1;
  cv::Point2f fromPx, toPx;
};

struct SubPixelMatchAnswer {
  cv::Point2f toPx;     ///< refined position; the start when not locked
  bool locked = false;  ///< false: too little texture, leaves the image, no convergence, or moved > maxShiftPx
};

class SubPixelMatcher {
public:
  /// maxShiftPx > 0: a match moved farther is not locked; halfWindowPx in [1, 7]. Throws Error for Device::Cuda
  /// without CUDA.
  SubPixelMatcher(Device device, double maxShiftPx, int halfWindowPx = kSubPixelHalfWindowPx);
  ~SubPixelMatcher();
  SubPixelMatcher(const SubPixelMatcher&) = delete;
  SubPixelMatcher& operator=(const SubPixelMatcher&) = delete;

  /// Refines every query. images: 8-bit grey images of one size; the queries index them. imageIds (optional, one
  /// per image, >= 0): names under which CUDA keeps an image on the device, so that a later call naming the same
  /// id does not upload it again (a frame's index: the caller guarantees that an id always means the same image).
  /// Throws Error for an empty list, differing sizes or types, an index outside the list, or a wrong id count.
  std::vector<SubPixelMatchAnswer> refine(const std::vector<cv::Mat>& images,
                                          const std::vector<SubPixelMatchQuery>& queries,
                                          const std::vector<int64_t>& imageIds = {});

  /// Drops the device copies kept by id (for a new sequence whose frame indices start again).
  void forgetImages();
  /// CUDA: keep at least this many images by id before reusing the least recently used one (default 0: reuse as
  /// soon as a call has what it needs). The reconstruct pipeline shares one matcher between the tracker, which
  /// uploads every frame, and the key-frame refiner, which then finds the intermediate frames already there.
  void setRetainedImages(int count);
  /// Images uploaded to the device so far (CUDA; 0 on the CPU, which reads them in place).
  long long uploadedImages() const;

  Device device() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
