#pragma once
/// @file DisparityPfm.h
/// @brief Disparity maps as PFM files (Middlebury's format): "Pf" header, width height, scale (negative: little-
/// endian), then 32-bit floats stored bottom row first. NaN ("no estimate") is kept as NaN.
#include <opencv2/core.hpp>

#include <string>

namespace tissuemosaic {

/// Writes a non-empty CV_32FC1 map as a little-endian grey PFM (scale -1.0). Throws Error for another type or an
/// unwritable path.
void writePfm(const std::string& path, const cv::Mat& image);

/// Reads a PFM written by writePfm or any other tool: "Pf" (grey) gives CV_32FC1, "PF" (colour) gives CV_32FC3 in
/// the file's RGB order; either endianness. Row 0 of the result is the top of the image. Throws Error for a
/// missing, truncated or malformed file.
cv::Mat readPfm(const std::string& path);

}  // namespace tissuemosaic
