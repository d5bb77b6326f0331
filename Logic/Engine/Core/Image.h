#pragma once
/// @file Image.h
/// @brief Images for both backends: ImageView is a plain, copyable window onto pixels that kernels capture by
/// value; Image owns a contiguous width x height buffer on one device.
#include "Buffer.h"
#include "HostDevice.h"

#include <cstdint>
#include <type_traits>

namespace tissuemosaic {

template <class T>
struct ImageView {
  T* data = nullptr;
  int width = 0;
  int height = 0;

  /// A view of mutable pixels converts to a read-only view.
  template <class U = T, std::enable_if_t<!std::is_const_v<U>, int> = 0>
  TM_HOST_DEVICE operator ImageView<const U>() const {
    return {data, width, height};
  }

  TM_HOST_DEVICE T& at(int x, int y) const { return data[static_cast<int64_t>(y) * width + x]; }
  TM_HOST_DEVICE T& operator[](int64_t index) const { return data[index]; }
  /// Pixel with coordinates clamped to the image (replicated border).
  TM_HOST_DEVICE T clamped(int x, int y) const {
    x = x < 0 ? 0 : (x >= width ? width - 1 : x);
    y = y < 0 ? 0 : (y >= height ? height - 1 : y);
    return at(x, y);
  }
  TM_HOST_DEVICE int64_t pixelCount() const { return static_cast<int64_t>(width) * height; }
  TM_HOST_DEVICE bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

template <class T>
class Image {
public:
  Image() = default;
  Image(Device device, int width, int height)
      : buffer_(device, static_cast<std::size_t>(width) * static_cast<std::size_t>(height)), width_(width), height_(height) {}

  int width() const { return width_; }
  int height() const { return height_; }
  Device device() const { return buffer_.device(); }
  ImageView<T> view() { return {buffer_.data(), width_, height_}; }
  ImageView<const T> view() const { return {buffer_.data(), width_, height_}; }
  Buffer<T>& buffer() { return buffer_; }
  const Buffer<T>& buffer() const { return buffer_; }

private:
  Buffer<T> buffer_;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace tissuemosaic
