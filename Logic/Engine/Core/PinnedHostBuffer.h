#pragma once
/// @file PinnedHostBuffer.h
/// @brief Host memory to stage uploads in: page-locked for Device::Cuda, so that Buffer::uploadQueued copies
/// from it while the host goes on (a copy from ordinary memory is staged by the driver first); ordinary for the CPU.
/// Move-only, like Buffer; a buffer moved from is only to be destroyed or assigned.
#include "CudaRuntime.h"
#include "Device.h"

#include <cstddef>
#include <memory>

namespace tissuemosaic {

template <class T>
class PinnedHostBuffer {
public:
  PinnedHostBuffer() = default;
  PinnedHostBuffer(Device device, std::size_t count)
      : count_(count),
        data_(count == 0                  ? nullptr
              : device == Device::Cuda ? static_cast<T*>(cuda::allocatePinnedHost(count * sizeof(T)))
                                       : new T[count],
              Release{device}) {}

  std::size_t size() const { return count_; }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }

private:
  struct Release {
    Device device = Device::Cpu;
    void operator()(T* pointer) const noexcept {
      if (device == Device::Cuda) cuda::releasePinnedHost(pointer);
      else delete[] pointer;
    }
  };
  std::size_t count_ = 0;
  std::unique_ptr<T[], Release> data_;
};

}  // namespace tissuemosaic
