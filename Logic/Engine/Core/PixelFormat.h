#pragma once
/// @file PixelFormat.h
/// @brief Conversions between the pixel formats the engine accepts. Kept apart from image file I/O so that code
/// which only converts (the pipeline, the benchmarks) does not pull in the image codecs.
#include <opencv2/core.hpp>

#include <string>

namespace tissuemosaic {

/// The order of a colour image's channels. The engine works in BGR (OpenCV's decoders give it); images from Python,
/// Pillow or PyTorch are RGB. The grey conversions below use the same weights for either (R 0.299, G 0.587,
/// B 0.114): an RGB image and its BGR twin give the same grey image bit for bit. A 4-channel image is BGRA or RGBA.
enum class ChannelOrder { Bgr, Rgb };

/// An 8-bit grey, BGR or BGRA image as 8-bit BGR (a BGR image is returned as it is, not copied). Throws Error
/// "<what> must be 8-bit grey, BGR or BGRA" for any other type.
cv::Mat toBgr8(const cv::Mat& image, const std::string& what);

/// An 8-bit grey, BGR or BGRA image (RGB or RGBA when `order` says so) as 8-bit grey in continuous memory (OpenCV's
/// weights; a continuous grey image is returned as it is, not copied). Throws Error naming `what` when the image is
/// empty or of any other type.
cv::Mat toGrey8(const cv::Mat& image, const std::string& what, ChannelOrder order = ChannelOrder::Bgr);

/// Throws Error "<what> is empty" or "<what> must be 8-bit grey, BGR or BGRA" unless toGrey8 can convert `image`.
void requireGrey8Convertible(const cv::Mat& image, const std::string& what);

/// The same conversion into `grey`: when it already has the image's size and type CV_8UC1 (say, a view of a staging
/// buffer) its memory is written, otherwise it is reallocated. Throws as toGrey8.
/// `bands` > 1: the rows in that many bands on the thread pool (the same pixels: the conversion is per pixel). One
/// thread converts about 10 GB/s of BGR, memory bound: 0.8 ms for a 1920x1080 image on an H100 host.
void convertToGrey8(const cv::Mat& image, cv::Mat& grey, const std::string& what, int bands = 1,
                    ChannelOrder order = ChannelOrder::Bgr);

/// An 8-bit colour image in `order` as 8-bit BGR in continuous memory: a continuous BGR image is returned as it is
/// (no copy), an RGB one converted, grey or 4-channel ones converted as toBgr8 does. Throws as toBgr8.
cv::Mat toContinuousBgr8(const cv::Mat& image, const std::string& what, ChannelOrder order);

}  // namespace tissuemosaic
