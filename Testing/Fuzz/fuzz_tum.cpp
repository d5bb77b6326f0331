// A TUM trajectory (`track --ground-truth`, `--start-tum`, `eval --trajectory`) through readTumTrajectory.
#include "FuzzFile.h"
#include "IO/TrajectoryTum.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("trajectory.txt");
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readTumTrajectory(path); });
  return 0;
}
