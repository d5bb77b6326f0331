#pragma once
/// @file ModelOutput.h
/// @brief Writing a reconstructed model (.ply always; .vtp and offscreen snapshots in builds with VTK).
#include "Core/StereoRig.h"

#include <string>

namespace tissuemosaic {
class ReconstructionPipeline;
}

namespace tissuemosaic::cli {

/// The comment in the header of a reconstructed model's file (reconstruct, the Python module's save()).
inline const char* const kReconstructedModelComment =
    "TissueMosaic reconstruct: world frame = first left rectified camera, mm";
/// The header of the key-frame trajectory file (reconstruct --trajectory, the Python module's save()).
inline const char* const kKeyFrameTrajectoryHeader =
    "TissueMosaic reconstruct: key frames, T_world_camera of the left rectified camera, mm\n"
    "t tx ty tz qx qy qz qw";

/// Throws Error, before any work is done, when the model path's extension cannot be written by this build.
void checkModelOutputPath(const std::string& path);
/// Binary PLY (xyz, rgb, normals) or, for .vtp, VTK XML poly data with the LPS mark.
void writeModelFile(const std::string& path, const ColoredPointCloud& model, const std::string& comment);
/// Throws Error, before any work is done, when this build cannot render snapshots.
void checkSnapshotAvailable();
/// Renders the pipeline's model, key-frame frusta and camera path offscreen into a PNG (a private Xvfb when there
/// is no display); returns a line for the log (what was drawn, the renderer).
std::string renderSnapshot(const std::string& path, const ReconstructionPipeline& pipeline);

}  // namespace tissuemosaic::cli
