#pragma once
/// @file StereoFrameSource.h
/// @brief Stereo video input, frame by frame: two folders of frames (paired in file-name order), two video files,
/// or one side-by-side video (left half, right half). Corrupt or missing frames are reported as Error naming the
/// frame, never skipped silently.
#include <opencv2/core.hpp>

#include <memory>
#include <string>

namespace tissuemosaic {

struct StereoFrame {
  int index = 0;
  double timeS = 0;  ///< from the video's time stamps, else index / fps
  cv::Mat left, right;  ///< 8-bit BGR, same size
};

class StereoFrameSource {
public:
  virtual ~StereoFrameSource() = default;
  /// The next frame; false at the end. Throws Error for an unreadable frame or mismatched sizes.
  virtual bool next(StereoFrame& frame) = 0;
  /// Frames in the source (-1 when the container does not say).
  virtual int frameCount() const = 0;
  /// Size of one eye's frame.
  virtual cv::Size frameSize() const = 0;
  /// What was opened, for messages ("frames in DIR and DIR", "video FILE").
  virtual std::string description() const = 0;

  /// Two folders of image files (PNG/JPEG/BMP/TIFF...), as many in each, paired in file-name order. fps gives the
  /// time stamps. Throws Error for a missing or empty folder or unequal counts.
  static std::unique_ptr<StereoFrameSource> openFrameFolders(const std::string& leftFolder, const std::string& rightFolder,
                                                             double fps);
  /// Two video files (cv::VideoCapture), frame by frame in lock step; the shorter one ends the source.
  static std::unique_ptr<StereoFrameSource> openVideoPair(const std::string& leftVideo, const std::string& rightVideo);
  /// One side-by-side video: the left eye in the left half of each frame.
  static std::unique_ptr<StereoFrameSource> openSideBySideVideo(const std::string& video);
};

}  // namespace tissuemosaic
