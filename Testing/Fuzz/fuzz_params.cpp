// A parameters file (`--params FILE`, the app's preset loader) through the strict reader: unknown nodes and keys,
// wrong types and out-of-range values must all be Errors.
#include "FuzzFile.h"
#include "Reconstruction/ReconstructionParameters.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("params.yaml");
  fuzz::quietOpenCv();
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { ReconstructionParameters::readFile(path).validate(); });
  return 0;
}
