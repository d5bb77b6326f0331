#pragma once
/// @file vtkTissueMosaicAnatomicalFrame.h
/// @brief LPS and RAS, the two axis conventions of medical files. Registration works in LPS throughout: ITK
/// transforms, DICOM and 3D Slicer's files (models since Slicer 4.11, markups, .tfm) are LPS; Slicer shows RAS.
#include <Eigen/Core>

#include <string>

namespace tissuemosaic {

/// The axis convention of coordinates stored in a file. LPS = +x left, +y posterior, +z superior; RAS flips x, y.
enum class AnatomicalFrame { LPS, RAS };

/// How to decide the frame of a model file: what the file declares (Slicer's "SPACE=LPS|RAS" header, PLY comment
/// or VTP field data "SPACE"; LPS when it declares nothing, as Slicer assumes), or an explicit override.
enum class ModelFrameChoice { FromFile, LPS, RAS };

/// "LPS" or "RAS".
const char* frameName(AnatomicalFrame frame);
/// Parses "lps"/"ras" (any case) for an explicit frame; throws Error naming the accepted words otherwise.
AnatomicalFrame parseFrame(const std::string& text);
/// Parses "file"/"lps"/"ras" (any case).
ModelFrameChoice parseModelFrameChoice(const std::string& text);

/// The LPS<->RAS flip diag(-1, -1, 1): its own inverse.
inline Eigen::Vector3d flipLpsRas(const Eigen::Vector3d& point) { return {-point.x(), -point.y(), point.z()}; }

/// A point given in `frame` expressed in LPS.
inline Eigen::Vector3d toLps(const Eigen::Vector3d& point, AnatomicalFrame frame) {
  return frame == AnatomicalFrame::LPS ? point : flipLpsRas(point);
}
/// An LPS point expressed in `frame`.
inline Eigen::Vector3d fromLps(const Eigen::Vector3d& pointLps, AnatomicalFrame frame) {
  return toLps(pointLps, frame);
}

}  // namespace tissuemosaic
