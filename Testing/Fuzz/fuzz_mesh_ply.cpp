// A triangle mesh PLY (`eval --reference mesh.ply`, ground-truth surfaces) through readMeshPly.
#include "FuzzFile.h"
#include "IO/MeshPly.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("mesh.ply");
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readMeshPly(path); });
  return 0;
}
