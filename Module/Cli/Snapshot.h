#pragma once
/// @file Snapshot.h
/// @brief `reconstruct --snapshot`: the model rendered offscreen into a PNG, in builds with VTK. (The model file
/// itself is Logic/ModelFile, shared with the Python module.)
#include <string>

namespace tissuemosaic {
class ReconstructionPipeline;
}

namespace tissuemosaic::cli {

/// Throws Error, before any work is done, when this build cannot render snapshots.
void checkSnapshotAvailable();
/// Renders the pipeline's model, key-frame frusta and camera path offscreen into a PNG (a private Xvfb when there
/// is no display); returns a line for the log (what was drawn, the renderer).
std::string renderSnapshot(const std::string& path, const ReconstructionPipeline& pipeline);

}  // namespace tissuemosaic::cli
