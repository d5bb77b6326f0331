// A Slicer landmark file (`register --landmarks`, `--model-landmarks`) through readLandmarkFile, then pairing as
// `register --landmarks` does when it holds two lists. Built once per extension (TM_FUZZ_EXTENSION: .mrk.json,
// .fcsv).
#include "FuzzFile.h"
#include "vtkTissueMosaicLandmarksFile.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file(std::string("landmarks") + TM_FUZZ_EXTENSION);
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] {
    const std::vector<LandmarkList> lists = readLandmarkFile(path, AnatomicalFrame::LPS);
    if (lists.size() == 2) pairLandmarks(lists[0], lists[1]);
  });
  fuzz::expectOnlyErrors([&] { readLandmarkFile(path); });
  return 0;
}
