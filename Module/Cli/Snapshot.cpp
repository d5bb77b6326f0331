#include "Snapshot.h"

#include "Core/Error.h"
#include "Reconstruction/ReconstructionPipeline.h"

#if defined(TM_WITH_REGISTRATION)
#include "vtkTissueMosaicSnapshot.h"
#endif

namespace tissuemosaic::cli {

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
