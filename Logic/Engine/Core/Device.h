#pragma once
/// @file Device.h
/// @brief Where engine work runs: the multithreaded CPU or a CUDA GPU, chosen at run time.
#include <string>

namespace tissuemosaic {

enum class Device { Cpu, Cuda };

/// True when this build has the CUDA backend and a CUDA device is usable right now.
bool cudaAvailable();
/// True when this build was compiled with the CUDA backend.
bool cudaCompiledIn();
/// Why CUDA cannot be used (empty when it can).
std::string cudaUnavailableReason();
/// For Device::Cuda where CUDA cannot be used, throws Error "<what> was asked for, but <why>"; else nothing.
/// Every engine component calls this rather than falling back to the CPU.
void requireUsableDevice(Device device, const std::string& what);

/// Parses "cpu", "cuda" or "auto" (auto: CUDA when available, else CPU). Throws Error on other text, and on
/// "cuda" when CUDA cannot be used, saying why: asking for CUDA never silently falls back to the CPU.
Device parseDevice(const std::string& text);
const char* deviceLabel(Device device);
/// Human-readable name: the GPU's name for CUDA, the CPU model and thread count otherwise.
std::string deviceDescription(Device device);
/// Blocks until the work the calling thread queued on the device has finished (no-op on the CPU).
void synchronize(Device device);

}  // namespace tissuemosaic
