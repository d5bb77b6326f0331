#include "ModelOutput.h"

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/PointCloudPly.h"
#include "Reconstruction/ReconstructionPipeline.h"

#if defined(TM_WITH_REGISTRATION)
#include "vtkTissueMosaicPointCloud.h"
#include "vtkTissueMosaicSnapshot.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <vtkPolyData.h>
#endif

#include <algorithm>
#include <filesystem>

namespace tissuemosaic::cli {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

}  // namespace

void checkModelOutputPath(const std::string& path) {
  const std::string extension = lowerExtension(path);
  require(extension == ".ply" || extension == ".vtp",
          "--out '" + path + "': the model is written as .ply or .vtp (the name's extension chooses)");
#if !defined(TM_WITH_REGISTRATION)
  require(extension == ".ply", "--out '" + path + "': this build has no VTK, so it writes .ply only");
#endif
  requireWritableOutput(path, "model (--out)");
}

void writeModelFile(const std::string& path, const ColoredPointCloud& model, const std::string& comment) {
  if (lowerExtension(path) == ".ply") {
    writePly(path, model, comment);
    return;
  }
#if defined(TM_WITH_REGISTRATION)
  writeSurfaceModel(path, pointCloudToPolyData(model));
#else
  throw Error("this build has no VTK: write the model as .ply");
#endif
}

void checkSnapshotAvailable() {
#if !defined(TM_WITH_REGISTRATION)
  throw Error("--snapshot needs a build with VTK (configure with -DTM_WITH_GUI=ON)");
#endif
}

std::string renderSnapshot(const std::string& path, const ReconstructionPipeline& pipeline) {
#if defined(TM_WITH_REGISTRATION)
  const SnapshotReport report = writeReconstructionSnapshotPng(path, pipeline);
  return "snapshot: " + std::to_string(report.modelPoints) + " points, " + std::to_string(report.keyFrames) +
         " key-frame frusta -> " + path + " (renderer " + report.renderer + "; " + report.display + ")";
#else
  (void)path, (void)pipeline;
  checkSnapshotAvailable();
  return {};
#endif
}

}  // namespace tissuemosaic::cli
