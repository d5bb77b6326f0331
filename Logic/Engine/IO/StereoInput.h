#pragma once
/// @file StereoInput.h
/// @brief The stereo video inputs given by name (two frame folders, two videos, one 3D video in a layout), opened
/// as the command line and the Python module's frames() open them.
#include "IO/StereoFrameSource.h"

#include <memory>
#include <string>

namespace tissuemosaic {

struct StereoInputPaths {
  std::string leftFrames, rightFrames;  ///< two folders of frames, paired in file-name order
  std::string leftVideo, rightVideo;    ///< two videos (files, V4L2 devices or GStreamer pipelines)
  std::string video;                    ///< one 3D video with both eyes in each frame
  std::string layout = "sbs";           ///< how `video` packs the eyes (StereoVideoLayout.h)
  double fps = 30;                      ///< time stamps of frame folders (videos carry their own)
  /// How many of the three kinds are given (the caller requires one; the command line adds OpenIGTLink).
  int kindsGiven() const { return !leftFrames.empty() + !leftVideo.empty() + !video.empty(); }
};

/// Opens the one input given. Throws Error when none or several kinds are given, when a pair lacks its second half,
/// for a layout other than sbs without `video`, and for whatever the source cannot open.
std::unique_ptr<StereoFrameSource> openStereoInput(const StereoInputPaths& paths);

}  // namespace tissuemosaic
