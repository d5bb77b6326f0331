#pragma once
/// @file HamlynRectified.h
/// @brief A rectified sequence of the Hamlyn Centre's endoscopic video data as the rectified release ships it
/// (rectifiedNN/: image01/ the left frames, image02/ the right ones, paired in file-name order, and intrinsics.txt
/// with the rectified camera matrix, 3x3, or 3x4 whose fourth column may hold the baseline as -f B). The folder may
/// also be the release's doubled rectifiedNN/rectifiedNN. docs/INPUT.md.
#include <optional>
#include <string>

namespace tissuemosaic {

struct HamlynRectified {
  std::string leftFolder, rightFolder;  ///< image01, image02
  double focalPx = 0, cxPx = 0, cyPx = 0;
  std::optional<double> baselineMm;  ///< from a 3x4 matrix's -f B; otherwise the user gives it
};

/// Reads the folder. Throws Error naming the part that is missing or unreadable.
HamlynRectified readHamlynRectified(const std::string& folder);

}  // namespace tissuemosaic
