#include "CudaRuntime.h"

#include "Error.h"

namespace tissuemosaic::cuda {

namespace {
[[noreturn]] void absent() { throw Error("this build of TissueMosaic has no CUDA backend"); }
}  // namespace

bool compiledIn() { return false; }
std::string deviceProblem() { return "this build of TissueMosaic has no CUDA backend"; }
std::string deviceName() { absent(); }
int multiprocessorCount() { absent(); }
std::size_t deviceBytesInUse() { absent(); }
void* allocate(std::size_t) { absent(); }
void release(void*) noexcept {}
void copyHostToDevice(void*, const void*, std::size_t) { absent(); }
void copyHostToDeviceQueued(void*, const void*, std::size_t) { absent(); }
void copyDeviceToHost(void*, const void*, std::size_t) { absent(); }
void* allocatePinnedHost(std::size_t) { absent(); }
void releasePinnedHost(void*) noexcept {}
void copyDeviceToDevice(void*, const void*, std::size_t) { absent(); }
void setZero(void*, std::size_t) { absent(); }
void synchronize() { absent(); }
void checkLaunch(const char*) { absent(); }
void* createEvent() { absent(); }
void destroyEvent(void*) noexcept {}
void recordEvent(void*) { absent(); }
double millisecondsBetween(void*, void*) { absent(); }

}  // namespace tissuemosaic::cuda
