#include "ModelFile.h"

#include "Core/ParameterError.h"
#include "IO/AtomicFile.h"
#include "IO/PointCloudPly.h"

#if defined(TM_MODEL_FILE_WITH_VTK)
#include "vtkTissueMosaicPointCloud.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <vtkPolyData.h>
#endif

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace tissuemosaic {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

}  // namespace

bool modelFileVtpAvailable() {
#if defined(TM_MODEL_FILE_WITH_VTK)
  return true;
#else
  return false;
#endif
}

void checkModelOutputPath(const std::string& path) {
  const std::string extension = lowerExtension(path);
  requireParameter(extension == ".ply" || extension == ".vtp", "modelPath",
                   "'" + path + "': the model is written as .ply or .vtp (the name's extension chooses)");
  requireParameter(extension == ".ply" || modelFileVtpAvailable(), "modelPath",
                   "'" + path + "': this build has no VTK, so it writes .ply only");
  try {
    requireWritableOutput(path, "model");
  } catch (const Error& e) {
    throw ParameterError("modelPath", e.what());
  }
}

void writeModelFile(const std::string& path, const ColoredPointCloud& model, const std::string& comment) {
  if (lowerExtension(path) == ".ply") {
    writePly(path, model, comment);
    return;
  }
#if defined(TM_MODEL_FILE_WITH_VTK)
  writeSurfaceModel(path, pointCloudToPolyData(model));
#else
  throw ParameterError("modelPath", "'" + path + "': this build has no VTK: write the model as .ply");
#endif
}

}  // namespace tissuemosaic
