#include "IO/StereoInput.h"

#include "Core/Error.h"
#include "IO/StereoVideoLayout.h"

namespace tissuemosaic {

std::unique_ptr<StereoFrameSource> openStereoInput(const StereoInputPaths& paths) {
  require(paths.leftFrames.empty() == paths.rightFrames.empty(), "left and right frame folders go together");
  require(paths.leftVideo.empty() == paths.rightVideo.empty(), "left and right videos go together");
  require(paths.kindsGiven() == 1, "give exactly one input: two frame folders, two videos, or one 3D video");
  require(paths.layout == "sbs" || !paths.video.empty(), "the video layout applies to a 3D video only");
  const VideoLayout layout = parseVideoLayout(paths.layout);
  if (!paths.leftFrames.empty()) return StereoFrameSource::openFrameFolders(paths.leftFrames, paths.rightFrames, paths.fps);
  if (!paths.leftVideo.empty()) return StereoFrameSource::openVideoPair(paths.leftVideo, paths.rightVideo);
  return StereoFrameSource::openStereoVideo(paths.video, layout);
}

}  // namespace tissuemosaic
