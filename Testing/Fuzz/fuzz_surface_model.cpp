// A surface model (`register --model/--target`, `eval --reference`, the app's model loader) through
// readSurfaceModel. Built once per extension (TM_FUZZ_EXTENSION: .stl .obj .vtp .vtk .ply), since the reader
// dispatches on it.
#include "FuzzFile.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <vtkObject.h>

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file(std::string("model") + TM_FUZZ_EXTENSION);
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readSurfaceModel(path, ModelFrameChoice::FromFile); });
  return 0;
}
