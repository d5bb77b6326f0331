// A frame file (`stereo --left`, frame folders): loadImage's checks before decoding (declared PNG/JPEG size,
// JPEG end marker) and OpenCV's decoders behind them.
#include "FuzzFile.h"
#include "IO/ImageFile.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("frame.png");
  fuzz::quietOpenCv();
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { loadImage(path); });
  return 0;
}
