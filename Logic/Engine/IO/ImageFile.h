#pragma once
/// @file ImageFile.h
/// @brief Image loading that fails loudly: cv::imread returns an empty Mat on any failure, these throw Error
/// saying whether the file is missing or unreadable.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <string>

namespace tissuemosaic {

/// The most pixels an image file may declare (8192 x 8192): beyond it is a broken or hostile file, refused before
/// decoding rather than ending in std::bad_alloc.
constexpr std::uint64_t kMaxImagePixels = 8192ull * 8192ull;

/// cv::imread(path, flags), but throws Error "cannot read image 'path': file does not exist" or "cannot read
/// image 'path': the file is not a readable image (corrupt or unsupported format)" instead of returning an empty Mat.
/// A truncated JPEG (which libjpeg decodes half grey with only a warning) and a header declaring more than
/// kMaxImagePixels are errors too.
cv::Mat loadImage(const std::string& path, int flags = cv::IMREAD_COLOR);

struct ImagePair {
  cv::Mat left, right;
};

/// Both images of a stereo pair (loadImage with the same flags); throws Error naming both sizes when they differ.
ImagePair loadImagePair(const std::string& leftPath, const std::string& rightPath, int flags = cv::IMREAD_COLOR);

}  // namespace tissuemosaic
