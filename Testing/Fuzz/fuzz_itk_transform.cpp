// An ITK/Slicer transform file (`register --initial-transform FILE.tfm`) through readModelToTargetTransform.
#include "FuzzFile.h"
#include "vtkTissueMosaicItkTransformFile.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("transform.tfm");
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readModelToTargetTransform(path); });
  return 0;
}
