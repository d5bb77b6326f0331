// openInput (CommonOptions.h) in its own file: it opens videos and image files, and tissuemosaic-bench, which links
// the rest of CommonOptions, must link no codecs.
#include "CommonOptions.h"
#include "IgtLinkOptions.h"

#include "IO/StereoFrameSource.h"

namespace tissuemosaic::cli {

std::unique_ptr<StereoFrameSource> openInput(const InputOptions& input) {
  const bool folders = !input.leftFrames.empty();
  const bool videos = !input.leftVideo.empty();
  const bool packed = !input.video.empty();
  const bool igtl = !input.igtlInput.empty();
  if (folders + videos + packed + igtl != 1) {
    throw UsageError("give exactly one input: --left-frames DIR --right-frames DIR, --left-video L --right-video R, "
                     "--video V, or --igtl-input HOST:PORT");
  }
  if (input.videoLayout != "sbs" && !packed && input.igtlSbs.empty()) {
    throw UsageError("--video-layout applies to --video and --igtl-sbs");
  }
  const VideoLayout layout = parseVideoLayout(input.videoLayout);
  if (folders) return StereoFrameSource::openFrameFolders(input.leftFrames, input.rightFrames, input.fps);
  if (videos) return StereoFrameSource::openVideoPair(input.leftVideo, input.rightVideo);
  if (igtl) return openIgtLinkInput(input, layout);
  return StereoFrameSource::openStereoVideo(input.video, layout);
}

}  // namespace tissuemosaic::cli
