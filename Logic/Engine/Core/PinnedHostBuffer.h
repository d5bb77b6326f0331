#pragma once
/// @file PinnedHostBuffer.h
/// @brief Host memory to stage uploads in: page-locked for Device::Cuda, so that Buffer::uploadPinnedQueued copies
/// from it while the host goes on (a copy from ordinary memory is staged by the driver first); ordinary for the CPU.
#include "CudaRuntime.h"
#include "Device.h"

#include <cstddef>
#include <utility>

namespace tissuemosaic {

template <class T>
class PinnedHostBuffer {
public:
  PinnedHostBuffer() = default;
  PinnedHostBuffer(Device device, std::size_t count) : device_(device), count_(count) {
    if (count == 0) return;
    data_ = device == Device::Cuda ? static_cast<T*>(cuda::allocatePinnedHost(count * sizeof(T))) : new T[count];
  }
  ~PinnedHostBuffer() { reset(); }
  PinnedHostBuffer(const PinnedHostBuffer&) = delete;
  PinnedHostBuffer& operator=(const PinnedHostBuffer&) = delete;
  PinnedHostBuffer(PinnedHostBuffer&& other) noexcept { swap(other); }
  PinnedHostBuffer& operator=(PinnedHostBuffer&& other) noexcept {
    if (this != &other) {
      reset();
      swap(other);
    }
    return *this;
  }

  std::size_t size() const { return count_; }
  T* data() { return data_; }
  const T* data() const { return data_; }

private:
  void reset() {
    if (device_ == Device::Cuda) cuda::releasePinnedHost(data_);
    else delete[] data_;
    data_ = nullptr;
    count_ = 0;
  }
  void swap(PinnedHostBuffer& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(data_, other.data_);
    std::swap(count_, other.count_);
  }

  Device device_ = Device::Cpu;
  T* data_ = nullptr;
  std::size_t count_ = 0;
};

}  // namespace tissuemosaic
