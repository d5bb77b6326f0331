#pragma once
/// @file SyntheticScanFrameSource.h
/// @brief Test helper: a StereoFrameSource that renders a SyntheticScan's rectified frames in memory (no files),
/// for the logic, widget and application tests. Frames are rendered on the thread that reads them (the worker).
#include "IO/StereoFrameSource.h"
#include "SyntheticScan.h"

#include <memory>
#include <string>

namespace tissuemosaic::testing {

class SyntheticScanFrameSource : public StereoFrameSource {
public:
  explicit SyntheticScanFrameSource(std::shared_ptr<const synthetic::SyntheticScan> scan) : scan_(std::move(scan)) {}
  bool next(StereoFrame& frame) override {
    if (next_ >= scan_->frameCount()) return false;
    const synthetic::SyntheticScanFrame rendered = scan_->renderFrame(next_);
    frame.index = rendered.index;
    frame.timeS = rendered.timeS;
    frame.left = rendered.leftRectified;
    frame.right = rendered.rightRectified;
    ++next_;
    return true;
  }
  int frameCount() const override { return scan_->frameCount(); }
  cv::Size frameSize() const override { return scan_->geometry().imageSize; }
  std::string description() const override { return "synthetic scan in memory"; }

private:
  std::shared_ptr<const synthetic::SyntheticScan> scan_;
  int next_ = 0;
};

/// A short, fast scan (small frames, a quick camera) that still makes several key frames.
inline synthetic::SyntheticScanOptions shortScanOptions(int frames = 30) {
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 180;
  options.frames = frames;
  options.seed = 5;
  options.supersampling = 1;
  return options;
}

}  // namespace tissuemosaic::testing
