#pragma once
/// @file Buffer.h
/// @brief A typed, owning, move-only array in host or CUDA device memory.
#include "CudaRuntime.h"
#include "Device.h"
#include "Error.h"
#include "HostMemory.h"

#include <cstddef>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

namespace tissuemosaic {

template <class T>
class Buffer {
public:
  Buffer() = default;
  /// `pages` applies on the CPU and to plain-data element types (HostPages).
  Buffer(Device device, std::size_t count, HostPages pages = HostPages::Normal)
      : device_(device), count_(count), hugePages_(pages == HostPages::Huge && kPlainData && device == Device::Cpu) {
    if (count == 0) return;
    if (device == Device::Cuda) data_ = static_cast<T*>(cuda::allocate(count * sizeof(T)));
    else if (hugePages_) data_ = static_cast<T*>(allocateHugePageMemory(count * sizeof(T)));
    else data_ = new T[count];
  }
  ~Buffer() { reset(); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& other) noexcept { swap(other); }
  Buffer& operator=(Buffer&& other) noexcept {
    if (this != &other) {
      reset();
      swap(other);
    }
    return *this;
  }

  Device device() const { return device_; }
  std::size_t size() const { return count_; }
  T* data() { return data_; }
  const T* data() const { return data_; }

  /// Copies count_ elements from host memory into this buffer.
  void upload(const T* host) {
    if (device_ == Device::Cuda) cuda::copyHostToDevice(data_, host, count_ * sizeof(T));
    else if (count_) std::memcpy(data_, host, count_ * sizeof(T));
  }
  /// As upload, but on CUDA queued on the calling thread's stream without waiting for the device: only the calling
  /// thread's later work is sure to see the data. Pageable `host` may be reused at once; page-locked `host` (a
  /// PinnedHostBuffer's) is read after the call returns and must not change until the thread's work has finished
  /// (cuda::copyHostToDeviceQueued).
  void uploadQueued(const T* host) {
    if (device_ == Device::Cuda) cuda::copyHostToDeviceQueued(data_, host, count_ * sizeof(T));
    else if (count_) std::memcpy(data_, host, count_ * sizeof(T));
  }
  /// Copies this buffer's elements into host memory.
  void download(T* host) const {
    if (device_ == Device::Cuda) cuda::copyDeviceToHost(host, data_, count_ * sizeof(T));
    else if (count_) std::memcpy(host, data_, count_ * sizeof(T));
  }
  /// Copies `count` host elements into this buffer from element `offset` on.
  void uploadPart(const T* host, std::size_t count, std::size_t offset = 0) {
    require(offset + count <= count_, "Buffer::uploadPart: beyond the end of the buffer");
    if (device_ == Device::Cuda) cuda::copyHostToDevice(data_ + offset, host, count * sizeof(T));
    else if (count) std::memcpy(data_ + offset, host, count * sizeof(T));
  }
  /// Copies the first `count` elements of this buffer into host memory.
  void downloadPart(T* host, std::size_t count) const {
    require(count <= count_, "Buffer::downloadPart: beyond the end of the buffer");
    if (device_ == Device::Cuda) cuda::copyDeviceToHost(host, data_, count * sizeof(T));
    else if (count) std::memcpy(host, data_, count * sizeof(T));
  }
  std::vector<T> toHost() const {
    std::vector<T> host(count_);
    download(host.data());
    return host;
  }
  /// Sets every byte to zero.
  void setZero() {
    if (device_ == Device::Cuda) cuda::setZero(data_, count_ * sizeof(T));
    else if (count_) std::memset(static_cast<void*>(data_), 0, count_ * sizeof(T));
  }
  /// Copies another buffer of the same size (any device) into this one.
  void copyFrom(const Buffer& other) {
    require(other.count_ == count_, "Buffer::copyFrom: sizes differ");
    if (count_ == 0) return;
    if (device_ == Device::Cuda && other.device_ == Device::Cuda) cuda::copyDeviceToDevice(data_, other.data_, count_ * sizeof(T));
    else if (device_ == Device::Cuda) cuda::copyHostToDevice(data_, other.data_, count_ * sizeof(T));
    else other.download(data_);
  }

private:
  /// Element types that need no construction or destruction may live in a huge-page mapping (left uninitialised,
  /// as new T[] leaves them).
  static constexpr bool kPlainData = std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>;

  void reset() {
    if (device_ == Device::Cuda) cuda::release(data_);
    else if (hugePages_) releaseHugePageMemory(data_, count_ * sizeof(T));
    else delete[] data_;
    data_ = nullptr;
    count_ = 0;
    hugePages_ = false;
  }
  void swap(Buffer& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(data_, other.data_);
    std::swap(count_, other.count_);
    std::swap(hugePages_, other.hugePages_);
  }

  Device device_ = Device::Cpu;
  T* data_ = nullptr;
  std::size_t count_ = 0;
  bool hugePages_ = false;
};

/// Grows `buffer` to hold at least `count` elements on `device`, with a quarter to spare; never shrinks, so that
/// per-frame calls reuse it. The contents are lost when it grows.
template <class T>
void reserveBuffer(Buffer<T>& buffer, Device device, std::size_t count) {
  if (buffer.size() < count || buffer.device() != device) buffer = Buffer<T>(device, count + count / 4);
}

}  // namespace tissuemosaic
