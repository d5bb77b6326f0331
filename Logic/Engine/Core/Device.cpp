#include "Device.h"

#include "CudaRuntime.h"
#include "Error.h"
#include "ParameterError.h"
#include "ParallelFor.h"

#include <fstream>
#include <thread>

namespace tissuemosaic {

bool cudaCompiledIn() { return cuda::compiledIn(); }

bool cudaAvailable() { return cudaUnavailableReason().empty(); }

std::string cudaUnavailableReason() {
  if (!cuda::compiledIn()) return "this build of TissueMosaic has no CUDA backend (configure with nvcc present)";
  return cuda::deviceProblem();
}

void requireUsableDevice(Device device, const std::string& what) {
  if (device != Device::Cuda) return;
  const std::string reason = cudaUnavailableReason();
  if (!reason.empty()) throw Error(what + " was asked for, but " + reason);
}

Device parseDevice(const std::string& text) {
  if (text == "cpu") return Device::Cpu;
  if (text == "auto") return cudaAvailable() ? Device::Cuda : Device::Cpu;
  if (text == "cuda") {
    const std::string reason = cudaUnavailableReason();
    requireParameter(reason.empty(), "device", "cuda was asked for, but " + reason);
    return Device::Cuda;
  }
  throw ParameterError("device", "unknown device '" + text + "': expected cpu, cuda or auto");
}

const char* deviceLabel(Device device) { return device == Device::Cuda ? "cuda" : "cpu"; }

static std::string cpuModelName() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "CPU";
}

std::string deviceDescription(Device device) {
  if (device == Device::Cuda) return cuda::deviceName();
  return cpuModelName() + " (" + std::to_string(cpuThreadCount()) + " threads)";
}

void synchronize(Device device) {
  if (device == Device::Cuda) cuda::synchronize();
}

}  // namespace tissuemosaic
