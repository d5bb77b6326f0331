// A model point cloud (`eval --model`, `--start` clouds): readPly, then readPlyWholeFile (the check that runs
// before VTK's PLY reader).
#include "FuzzFile.h"
#include "IO/PointCloudPly.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("model.ply");
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readPly(path); });
  fuzz::expectOnlyErrors([&] { readPlyWholeFile(path); });
  return 0;
}
