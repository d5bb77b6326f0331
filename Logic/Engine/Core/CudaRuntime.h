#pragma once
/// @file CudaRuntime.h
/// @brief The few CUDA runtime services the engine needs, callable from plain C++ translation units.
/// Implemented in CudaRuntime.cu when the CUDA backend is built, and by CudaRuntimeAbsent.cpp otherwise (where
/// every call that needs a GPU throws Error).
#include <cstddef>
#include <string>

namespace tissuemosaic::cuda {

bool compiledIn();
/// Empty when a CUDA device can be used, otherwise the reason (no driver, no device, ...).
std::string deviceProblem();
std::string deviceName();
/// Streaming multiprocessors of the current GPU (queried once).
int multiprocessorCount();
/// Bytes of device memory in use on the current GPU (by every process and the context), from cudaMemGetInfo.
std::size_t deviceBytesInUse();
void* allocate(std::size_t bytes);
void release(void* pointer) noexcept;
void copyHostToDevice(void* device, const void* host, std::size_t bytes);
/// Queues the copy on the calling thread's stream and returns without waiting for the device (copyHostToDevice first
/// waits for the work queued before it). Pageable `host` memory is staged before the call returns, so it may be
/// reused at once. Page-locked memory (allocatePinnedHost) is copied from after the call returns, while the host goes
/// on: it must not change until the calling thread's work has finished (synchronize(), or any blocking copy on the
/// same thread).
void copyHostToDeviceQueued(void* device, const void* host, std::size_t bytes);
void copyDeviceToHost(void* host, const void* device, std::size_t bytes);
/// Page-locked host memory (cudaHostAlloc): copies from it need no staging and run while the host goes on.
void* allocatePinnedHost(std::size_t bytes);
void releasePinnedHost(void* pointer) noexcept;
void copyDeviceToDevice(void* destination, const void* source, std::size_t bytes);
void setZero(void* device, std::size_t bytes);
/// Blocks until the work the calling thread queued has finished. The engine is built with per-thread default
/// streams, so this does not wait for work another thread queued (and a thread that hands device data to another
/// must call it first).
void synchronize();
/// Throws Error naming `what` when the last kernel launch failed.
void checkLaunch(const char* what);
/// Time marks queued on the calling thread's stream behind the work launched before them (cudaEvent_t as an opaque handle).
void* createEvent();
void destroyEvent(void* event) noexcept;
void recordEvent(void* event);
/// Milliseconds of device time between two recorded marks; waits until `to` is reached.
double millisecondsBetween(void* from, void* to);

}  // namespace tissuemosaic::cuda
