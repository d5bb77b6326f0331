#pragma once
/// @file StereoVideoLayout.h
/// @brief How a 3D video packs both eyes into one frame (docs/INPUT.md): side by side, squeezed side by side, top
/// bottom, squeezed top bottom, row-interlaced. Squeezed layouts carry each eye at half its width (height); they
/// are stretched back (bilinear) to the eye's full size, the size the rig was calibrated at.
#include <opencv2/core.hpp>

#include <string>

namespace tissuemosaic {

enum class VideoLayout {
  SideBySide,          ///< "sbs": left eye | right eye, each half the frame's width
  SideBySideHalf,      ///< "sbs-half": the same, each eye squeezed to half its width
  TopBottom,           ///< "tb": left eye above the right eye, each half the frame's height
  TopBottomHalf,       ///< "tb-half": the same, each eye squeezed to half its height
  RowInterlaced,       ///< "rows": even rows (0, 2, ...) the left eye, odd rows the right eye
};

/// "sbs", "sbs-half", "tb", "tb-half", "rows"; Error listing them for anything else.
VideoLayout parseVideoLayout(const std::string& name);
const char* videoLayoutName(VideoLayout layout);
/// Each eye's size in frames of `packedSize`; Error when the frame cannot hold two eyes (odd width or height).
cv::Size eyeSizeOf(const cv::Size& packedSize, VideoLayout layout);
/// The two eyes of one packed frame (copies, each eyeSizeOf(packed.size())).
void unpackStereoFrame(const cv::Mat& packed, VideoLayout layout, cv::Mat& left, cv::Mat& right);
/// The inverse (squeezed layouts average pairs of columns or rows, cv::INTER_AREA), for writers and tests.
cv::Mat packStereoFrame(const cv::Mat& left, const cv::Mat& right, VideoLayout layout);

}  // namespace tissuemosaic
