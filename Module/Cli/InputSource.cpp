// openInput (CommonOptions.h) in its own file: it opens videos and image files, and tissuemosaic-bench, which links
// the rest of CommonOptions, must link no codecs.
#include "CommonOptions.h"

#include "IO/StereoFrameSource.h"

namespace tissuemosaic::cli {

std::unique_ptr<StereoFrameSource> openInput(const InputOptions& input) {
  const bool folders = !input.leftFrames.empty();
  const bool videos = !input.leftVideo.empty();
  const bool sideBySide = !input.video.empty();
  if (folders + videos + sideBySide != 1) {
    throw UsageError("give exactly one input: --left-frames DIR --right-frames DIR, --left-video L --right-video R, "
                     "or --video SBS");
  }
  if (folders) return StereoFrameSource::openFrameFolders(input.leftFrames, input.rightFrames, input.fps);
  if (videos) return StereoFrameSource::openVideoPair(input.leftVideo, input.rightVideo);
  return StereoFrameSource::openSideBySideVideo(input.video);
}

}  // namespace tissuemosaic::cli
