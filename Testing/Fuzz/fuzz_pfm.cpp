// A disparity map (`stereo --ground-truth FILE.pfm`) through readPfm.
#include "FuzzFile.h"
#include "IO/DisparityPfm.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("disparity.pfm");
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readPfm(path); });
  return 0;
}
