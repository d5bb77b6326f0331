#pragma once
/// @file StereoFrameSource.h
/// @brief Stereo video input, frame by frame: two folders of frames (paired in file-name order), two videos, or one
/// 3D video in any StereoVideoLayout. A video is a file, a V4L2 device (/dev/videoN) or a GStreamer pipeline ending
/// in appsink; the last two are live: read at their own pace, the newest frame first, the frames the reconstruction
/// was too slow for dropped and counted (LiveVideoCapture). Corrupt or missing frames are reported as Error naming
/// the frame, never skipped silently.
#include "IO/StereoVideoLayout.h"

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
  /// A live source (capture device, pipeline, network stream): frames come at the source's pace and next() returns
  /// the newest one.
  virtual bool isLive() const { return false; }
  /// Live sources: frames that came but were never returned by next() because a newer one replaced them.
  virtual long long droppedFrames() const { return 0; }
  /// Makes a waiting and every later next() return false (a clean stop of a live source). Thread-safe.
  virtual void interrupt() {}

  /// Two folders of image files (PNG/JPEG/BMP/TIFF...), as many in each, paired in file-name order. fps gives the
  /// time stamps. Throws Error for a missing or empty folder or unequal counts.
  static std::unique_ptr<StereoFrameSource> openFrameFolders(const std::string& leftFolder, const std::string& rightFolder,
                                                             double fps);
  /// Two videos: files frame by frame in lock step (the shorter one ends the source), or two live inputs whose
  /// newest frames are paired.
  static std::unique_ptr<StereoFrameSource> openVideoPair(const std::string& leftVideo, const std::string& rightVideo);
  /// One 3D video (file or live) with both eyes in each frame as `layout` packs them.
  static std::unique_ptr<StereoFrameSource> openStereoVideo(const std::string& video, VideoLayout layout);
  /// openStereoVideo(video, VideoLayout::SideBySide).
  static std::unique_ptr<StereoFrameSource> openSideBySideVideo(const std::string& video);
};

}  // namespace tissuemosaic
