#pragma once
/// @file ModelFile.h
/// @brief A reconstructed model's file as `tissuemosaic reconstruct --out` and the Python module's save() write it:
/// binary PLY always, VTK XML poly data (.vtp, with the LPS mark) in builds with VTK. The library
/// TissueMosaicModelFile, which the command line and the Python module both link.
#include "Core/StereoRig.h"

#include <string>

namespace tissuemosaic {

/// The comment in the header of a reconstructed model's file (reconstruct, the Python module's save()).
inline const char* const kReconstructedModelComment =
    "TissueMosaic reconstruct: world frame = first left rectified camera, mm";
/// The header of the key-frame trajectory file (reconstruct --trajectory, the Python module's save()).
inline const char* const kKeyFrameTrajectoryHeader =
    "TissueMosaic reconstruct: key frames, T_world_camera of the left rectified camera, mm\n"
    "t tx ty tz qx qy qz qw";

/// Whether this build writes .vtp models (it has VTK).
bool modelFileVtpAvailable();
/// Throws ParameterError "modelPath" (Core/ParameterError.h), before any work is done, when the path's extension
/// cannot be written by this build or its folder cannot be written.
void checkModelOutputPath(const std::string& path);
/// Binary PLY (xyz, rgb, normals) or, for .vtp, VTK XML poly data with the LPS mark; the extension chooses.
void writeModelFile(const std::string& path, const ColoredPointCloud& model, const std::string& comment);

}  // namespace tissuemosaic
