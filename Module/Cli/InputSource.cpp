// openInput (CommonOptions.h) in its own file: it opens videos and image files, and tissuemosaic-bench, which links
// the rest of CommonOptions, must link no codecs.
#include "CommonOptions.h"
#include "IgtLinkOptions.h"

#include "IO/StereoFrameSource.h"
#include "IO/StereoInput.h"
#include "IO/StereoVideoLayout.h"

namespace tissuemosaic::cli {

std::unique_ptr<StereoFrameSource> openInput(const InputOptions& input) {
  requireOneInput(input);
  if (!input.igtlInput.empty()) return openIgtLinkInput(input, parseVideoLayout(input.videoLayout));
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
