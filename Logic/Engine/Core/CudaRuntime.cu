#include "CudaRuntime.h"

#include "Error.h"

#include <cuda_runtime.h>

#include <cstdint>

namespace tissuemosaic::cuda {

namespace {
void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw Error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(status));
}
}  // namespace

bool compiledIn() { return true; }

std::string deviceProblem() {
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) return std::string("no usable CUDA device (") + cudaGetErrorString(status) + ")";
  if (count == 0) return "no CUDA device is present";
  return {};
}

std::string deviceName() {
  cudaDeviceProp properties{};
  check(cudaGetDeviceProperties(&properties, 0), "cudaGetDeviceProperties");
  return properties.name;
}

int multiprocessorCount() {
  static const int count = [] {
    int device = 0, value = 0;
    check(cudaGetDevice(&device), "cudaGetDevice");
    check(cudaDeviceGetAttribute(&value, cudaDevAttrMultiProcessorCount, device), "cudaDeviceGetAttribute");
    return value;
  }();
  return count;
}

std::size_t deviceBytesInUse() {
  std::size_t freeBytes = 0, totalBytes = 0;
  check(cudaMemGetInfo(&freeBytes, &totalBytes), "cudaMemGetInfo");
  return totalBytes - freeBytes;
}

namespace {

/// Whether the device has stream-ordered memory pools; when it has, the default pool keeps up to 256 MiB of what is
/// freed, so that the per-key-frame buffers (surface maps, solver arrays: about 20 MB) are taken from it again rather
/// than from the driver, while the model's outgrown arrays still go back at the next synchronisation.
bool useMemoryPool() {
  static const bool pooled = [] {
    int device = 0, supported = 0;
    if (cudaGetDevice(&device) != cudaSuccess) return false;
    if (cudaDeviceGetAttribute(&supported, cudaDevAttrMemoryPoolsSupported, device) != cudaSuccess || !supported) {
      return false;
    }
    cudaMemPool_t pool = nullptr;
    if (cudaDeviceGetDefaultMemPool(&pool, device) != cudaSuccess) return false;
    uint64_t keptBytes = 256ull << 20;
    return cudaMemPoolSetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &keptBytes) == cudaSuccess;
  }();
  return pooled;
}

}  // namespace

// Stream-ordered on the calling thread's stream: neither call waits for the device, so a buffer allocated or freed
// on one thread does not stall the work another thread has queued (cudaMalloc and cudaFree would). A buffer handed to
// another thread is handed over after synchronize(), as all device data is.
void* allocate(std::size_t bytes) {
  void* pointer = nullptr;
  if (bytes == 0) return nullptr;
  if (useMemoryPool()) check(cudaMallocAsync(&pointer, bytes, cudaStreamPerThread), "cudaMallocAsync");
  else check(cudaMalloc(&pointer, bytes), "cudaMalloc");
  return pointer;
}

void release(void* pointer) noexcept {
  if (!pointer) return;
  if (useMemoryPool()) cudaFreeAsync(pointer, cudaStreamPerThread);
  else cudaFree(pointer);
}

void copyHostToDevice(void* device, const void* host, std::size_t bytes) {
  if (bytes) check(cudaMemcpy(device, host, bytes, cudaMemcpyHostToDevice), "cudaMemcpy host to device");
}
void copyHostToDeviceQueued(void* device, const void* host, std::size_t bytes) {
  if (bytes) {
    check(cudaMemcpyAsync(device, host, bytes, cudaMemcpyHostToDevice, cudaStreamPerThread),
          "cudaMemcpyAsync host to device");
  }
}
void copyDeviceToHost(void* host, const void* device, std::size_t bytes) {
  if (bytes) check(cudaMemcpy(host, device, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy device to host");
}
void* allocatePinnedHost(std::size_t bytes) {
  void* pointer = nullptr;
  if (bytes) check(cudaHostAlloc(&pointer, bytes, cudaHostAllocDefault), "cudaHostAlloc");
  return pointer;
}
void releasePinnedHost(void* pointer) noexcept {
  if (pointer) cudaFreeHost(pointer);
}
void copyDeviceToDevice(void* destination, const void* source, std::size_t bytes) {
  if (bytes) check(cudaMemcpy(destination, source, bytes, cudaMemcpyDeviceToDevice), "cudaMemcpy device to device");
}
void setZero(void* device, std::size_t bytes) {
  if (bytes) check(cudaMemset(device, 0, bytes), "cudaMemset");
}
void synchronize() { check(cudaStreamSynchronize(cudaStreamPerThread), "cudaStreamSynchronize"); }

void checkLaunch(const char* what) { check(cudaGetLastError(), what); }

void* createEvent() {
  cudaEvent_t event = nullptr;
  check(cudaEventCreate(&event), "cudaEventCreate");
  return event;
}
void destroyEvent(void* event) noexcept {
  if (event) cudaEventDestroy(static_cast<cudaEvent_t>(event));
}
void recordEvent(void* event) { check(cudaEventRecord(static_cast<cudaEvent_t>(event)), "cudaEventRecord"); }
double millisecondsBetween(void* from, void* to) {
  check(cudaEventSynchronize(static_cast<cudaEvent_t>(to)), "cudaEventSynchronize");
  float ms = 0.0f;
  check(cudaEventElapsedTime(&ms, static_cast<cudaEvent_t>(from), static_cast<cudaEvent_t>(to)), "cudaEventElapsedTime");
  return ms;
}

}  // namespace tissuemosaic::cuda
