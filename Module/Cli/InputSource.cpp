// openInput (CommonOptions.h) in its own file: it opens videos and image files, and tissuemosaic-bench, which links
// the rest of CommonOptions, must link no codecs.
#include "CommonOptions.h"
#include "IgtLinkOptions.h"

#include "IO/StereoFrameSource.h"
#include "IO/StereoInput.h"
#include "IO/StereoVideoLayout.h"

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
  if (igtl) return openIgtLinkInput(input, parseVideoLayout(input.videoLayout));
  StereoInputPaths paths;
  paths.leftFrames = input.leftFrames;
  paths.rightFrames = input.rightFrames;
  paths.leftVideo = input.leftVideo;
  paths.rightVideo = input.rightVideo;
  paths.video = input.video;
  paths.layout = input.videoLayout;
  paths.fps = input.fps;
  return openStereoInput(paths);
}

}  // namespace tissuemosaic::cli
