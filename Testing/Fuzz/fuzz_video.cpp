// A side-by-side stereo video (`--video FILE`): the checks when it opens (empty file, container, eye size) and
// while its frames are read (declared frame count, frame size), at most 4 frames.
#include "FuzzFile.h"
#include "IO/StereoFrameSource.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("video.avi");
  fuzz::quietOpenCv();
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] {
    const auto source = StereoFrameSource::openSideBySideVideo(path);
    StereoFrame frame;
    for (int i = 0; i < 4 && source->next(frame); ++i) {
    }
  });
  return 0;
}
