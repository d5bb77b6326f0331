#include "IO/StereoVideoLayout.h"

#include "Core/Error.h"

#include <opencv2/imgproc.hpp>

namespace tissuemosaic {
namespace {

struct LayoutName {
  VideoLayout layout;
  const char* name;
};
constexpr LayoutName kNames[] = {{VideoLayout::SideBySide, "sbs"},
                                 {VideoLayout::SideBySideHalf, "sbs-half"},
                                 {VideoLayout::TopBottom, "tb"},
                                 {VideoLayout::TopBottomHalf, "tb-half"},
                                 {VideoLayout::RowInterlaced, "rows"}};

bool splitsColumns(VideoLayout layout) {
  return layout == VideoLayout::SideBySide || layout == VideoLayout::SideBySideHalf;
}
bool squeezed(VideoLayout layout) {
  return layout == VideoLayout::SideBySideHalf || layout == VideoLayout::TopBottomHalf;
}

/// Rows 0, 2, 4... (first = 0) or 1, 3, 5... (first = 1) of `image`.
cv::Mat everyOtherRow(const cv::Mat& image, int first) {
  cv::Mat rows(image.rows / 2, image.cols, image.type());
  for (int y = 0; y < rows.rows; ++y) image.row(2 * y + first).copyTo(rows.row(y));
  return rows;
}

}  // namespace

VideoLayout parseVideoLayout(const std::string& name) {
  for (const LayoutName& entry : kNames)
    if (name == entry.name) return entry.layout;
  throw Error("unknown video layout '" + name + "': expected sbs, sbs-half, tb, tb-half or rows");
}

const char* videoLayoutName(VideoLayout layout) {
  for (const LayoutName& entry : kNames)
    if (layout == entry.layout) return entry.name;
  return "?";
}

cv::Size eyeSizeOf(const cv::Size& packedSize, VideoLayout layout) {
  const std::string what = std::string("a '") + videoLayoutName(layout) + "' frame of " +
                           std::to_string(packedSize.width) + "x" + std::to_string(packedSize.height);
  if (splitsColumns(layout)) {
    require(packedSize.width >= 2 && packedSize.width % 2 == 0,
            what + " cannot hold two eyes: the width must be even (left eye | right eye)");
    return squeezed(layout) ? packedSize : cv::Size(packedSize.width / 2, packedSize.height);
  }
  require(packedSize.height >= 2 && packedSize.height % 2 == 0, what + " cannot hold two eyes: the height must be even");
  return layout == VideoLayout::TopBottomHalf ? packedSize : cv::Size(packedSize.width, packedSize.height / 2);
}

void unpackStereoFrame(const cv::Mat& packed, VideoLayout layout, cv::Mat& left, cv::Mat& right) {
  const cv::Size eye = eyeSizeOf(packed.size(), layout);
  const int halfWidth = packed.cols / 2, halfHeight = packed.rows / 2;
  cv::Mat a, b;
  switch (layout) {
    case VideoLayout::SideBySide:
    case VideoLayout::SideBySideHalf:
      a = packed(cv::Rect(0, 0, halfWidth, packed.rows));
      b = packed(cv::Rect(halfWidth, 0, halfWidth, packed.rows));
      break;
    case VideoLayout::TopBottom:
    case VideoLayout::TopBottomHalf:
      a = packed(cv::Rect(0, 0, packed.cols, halfHeight));
      b = packed(cv::Rect(0, halfHeight, packed.cols, halfHeight));
      break;
    case VideoLayout::RowInterlaced:
      a = everyOtherRow(packed, 0);
      b = everyOtherRow(packed, 1);
      break;
  }
  if (squeezed(layout)) {
    cv::resize(a, left, eye, 0, 0, cv::INTER_LINEAR);
    cv::resize(b, right, eye, 0, 0, cv::INTER_LINEAR);
  } else {
    left = a.clone();
    right = b.clone();
  }
}

cv::Mat packStereoFrame(const cv::Mat& left, const cv::Mat& right, VideoLayout layout) {
  require(!left.empty() && left.size() == right.size() && left.type() == right.type(),
          "packStereoFrame: the eyes must be non-empty images of one size and type");
  cv::Mat a = left, b = right, packed;
  if (layout == VideoLayout::SideBySideHalf) {
    require(left.cols % 2 == 0, "packStereoFrame: a squeezed side-by-side eye needs an even width");
    cv::resize(left, a, cv::Size(left.cols / 2, left.rows), 0, 0, cv::INTER_AREA);
    cv::resize(right, b, cv::Size(left.cols / 2, left.rows), 0, 0, cv::INTER_AREA);
  } else if (layout == VideoLayout::TopBottomHalf) {
    require(left.rows % 2 == 0, "packStereoFrame: a squeezed top-bottom eye needs an even height");
    cv::resize(left, a, cv::Size(left.cols, left.rows / 2), 0, 0, cv::INTER_AREA);
    cv::resize(right, b, cv::Size(left.cols, left.rows / 2), 0, 0, cv::INTER_AREA);
  }
  if (splitsColumns(layout)) {
    cv::hconcat(a, b, packed);
  } else if (layout == VideoLayout::RowInterlaced) {
    packed.create(2 * left.rows, left.cols, left.type());
    for (int y = 0; y < left.rows; ++y) {
      left.row(y).copyTo(packed.row(2 * y));
      right.row(y).copyTo(packed.row(2 * y + 1));
    }
  } else {
    cv::vconcat(a, b, packed);
  }
  return packed;
}

}  // namespace tissuemosaic
