#pragma once
/// @file vtkTissueMosaicLandmarksFile.h
/// @brief Landmark (fiducial) lists in 3D Slicer's files: markups JSON (.mrk.json, "markups" -> "controlPoints"
/// -> "position", frame in "coordinateSystem") and the older markups CSV (.fcsv, frame in a
/// "# CoordinateSystem = LPS|RAS|0|1" header line). In memory, positions are LPS millimetres.
#include "vtkTissueMosaicAnatomicalFrame.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace tissuemosaic {

struct Landmark {
  std::string label;
  Eigen::Vector3d positionLps = Eigen::Vector3d::Zero();
};

/// One markups node: a named, ordered list of points.
struct LandmarkList {
  std::string name;
  std::vector<Landmark> points;
  AnatomicalFrame fileFrame = AnatomicalFrame::LPS;  ///< the frame the file held the positions in
};

/// Every markups node of a .mrk.json file, or the one list of an .fcsv file (by extension). Points whose
/// "positionStatus" is "missing" are skipped. A file that declares no frame is read in `frameIfUndeclared`;
/// without it, such a file is an Error (no guessing). Throws Error for missing or malformed files.
std::vector<LandmarkList> readLandmarkFile(const std::string& path,
                                           std::optional<AnatomicalFrame> frameIfUndeclared = std::nullopt);

/// The single list of a landmark file; Error when the file holds no list or several.
LandmarkList readLandmarks(const std::string& path, std::optional<AnatomicalFrame> frameIfUndeclared = std::nullopt);

/// Writes lists as .mrk.json (one markups node per list, Slicer's fiducial schema) or .fcsv (exactly one list),
/// positions in `fileFrame`, the frame declared in the file. Throws Error when the file cannot be written.
void writeLandmarkFile(const std::string& path, const std::vector<LandmarkList>& lists,
                       AnatomicalFrame fileFrame = AnatomicalFrame::LPS);

/// Corresponding points of the model and target lists, in the model list's order.
struct LandmarkPairs {
  std::vector<std::string> labels;
  std::vector<Eigen::Vector3d> modelLps;
  std::vector<Eigen::Vector3d> targetLps;
  bool pairedByLabel = false;
};

/// Pairs by label when both lists have unique, non-empty labels and the same label set; otherwise by order when
/// the lists are equally long; otherwise throws Error explaining the mismatch.
LandmarkPairs pairLandmarks(const LandmarkList& model, const LandmarkList& target);

/// The pairs of a single file: a .mrk.json with exactly two markups nodes, the model's first, the target's second.
LandmarkPairs readLandmarkPairs(const std::string& path,
                                std::optional<AnatomicalFrame> frameIfUndeclared = std::nullopt);

}  // namespace tissuemosaic
